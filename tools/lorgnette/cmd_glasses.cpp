// `lorgnette glasses inspect FILE [--json] [-o preview.png]`: canonical size, reference points,
// lens parts and a preview sheet of a glasses file; `lorgnette glasses make ...`: a parametric
// frame written as .glb with its reference-point sidecar. Logic lives in mesh/.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "host/util/output_folder.h"
#include "mesh/glasses.h"
#include "mesh/gltf_writer.h"
#include "mesh/parametric.h"
#include "mesh/preview.h"
#include "tools/lorgnette/command.h"

namespace lorgnette::cli {
namespace {

nlohmann::json vec_json(const Eigen::Vector3f& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json glasses_json(const mesh::Glasses& g) {
  const auto& m = g.metrics;
  nlohmann::json lenses = nlohmann::json::array();
  for (int p : m.lens_parts) lenses.push_back(g.mesh.part_names[p]);
  return {{"path", g.path},
          {"units", g.canonical.units},
          {"mm_per_unit", g.canonical.mm_per_unit},
          {"size_mm",
           {{"total_width", m.total_width_mm},
            {"total_height", m.total_height_mm},
            {"total_depth", m.total_depth_mm},
            {"lens_width", m.lens_width_mm},
            {"lens_height", m.lens_height_mm},
            {"bridge", m.bridge_mm},
            {"temple_length", m.temple_length_mm}}},
          {"reference_points_mm",
           {{"g_c", vec_json(g.ref.g_c)},
            {"g_l", vec_json(g.ref.g_l)},
            {"g_r", vec_json(g.ref.g_r)},
            {"source", g.ref.source}}},
          {"parts", g.mesh.part_names},
          {"lens_parts", lenses},
          {"triangles", g.mesh.triangle_count()},
          {"notes", g.notes}};
}

void print_text(const mesh::Glasses& g) {
  const auto& m = g.metrics;
  auto v = [](const Eigen::Vector3f& p) {
    return fmt::format("({:7.2f}, {:7.2f}, {:7.2f})", p.x(), p.y(), p.z());
  };
  std::cout << fmt::format("{}\n  units: {}\n", g.path, g.canonical.units);
  std::cout << fmt::format(
      "  size: total width {:.1f} mm, lens {:.1f} x {:.1f} mm, bridge {:.1f} mm, temple {:.1f} mm\n",
      m.total_width_mm, m.lens_width_mm, m.lens_height_mm, m.bridge_mm, m.temple_length_mm);
  std::cout << fmt::format("  reference points ({}, canonical mm: x wearer's left, y up, z forward):\n",
                           g.ref.source);
  std::cout << fmt::format("    g_c {}\n    g_l {}\n    g_r {}\n", v(g.ref.g_c), v(g.ref.g_l), v(g.ref.g_r));
  std::cout << "  parts:";
  for (size_t i = 0; i < g.mesh.part_names.size(); ++i) {
    bool lens =
        std::find(m.lens_parts.begin(), m.lens_parts.end(), static_cast<int>(i)) != m.lens_parts.end();
    std::cout << " " << g.mesh.part_names[i] << (lens ? " [lens]" : "");
  }
  std::cout << "\n";
  for (const auto& n : g.notes) std::cout << "  note: " << n << "\n";
}

void add_inspect(CLI::App& parent) {
  struct Opts {
    std::string file, preview;
    bool json = false, force = false;
    double mm_per_unit = 0.0;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd =
      parent.add_subcommand("inspect", "canonical size, reference points, lenses and a preview of a frame");
  cmd->add_option("file", o->file, "glasses mesh (.gltf/.glb/.obj/.ply)")->required();
  cmd->add_flag("--json", o->json, "print one JSON object on stdout");
  cmd->add_option("-o,--output", o->preview, "write a preview sheet (PNG) with the points marked");
  cmd->add_option("--mm-per-unit", o->mm_per_unit, "file units in millimetres (skips unit detection)");
  cmd->add_flag("--force", o->force, "overwrite an existing preview file");
  cmd->callback([o] {
    refuse_output_onto_input(o->preview, {o->file, mesh::sidecar_path(o->file)});
    refuse_existing_output(o->preview, o->force);
    mesh::GlassesOptions opts;
    opts.mm_per_unit = o->mm_per_unit;
    mesh::Glasses g = mesh::load_glasses(o->file, opts);
    if (!o->preview.empty()) {
      write_image(o->preview, mesh::render_glasses_preview(g));
      spdlog::info("preview written to {}", o->preview);
    }
    if (o->json)
      std::cout << glasses_json(g).dump(2) << "\n";
    else
      print_text(g);
  });
}

void add_make(CLI::App& parent) {
  struct Opts {
    mesh::FrameParams p;
    std::string shape = "rect", color = "black", tint = "clear", output, preview;
    bool json = false, force = false;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = parent.add_subcommand("make", "make a parametric frame (.glb + .refpoints.json sidecar)");
  cmd->add_option("--lens", o->p.lens_width, "lens width in mm (the first number on the temple)")
      ->capture_default_str();
  cmd->add_option("--bridge", o->p.bridge, "bridge in mm (the second number)")->capture_default_str();
  cmd->add_option("--temple", o->p.temple_length, "temple length in mm (the third number)")
      ->capture_default_str();
  cmd->add_option("--shape", o->shape, "round, rect, aviator or cateye")->capture_default_str();
  cmd->add_option("--rim", o->p.rim, "rim width in mm")->capture_default_str();
  cmd->add_option("--lens-height", o->p.lens_height, "lens height in mm (default: from the shape)");
  cmd->add_option("--color", o->color, "frame colour: #rrggbb, r,g,b (linear 0..1) or a name")
      ->capture_default_str();
  cmd->add_option("--lens-tint", o->tint, "lens tint: #rrggbb, r,g,b or a name (clear, grey, green, brown)")
      ->capture_default_str();
  cmd->add_option("--metallic", o->p.metallic, "frame metallic 0..1")->capture_default_str();
  cmd->add_option("--roughness", o->p.roughness, "frame roughness 0..1")->capture_default_str();
  cmd->add_option("-o,--output", o->output, "output .glb (the sidecar goes next to it)")->required();
  cmd->add_option("--preview", o->preview, "also write a preview sheet (PNG)");
  cmd->add_flag("--json", o->json, "print one JSON object on stdout");
  cmd->add_flag("--force", o->force, "overwrite existing output files (.glb, its sidecar, the preview)");
  cmd->callback([o] {
    refuse_output_onto_input(o->preview, {o->output, mesh::sidecar_path(o->output)}, "--preview");
    refuse_existing_output(o->output, o->force);
    refuse_existing_output(mesh::sidecar_path(o->output), o->force);
    refuse_existing_output(o->preview, o->force, "--preview");
    o->p.shape = mesh::parse_frame_shape(o->shape);
    o->p.color = mesh::parse_color(o->color);
    o->p.lens_tint = mesh::parse_color(o->tint);
    mesh::ParametricFrame f = mesh::make_parametric_frame(o->p);
    mesh::write_glb(o->output, f.mesh);
    mesh::RefPointsSidecar s;  // file coordinates of a .glb are metres
    s.points = f.ref;
    s.points.g_l /= 1000.0f, s.points.g_r /= 1000.0f;
    s.mm_per_unit = 1000.0;  // stated: a frame narrower than unit detection's adult range keeps its size
    mesh::write_refpoints_sidecar(o->output, s);
    mesh::Glasses g = mesh::load_glasses(o->output);
    if (!o->preview.empty()) write_image(o->preview, mesh::render_glasses_preview(g));
    if (o->json)
      std::cout << glasses_json(g).dump(2) << "\n";
    else
      print_text(g);
  });
}

void add_glasses(CLI::App& app, GlobalOptions& /*global*/) {
  auto* cmd = app.add_subcommand("glasses", "inspect glasses files, make parametric frames");
  cmd->require_subcommand(1);
  add_inspect(*cmd);
  add_make(*cmd);
}

}  // namespace
LGN_REGISTER_COMMAND(40, add_glasses);
}  // namespace lorgnette::cli
