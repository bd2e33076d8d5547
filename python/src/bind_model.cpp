// lorgnette.Camera and lorgnette.Model: cameras from a pose JSON (render --pose), a transforms.json
// frame or look-at parameters; loading a .lnerf, rendering it with or without glasses (the same
// calls as `lorgnette render`, with the GIL released), the orbit `render --orbit` uses and the range
// of directions the capture saw.
#include <fmt/format.h>
#include <pybind11/stl.h>
#include <spdlog/spdlog.h>

#include <cmath>

#include "fit/placement_json.h"
#include "host/dataset/dataset.h"
#include "host/render/orbit.h"
#include "host/render/render_job.h"
#include "host/render/render_settings.h"
#include "host/render/view_plan.h"
#include "python/src/bindings.h"

namespace lorgnette::py {
namespace {

using Size = std::array<uint32_t, 2>;
// Model.render's and Model.orbit's defaults are `lorgnette render`'s: the one request's.
const render::RenderSettings kRenderDefaults;
const render::OrbitSettings kOrbitDefaults;

pyb::array_t<double> c2w_matrix(const Camera& c) {
  pyb::array_t<double> out({4, 4});
  double* p = out.mutable_data();
  for (int i = 0; i < 12; ++i) p[i] = c.c2w[i];
  p[12] = p[13] = p[14] = 0.0, p[15] = 1.0;
  return out;
}

// (width, height) within bounds::kImageSide, as `--size WxH`.
Size size_arg(const pyb::handle& obj) {
  if (!pyb::isinstance<pyb::sequence>(obj) || pyb::isinstance<pyb::str>(obj) || pyb::len(obj) != 2)
    throw pyb::type_error("size must be (width, height), two whole numbers (render --size WxH)");
  pyb::sequence seq = pyb::reinterpret_borrow<pyb::sequence>(obj);
  return {uint32_t(count_arg(seq[0], bounds::kImageSide)), uint32_t(count_arg(seq[1], bounds::kImageSide))};
}

// The same rays on a differently sized image (intrinsics scaled with the size).
Camera resized(const Camera& c, Size size) {
  check_bound(bounds::kImageSide, size[0]);
  check_bound(bounds::kImageSide, size[1]);
  if (size[0] == c.width && size[1] == c.height) return c;
  Camera r = c;
  const float sx = float(size[0]) / float(c.width), sy = float(size[1]) / float(c.height);
  r.fx *= sx, r.cx *= sx, r.fy *= sy, r.cy *= sy;
  r.width = size[0], r.height = size[1];
  return r;
}

Camera make_camera(const pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>& c2w, float fx,
                   float fy, float cx, float cy, Size size) {
  if (!((c2w.ndim() == 2 && c2w.shape(0) >= 3 && c2w.shape(0) <= 4 && c2w.shape(1) == 4)))
    throw pyb::value_error(
        "c2w must be a 3x4 or 4x4 camera-to-world matrix (OpenGL: the camera looks down -z)");
  Camera c{};
  for (int i = 0; i < 12; ++i) c.c2w[i] = float(c2w.data()[i]);
  c.fx = fx, c.fy = fy, c.cx = cx, c.cy = cy, c.width = size[0], c.height = size[1];
  return c;
}

// The model's view range (host/render/view_plan.h): yaw (about up, + towards the head's right = the
// orbit's +x) and pitch of the capture's camera positions around the box centre; an empty dict when
// no range is known.
pyb::dict captured_range(const nerf::NerfModel& model) {
  pyb::dict out;
  std::string source;
  std::optional<nerf::ViewRange> r = render::model_view_range(model, &source);
  if (!r) return out;
  out["cameras"] = r->cameras;
  out["front"] = r->front, out["up"] = r->up, out["center"] = r->center;
  out["yaw_deg"] = std::make_pair(r->yaw_min, r->yaw_max);
  out["pitch_deg"] = std::make_pair(r->pitch_min, r->pitch_max);
  out["margin_deg"] = nerf::kViewMarginDeg;
  out["source"] = source;
  return out;
}

// The surface pass of `g` placed by (transform, temples), built once per placement.
std::shared_ptr<mesh::PlacedGlasses> placed_glasses(Glasses& g, const fit::Transform& transform,
                                                    const mesh::TempleBend& temples) {
  std::string key = fmt::format("{}|{}", fmt::join(transform.data(), transform.data() + 16, ","),
                                fit::temple_bend_to_json(temples).dump());
  std::lock_guard<std::mutex> lock(g.mutex);
  if (!g.placed || g.placed_key != key) {
    g.placed = std::make_shared<mesh::PlacedGlasses>(mesh::place_glasses_mesh(g.glasses, transform, temples));
    g.placed_key = key;
  }
  return g.placed;
}

struct RenderArgs {
  pyb::object glasses, placement;
  std::optional<Size> size;
  render::RenderSettings settings;  // checked by render::validate, as `lorgnette render` is
  bool depth = false;
};

// The render settings from Python's arguments (numbers checked against bounds.h, as the CLI's).
render::RenderSettings render_settings(const pyb::handle& spp, const pyb::handle& surface_spp,
                                       const pyb::handle& step_scale, const pyb::handle& background,
                                       bool alpha) {
  render::RenderSettings s;
  s.spp = uint32_t(count_arg(spp, bounds::kSpp));
  s.surface_spp = uint32_t(count_arg(surface_spp, bounds::kSurfaceSpp));
  s.step_scale = float(number_arg(step_scale, bounds::kStepScale));
  if (!pyb::isinstance<pyb::sequence>(background) || pyb::isinstance<pyb::str>(background) ||
      pyb::len(background) != 3)
    throw pyb::type_error(
        "background must be three numbers, linear RGB each 0..1 (render --background R G B)");
  pyb::sequence bg = pyb::reinterpret_borrow<pyb::sequence>(background);
  for (int i = 0; i < 3; ++i) s.background[i] = float(number_arg(bg[i], bounds::kBackground));
  s.alpha = alpha;
  s.marcher = "auto";
  render::validate(s);
  return s;
}

// A Glasses, or a path to load (as `render --glasses FRAME`).
std::shared_ptr<Glasses> glasses_arg(const pyb::handle& obj) {
  if (pyb::isinstance<Glasses>(obj)) return obj.cast<std::shared_ptr<Glasses>>();
  if (pyb::isinstance<pyb::str>(obj) || pyb::hasattr(obj, "__fspath__")) {
    std::string path = pyb::str(pyb::module_::import("os").attr("fspath")(obj));
    require_file(path, "glasses");
    return load_glasses(path);
  }
  throw pyb::type_error(fmt::format("glasses must be a lorgnette.Glasses or a path to a frame file, found {}",
                                    Py_TYPE(obj.ptr())->tp_name));
}

// `lorgnette render` for one camera: the same glasses placement, surface pass and marcher calls.
pyb::object render_model(Model& m, const Camera& camera, const RenderArgs& a) {
  Camera cam = a.size ? resized(camera, *a.size) : camera;
  render::RenderOptions ro = render::render_options(a.settings);
  std::shared_ptr<Glasses> glasses;
  fit::Transform transform = fit::Transform::Identity();
  mesh::TempleBend temples;
  if (!a.glasses.is_none()) glasses = glasses_arg(a.glasses);
  if (glasses && a.placement.is_none()) render::check_glasses_and_placement(true, false);
  if (!a.placement.is_none()) {
    if (pyb::isinstance<Placement>(a.placement)) {
      const fit::PlacementFile& p = a.placement.cast<const Placement&>().file;
      transform = p.transform;
      temples = p.temples.bend;
      if (!glasses) {
        if (p.glasses_path.empty())
          throw std::runtime_error("a placement was given but no glasses: pass glasses=Glasses.load(FRAME)");
        glasses = load_glasses(p.glasses_path);
      }
      warn_glasses_mismatch(p, glasses->glasses.path);
    } else {
      transform = placement_matrix(a.placement, "placement");
      if (!glasses)
        throw std::runtime_error("a placement was given but no glasses: pass glasses=Glasses.load(FRAME)");
    }
  }
  render::RenderResult r;
  {
    pyb::gil_scoped_release release;
    std::shared_ptr<mesh::PlacedGlasses> placed;
    if (glasses) placed = placed_glasses(*glasses, transform, temples);
    std::lock_guard<std::mutex> lock(m.device->mutex);
    if (!m.renderer) m.renderer = std::make_unique<render::Renderer>(m.device->runtime);
    if (placed) {
      mesh::SurfaceParams sp;
      sp.samples_per_pixel = int(a.settings.surface_spp);
      auto s = placed->pass->render(cam, sp);
      r = m.renderer->render(*m.nerf, cam, &s, ro);
    } else {
      r = m.renderer->render(*m.nerf, cam, nullptr, ro);
    }
  }
  pyb::array_t<float> rgba = to_numpy(r.rgba);
  if (!a.depth) return rgba;
  return pyb::make_tuple(rgba, to_numpy(r.depth));
}

std::shared_ptr<Model> load_model(const std::string& path, const std::string& device) {
  require_file(path, "model");
  auto m = std::make_shared<Model>();
  m->device = device_for(device);
  m->path = path;
  pyb::gil_scoped_release release;
  std::lock_guard<std::mutex> lock(m->device->mutex);
  m->nerf = std::make_unique<nerf::NerfModel>(nerf::NerfModel::load(m->device->runtime, path));
  return m;
}

Camera camera_from_transforms(const std::string& path, size_t index, std::optional<Size> size) {
  if (!std::filesystem::exists(path)) require_file(path, "transforms");
  dataset::LoadOptions lo;
  lo.load_images = false;
  lo.any_missing_images_ok = true;
  auto ds = dataset::load_dataset(path, lo);
  if (index >= ds.frames.size())
    throw pyb::index_error(fmt::format("frame {} of '{}': it has {} frames", index, path, ds.frames.size()));
  return size ? resized(ds.frames[index].camera, *size) : ds.frames[index].camera;
}

// Model.render's Python arguments, checked as `lorgnette render` checks its options.
pyb::object render_with_args(Model& self, const Camera& cam, pyb::object glasses, pyb::object placement,
                             pyb::object size, pyb::object spp, pyb::object surface_spp,
                             pyb::object step_scale, pyb::object background, bool alpha, bool depth) {
  RenderArgs a;
  a.glasses = glasses, a.placement = placement, a.depth = depth;
  if (!size.is_none()) a.size = size_arg(size);
  a.settings = render_settings(spp, surface_spp, step_scale, background, alpha);
  return render_model(self, cam, a);
}

// Model.orbit: the orbit request every front end makes (render::OrbitSettings), checked by
// render::validate as `render --orbit` is.
std::vector<Camera> orbit_with_args(Model& self, pyb::object views, pyb::object size, pyb::object elevation,
                                    pyb::object fov, std::optional<render::Vec3> front, bool beyond_capture) {
  render::OrbitSettings s;
  s.views = uint32_t(count_arg(views, bounds::kOrbitViews));
  Size wh = size_arg(size);
  s.width = wh[0], s.height = wh[1];
  s.elevation_deg = float(number_arg(elevation, bounds::kElevationDeg));
  s.fov_y_deg = float(number_arg(fov, bounds::kFovDeg));
  s.front = front, s.beyond_capture = beyond_capture;
  render::OrbitPlan plan = render::plan_model_orbit(*self.nerf, s, render::model_view_range(*self.nerf));
  return render::orbit_cameras(plan.spec);
}

void save_model(Model& self, const std::string& path, bool force) {
  if (!force && std::filesystem::exists(path))
    throw std::runtime_error("'" + path + "' exists: pass force=True to overwrite it or choose another path");
  pyb::gil_scoped_release release;
  std::lock_guard<std::mutex> lock(self.device->mutex);
  self.nerf->save(path);
  self.path = path;
}

pyb::dict model_metadata(const Model& self) {
  const auto& md = self.nerf->metadata;
  pyb::dict d;
  d["steps"] = md.steps, d["train_seconds"] = md.train_seconds, d["samples_trained"] = md.samples_trained;
  d["seed"] = md.seed, d["final_loss"] = md.final_loss, d["dataset_path"] = md.dataset_path;
  d["dataset_hash"] = md.dataset_hash, d["device"] = md.device, d["created"] = md.created;
  return d;
}

void bind_camera(pyb::module_& m) {
  pyb::class_<Camera>(m, "Camera",
                      "A pinhole camera (OpenGL convention: looks down -z, +y up; pixel centres at i + 0.5).")
      .def(pyb::init(&make_camera), pyb::arg("c2w"), pyb::arg("fx"), pyb::arg("fy"), pyb::arg("cx"),
           pyb::arg("cy"), pyb::arg("size"))
      .def_static(
          "look_at",
          [](render::Vec3 eye, render::Vec3 target, render::Vec3 up, Size size, float fov) {
            return render::look_at(eye, target, up, size[0], size[1], fov);
          },
          pyb::arg("eye"), pyb::arg("target"), pyb::arg("up") = render::Vec3{0, 1, 0},
          pyb::arg("size") = Size{640, 480}, pyb::arg("fov_y_deg") = 30.0f)
      .def_static(
          "from_pose",
          [](const std::string& path, Size size, float fov) {
            require_file(path, "pose");
            return render::read_pose(path, size[0], size[1], fov);
          },
          pyb::arg("path"), pyb::arg("size") = Size{854, 480}, pyb::arg("fov_y_deg") = 30.0f,
          "The camera `lorgnette render --pose PATH --size WxH --fov F` renders.")
      .def_static("from_transforms", &camera_from_transforms, pyb::arg("path"), pyb::arg("index") = 0,
                  pyb::arg("size") = pyb::none(),
                  "Frame `index` of a transforms.json (or its directory), in the loader's frame order.")
      .def("resized", &resized, pyb::arg("size"), "The same rays on a (width, height) image.")
      .def_property_readonly("width", [](const Camera& c) { return c.width; })
      .def_property_readonly("height", [](const Camera& c) { return c.height; })
      .def_property_readonly("size",
                             [](const Camera& c) {
                               return Size{c.width, c.height};
                             })
      .def_property_readonly("fx", [](const Camera& c) { return c.fx; })
      .def_property_readonly("fy", [](const Camera& c) { return c.fy; })
      .def_property_readonly("cx", [](const Camera& c) { return c.cx; })
      .def_property_readonly("cy", [](const Camera& c) { return c.cy; })
      .def_property_readonly("distortion",
                             [](const Camera& c) {
                               return std::array<float, 4>{c.k1, c.k2, c.p1, c.p2};
                             })
      .def_property_readonly("c2w", &c2w_matrix, "4x4 camera-to-world")
      .def("__repr__", [](const Camera& c) {
        return fmt::format("Camera({}x{}, f=({:.1f}, {:.1f}), eye=({:.3f}, {:.3f}, {:.3f}))", c.width,
                           c.height, c.fx, c.fy, c.c2w[3], c.c2w[7], c.c2w[11]);
      });
}

}  // namespace

void bind_model(pyb::module_& m) {
  bind_camera(m);
  pyb::class_<Model, std::shared_ptr<Model>>(m, "Model", pyb::dynamic_attr(),
                                             "A trained NeRF head (.lnerf) on an OpenCL device.")
      .def_static("load", &load_model, pyb::arg("path"), pyb::arg("device") = "",
                  "Loads a snapshot; a missing, newer or corrupt file raises with the CLI's message.")
      .def("render", &render_with_args, pyb::arg("camera"), pyb::arg("glasses") = pyb::none(),
           pyb::arg("placement") = pyb::none(), pyb::arg("size") = pyb::none(),
           pyb::arg("spp") = kRenderDefaults.spp, pyb::arg("surface_spp") = kRenderDefaults.surface_spp,
           pyb::arg("step_scale") = kRenderDefaults.step_scale,
           pyb::arg("background") = std::make_tuple(
               kRenderDefaults.background[0], kRenderDefaults.background[1], kRenderDefaults.background[2]),
           pyb::arg("alpha") = kRenderDefaults.alpha, pyb::arg("depth") = false,
           "Renders the head (with glasses - a Glasses or a frame's path - placed by a Placement or a 4x4 "
           "canonical mm -> scene; glasses without a placement are refused as `render` refuses them) as a "
           "float32 H x W x 4 array: linear RGB over `background` and alpha = coverage (alpha=True: no "
           "background, RGB premultiplied). depth=True returns (rgba, depth H x W: distance along the unit "
           "ray, 0 where empty). to_srgb8() gives the CLI's PNG pixels. The GIL is released meanwhile.")
      .def("orbit", &orbit_with_args, pyb::arg("views"),
           pyb::arg("size") = std::make_tuple(kOrbitDefaults.width, kOrbitDefaults.height),
           pyb::arg("elevation_deg") = kOrbitDefaults.elevation_deg,
           pyb::arg("fov_y_deg") = kOrbitDefaults.fov_y_deg, pyb::arg("front") = pyb::none(),
           pyb::arg("beyond_capture") = false,
           "The cameras of `lorgnette render --orbit N`: around the head's box from its front, within the "
           "directions the capture saw plus a margin (captured_range), starting at `front` (a direction from "
           "the head; its tilt adds to elevation_deg) clamped into them; beyond_capture=True: the full "
           "circle from `front`.")
      .def(
          "capture_cameras", [](Model& self) { return render::capture_cameras(*self.nerf); },
          "The cameras of the dataset the model was trained on (empty when it is gone).")
      .def(
          "captured_range", [](Model& self) { return captured_range(*self.nerf); },
          "The yaw and pitch range (degrees) of the capture's cameras around the head, in the orbit's frame "
          "(orbits stay inside it plus margin_deg); {} when the model records none and its dataset is gone.")
      .def("save", &save_model, pyb::arg("path"), pyb::arg("force") = false)
      .def_property_readonly("path", [](const Model& self) { return self.path; })
      .def_property_readonly("device", [](const Model& self) { return self.device->runtime.device().name; })
      .def_property_readonly(
          "aabb",
          [](const Model& self) { return std::make_pair(self.nerf->aabb().min, self.nerf->aabb().max); },
          "The scene box (min, max) the field covers.")
      .def_property_readonly("step", [](const Model& self) { return self.nerf->step(); })
      .def_property_readonly("metadata", &model_metadata)
      .def("__repr__", [](const Model& self) {
        return fmt::format("Model('{}', {} steps, on {})", self.path, self.nerf->metadata.steps,
                           self.device->runtime.device().name);
      });
}

}  // namespace lorgnette::py
