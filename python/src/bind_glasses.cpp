// lorgnette.Glasses and lorgnette.Placement: a frame loaded and canonicalised in millimetres (the
// calls of `lorgnette glasses inspect` / `glasses make`), its reference points and sizes, its
// vertices under a transform; placement.json in memory (read, written, adjusted in canonical mm).
#include <fmt/format.h>
#include <pybind11/stl.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include "fit/placement_json.h"
#include "fit/placement_transform.h"
#include "host/util/bounds.h"
#include "mesh/gltf_writer.h"
#include "mesh/parametric.h"
#include "python/src/bindings.h"

namespace lorgnette::py {
namespace {

pyb::array_t<double> vec(const Eigen::Vector3f& v) {
  pyb::array_t<double> out(3);
  for (int i = 0; i < 3; ++i) out.mutable_data()[i] = v[i];
  return out;
}

pyb::array_t<double> matrix(const Eigen::Matrix4d& m) {
  pyb::array_t<double> out({4, 4});
  for (int i = 0; i < 16; ++i) out.mutable_data()[i] = m(i / 4, i % 4);
  return out;
}

Eigen::Matrix4d matrix_from(const pyb::handle& obj) {
  auto a = pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>::ensure(obj);
  if (!a || a.size() != 16) throw pyb::value_error("expected a 4x4 matrix");
  Eigen::Matrix4d m;
  for (int i = 0; i < 16; ++i) m(i / 4, i % 4) = a.data()[i];
  return m;
}

std::shared_ptr<Placement> placement_of(fit::PlacementFile pf) {
  auto p = std::make_shared<Placement>();
  p->file = std::move(pf);
  return p;
}

// `lorgnette glasses inspect --json`'s object.
pyb::dict glasses_info(const mesh::Glasses& g) {
  const auto& m = g.metrics;
  pyb::dict size, ref;
  size["total_width"] = m.total_width_mm, size["total_height"] = m.total_height_mm;
  size["total_depth"] = m.total_depth_mm, size["lens_width"] = m.lens_width_mm;
  size["lens_height"] = m.lens_height_mm, size["bridge"] = m.bridge_mm,
  size["temple_length"] = m.temple_length_mm;
  ref["g_c"] = vec(g.ref.g_c), ref["g_l"] = vec(g.ref.g_l), ref["g_r"] = vec(g.ref.g_r),
  ref["source"] = g.ref.source;
  std::vector<std::string> lenses;
  for (int p : m.lens_parts) lenses.push_back(g.mesh.part_names[p]);
  pyb::dict d;
  d["path"] = g.path, d["units"] = g.canonical.units, d["mm_per_unit"] = g.canonical.mm_per_unit;
  d["size_mm"] = size, d["reference_points_mm"] = ref, d["parts"] = g.mesh.part_names;
  d["lens_parts"] = lenses, d["triangles"] = g.mesh.triangle_count(), d["notes"] = g.notes;
  return d;
}

// `glasses make`; without a path the frame goes to a fresh temporary directory.
std::shared_ptr<Glasses> make_glasses(const mesh::FrameParams& params, std::string path, bool force) {
  if (path.empty()) {
    static int made = 0;
    auto dir =
        std::filesystem::temp_directory_path() / fmt::format("lorgnette-glasses-{}-{}", getpid(), made++);
    std::filesystem::create_directories(dir);
    path = (dir / fmt::format("frame-{:.0f}-{:.0f}-{:.0f}.glb", params.lens_width, params.bridge,
                              params.temple_length))
               .string();
  }
  if (!force)
    for (const std::string& p : {path, mesh::sidecar_path(path)})
      if (std::filesystem::exists(p))
        throw std::runtime_error("'" + p +
                                 "' exists: pass force=True to overwrite it or choose another path");
  mesh::ParametricFrame f = mesh::make_parametric_frame(params);
  mesh::write_glb(path, f.mesh);
  mesh::RefPointsSidecar s;  // file coordinates of a .glb are metres (as `glasses make`)
  s.points = f.ref;
  s.points.g_l /= 1000.0f, s.points.g_r /= 1000.0f;
  s.mm_per_unit = 1000.0;  // stated: a frame narrower than unit detection's adult range keeps its size
  mesh::write_refpoints_sidecar(path, s);
  return load_glasses(path);
}

// Glasses.make: the arguments of `lorgnette glasses make`.
std::shared_ptr<Glasses> make_glasses_args(float lens, float bridge, float temple, const std::string& shape,
                                           const std::string& path, const std::string& color,
                                           const std::string& tint, bool force) {
  mesh::FrameParams p;
  p.lens_width = lens, p.bridge = bridge, p.temple_length = temple;
  p.shape = mesh::parse_frame_shape(shape);
  p.color = mesh::parse_color(color);
  p.lens_tint = mesh::parse_color(tint);
  return make_glasses(p, path, force);
}

// N x 3 vertices in canonical mm, or mapped by a 4x4.
pyb::array_t<double> glasses_vertices(const Glasses& g, pyb::object transform) {
  const auto& pos = g.glasses.mesh.positions;
  Eigen::Matrix4d t = transform.is_none() ? Eigen::Matrix4d::Identity() : matrix_from(transform);
  pyb::array_t<double> out({pyb::ssize_t(pos.size()), pyb::ssize_t(3)});
  double* o = out.mutable_data();
  for (size_t i = 0; i < pos.size(); ++i) {
    Eigen::Vector4d p = t * Eigen::Vector4d(pos[i].x(), pos[i].y(), pos[i].z(), 1.0);
    o[3 * i] = p.x(), o[3 * i + 1] = p.y(), o[3 * i + 2] = p.z();
  }
  return out;
}

pyb::array_t<int32_t> glasses_triangles(const Glasses& g) {
  const auto& t = g.glasses.mesh.triangles;
  pyb::array_t<int32_t> out({pyb::ssize_t(t.size()), pyb::ssize_t(3)});
  for (size_t i = 0; i < t.size(); ++i)
    for (int k = 0; k < 3; ++k) out.mutable_data()[3 * i + k] = t[i][k];
  return out;
}

// Placement.from_transform: a placement made by hand, naming its frame (path and content hash) so a
// later render can tell another frame from it.
std::shared_ptr<Placement> placement_from_transform(pyb::object transform, pyb::object glasses) {
  fit::PlacementFile pf;
  pf.transform = placement_matrix(transform, "transform");
  if (!glasses.is_none()) {
    pf.glasses_path = glasses.cast<std::shared_ptr<Glasses>>()->glasses.path;
    try {
      pf.glasses_hash = fit::file_hash(pf.glasses_path);
    } catch (const std::runtime_error&) {
    }
  }
  pf.ok = true;
  return placement_of(std::move(pf));
}

// Placement.save: an existing file is kept unless force=True (nothing the user made is lost).
void save_placement(const Placement& p, const std::string& path, bool force) {
  if (!force && std::filesystem::exists(path))
    throw std::runtime_error("'" + path + "' exists: pass force=True to overwrite it or choose another path");
  fit::write_placement(path, p.file);
}

std::shared_ptr<Placement> adjusted_placement(const Placement& p, std::array<float, 3> t,
                                              std::array<float, 3> r, float s) {
  fit::PlacementFile pf = p.file;
  pf.transform = pf.transform * fit::trs_transform(t, r, s);
  fit::check_transform(pf.transform, "adjusted placement");
  return placement_of(std::move(pf));
}

void bind_glasses_class(pyb::module_& m) {
  pyb::class_<Glasses, std::shared_ptr<Glasses>>(m, "Glasses",
                                                 "A glasses frame in its canonical frame: millimetres, x to "
                                                 "the wearer's left, +y up, +z forward, origin "
                                                 "at the bridge point g_c.")
      .def_static("load", &load_glasses, pyb::arg("path"), pyb::arg("mm_per_unit") = 0.0,
                  "glTF/GLB/OBJ/PLY (a <file>.refpoints.json sidecar overrides the detected points).")
      .def_static("make", &make_glasses_args, pyb::arg("lens"), pyb::arg("bridge"), pyb::arg("temple"),
                  pyb::arg("shape") = "rect", pyb::arg("path") = "", pyb::arg("color") = "black",
                  pyb::arg("lens_tint") = "clear", pyb::arg("force") = false,
                  "`lorgnette glasses make`: writes PATH (.glb; default a temporary file) and its sidecar, "
                  "then loads it.")
      .def_property_readonly("path", [](const Glasses& g) { return g.glasses.path; })
      .def_property_readonly(
          "info", [](const Glasses& g) { return glasses_info(g.glasses); },
          "What `lorgnette glasses inspect --json` prints.")
      .def_property_readonly("size_mm",
                             [](const Glasses& g) { return pyb::object(glasses_info(g.glasses)["size_mm"]); })
      .def_property_readonly(
          "reference_points",
          [](const Glasses& g) { return pyb::object(glasses_info(g.glasses)["reference_points_mm"]); },
          "g_c (bridge), g_l and g_r (temple tips resting on the ears), canonical mm, and their source.")
      .def_property_readonly("notes", [](const Glasses& g) { return g.glasses.notes; })
      .def("vertices", &glasses_vertices, pyb::arg("transform") = pyb::none(),
           "N x 3 vertices in canonical mm, or mapped by a 4x4 (e.g. placement.transform: into the scene).")
      .def_property_readonly("triangles", &glasses_triangles)
      .def("__repr__", [](const Glasses& g) {
        const auto& mm = g.glasses.metrics;
        return fmt::format("Glasses('{}', {:.0f}-{:.0f}-{:.0f} mm)", g.glasses.path, mm.lens_width_mm,
                           mm.bridge_mm, mm.temple_length_mm);
      });
}

void bind_placement_class(pyb::module_& m) {
  pyb::class_<Placement, std::shared_ptr<Placement>>(m, "Placement",
                                                     "placement.json in memory: `transform` (canonical mm -> "
                                                     "scene), the fit's estimates, the temple spread.")
      .def_static(
          "load",
          [](const std::string& path) {
            require_file(path, "placement");
            return placement_of(fit::read_placement(path));
          },
          pyb::arg("path"),
          "Reads and validates placement.json (the fit's reader: a bad field raises naming it).")
      .def_static("from_transform", &placement_from_transform, pyb::arg("transform"),
                  pyb::arg("glasses") = pyb::none())
      .def_static(
          "from_json",
          [](const std::string& text) {
            return placement_of(fit::placement_from_json(nlohmann::json::parse(text)));
          },
          pyb::arg("text"), "Reads placement.json's text (a relative glasses path stays as written).")
      .def("to_json", [](const Placement& p) { return fit::to_json(p.file).dump(2); })
      .def("save", &save_placement, pyb::arg("path"), pyb::arg("force") = false)
      .def_property(
          "transform", [](const Placement& p) { return matrix(p.file.transform); },
          [](Placement& p, pyb::object t) { p.file.transform = placement_matrix(t, "transform"); },
          "4x4 canonical mm -> scene (writable).")
      .def("adjusted", &adjusted_placement, pyb::arg("translate_mm") = std::array<float, 3>{0, 0, 0},
           pyb::arg("rotate_deg") = std::array<float, 3>{0, 0, 0}, pyb::arg("scale") = 1.0f,
           "A copy moved in the frame's canonical millimetres (e.g. translate_mm=(0, -2, 0): 2 mm down the "
           "nose).")
      .def_property(
          "glasses_path", [](const Placement& p) { return p.file.glasses_path; },
          [](Placement& p, const std::string& path) { p.file.glasses_path = path; })
      .def_property_readonly("ok", [](const Placement& p) { return p.file.ok; })
      .def_property_readonly("warnings", [](const Placement& p) { return p.file.warnings; })
      .def_property_readonly("pd_mm", [](const Placement& p) { return p.file.pd_mm; })
      .def_property_readonly("mm_per_unit", [](const Placement& p) { return p.file.mm_per_unit; })
      .def_property_readonly(
          "scale_source", [](const Placement& p) { return p.file.scale_source; },
          "Where mm_per_unit came from: 'card', 'iris' or 'mean-face' ('' for an older placement).")
      .def_property_readonly("mm_per_unit_uncertainty",
                             [](const Placement& p) { return p.file.mm_per_unit_uncertainty; })
      .def_property_readonly("pd_uncertainty_mm", [](const Placement& p) { return p.file.pd_uncertainty_mm; })
      .def_property_readonly("scale_policy", [](const Placement& p) { return p.file.scale_policy; })
      .def_property_readonly(
          "advice",
          [](const Placement& p) {
            return to_python(p.file.has_advice ? fit::to_json(p.file)["advice"] : nlohmann::json());
          },
          "The fit advice: {'approximate': bool, 'rules': [{'name', 'verdict', 'frame_mm', 'head_mm', "
          "'difference_mm', 'low_mm', 'high_mm', 'off_by_mm', 'text'}]}, or None.")
      .def_property_readonly("scale", [](const Placement& p) { return p.file.scale; })
      .def_property_readonly("penetration_mm", [](const Placement& p) { return p.file.penetration_mm; })
      .def_property_readonly("views_used", [](const Placement& p) { return p.file.views_used; })
      .def_property_readonly(
          "data", [](const Placement& p) { return to_python(fit::to_json(p.file)); },
          "The whole placement.json object as Python dicts and lists (a copy).")
      .def("__repr__", [](const Placement& p) {
        const fit::PlacementFile& pf = p.file;
        return fmt::format("Placement(ok={}, PD {:.1f} mm, {:.1f} mm/unit, glasses '{}')", pf.ok, pf.pd_mm,
                           pf.mm_per_unit, pf.glasses_path);
      });
}

}  // namespace

Eigen::Matrix4d placement_matrix(const pyb::handle& obj, const std::string& what) {
  auto a = pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>::ensure(obj);
  if (!a || a.size() != 16) throw pyb::value_error(what + ": a 4x4 matrix (canonical mm -> scene)");
  Eigen::Matrix4d m;
  for (int i = 0; i < 16; ++i) m(i / 4, i % 4) = a.data()[i];
  try {
    fit::check_transform(m, what);
  } catch (const std::invalid_argument& e) {
    throw OutOfRange(e.what());  // lorgnette.RangeError: a lorgnette.Error and a ValueError
  }
  return m;
}

void warn_glasses_mismatch(const fit::PlacementFile& p, const std::string& glasses_path) {
  std::string why = fit::glasses_mismatch(p, glasses_path);
  if (!why.empty() && PyErr_WarnEx(PyExc_UserWarning, why.c_str(), 1) != 0) throw pyb::error_already_set();
}

std::shared_ptr<Glasses> load_glasses(const std::string& path, double mm_per_unit) {
  require_file(path, "glasses");
  auto g = std::make_shared<Glasses>();
  mesh::GlassesOptions o;
  o.mm_per_unit = mm_per_unit;
  pyb::gil_scoped_release release;
  g->glasses = mesh::load_glasses(path, o);
  return g;
}

void bind_glasses(pyb::module_& m) {
  bind_glasses_class(m);
  bind_placement_class(m);
}

}  // namespace lorgnette::py
