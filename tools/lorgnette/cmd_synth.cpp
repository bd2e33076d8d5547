// `lorgnette synth (--mesh FILE | --procedural) -o DATASET [...]`: renders a synthetic training
// dataset with exact ground truth (transforms.json, RGBA images, depth EXRs, ground_truth.json).
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "host/util/bounds.h"
#include "host/util/image_io.h"
#include "host/util/progress.h"
#include "synth/room.h"
#include "synth/synthesize.h"
#include "tools/lorgnette/command.h"

namespace lorgnette::cli {
namespace {

struct SynthArgs {
  std::string mesh, out, size = "256x256", background = "transparent", skin, hair, wall;
  float specular = 0.0f, wall_mm = 1000.0f, head_scale = 1.0f;
  bool procedural = false, force = false, json = false, card = false, window = false;
  int views = 24, samples = 3, room = 0;
  float fov = 60.0f, phone_mm = 480.0f;
  std::vector<float> yaw{-35.0f, 35.0f}, pitch{-12.0f, 18.0f};
  uint64_t seed = 0;
  double mesh_mm = 0.0;
  std::vector<float> look_at;  // empty = the subject's (bounding-box centre for mesh files)
  float frame_radius = 0.0f;   // 0 = the subject's
};

std::pair<int, int> parse_size(const std::string& s) {
  int w = 0, h = 0;
  char x = 0;
  std::istringstream in(s);
  if (!(in >> w >> x >> h) || (x != 'x' && x != 'X') || !in.eof())
    throw std::runtime_error(fmt::format("--size '{}' is not WxH (e.g. 256x256)", s));
  check_bound(bounds::kSynthSide, w);
  check_bound(bounds::kSynthSide, h);
  return {w, h};
}

// Every number against host/util/bounds.h before anything is rendered or written.
void validate(const SynthArgs& a) {
  namespace b = bounds;
  check_bound(b::kSynthViews, a.views);
  for (float y : a.yaw) check_bound(b::kSynthYaw, y);
  for (float p : a.pitch) check_bound(b::kSynthPitch, p);
  check_bound(b::kSynthSamples, a.samples);
  check_bound_or_zero(b::kMeshMmPerUnit, a.mesh_mm);
  for (float c : a.look_at) check_bound(b::kLookAt, c);
  check_bound_or_zero(b::kFrameRadius, a.frame_radius);
  check_bound(b::kSynthFov, a.fov);
  check_bound(b::kPhoneDistance, a.phone_mm);
  check_bound(b::kSpecular, a.specular);
  check_bound(b::kWallMm, a.wall_mm);
  check_bound(b::kHeadScale, a.head_scale);
  const Bound room{"--room", "", 0, double(synth::kRoomLayouts), "room layout; 0: none"};
  check_bound(room, a.room);
}

// r,g,b in 0-255 sRGB as linear RGB; `flag` names the option in errors.
Eigen::Vector3f parse_srgb(const std::string& s, const char* flag) {
  float c[3];
  char comma1 = 0, comma2 = 0;
  std::istringstream in(s);
  if (!(in >> c[0] >> comma1 >> c[1] >> comma2 >> c[2]) || comma1 != ',' || comma2 != ',' || !in.eof())
    throw std::runtime_error(fmt::format("{} '{}' is not r,g,b (0-255 sRGB, e.g. 255,255,255)", flag, s));
  Eigen::Vector3f lin;
  for (int k = 0; k < 3; ++k) {
    if (c[k] < 0 || c[k] > 255)
      throw std::runtime_error(fmt::format("{} component {} is outside 0..255", flag, c[k]));
    lin[k] = srgb_to_linear(c[k] / 255.0f);
  }
  return lin;
}

std::optional<Eigen::Vector3f> parse_background(const std::string& s) {
  if (s == "transparent") return std::nullopt;
  try {
    return parse_srgb(s, "--background");
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string(e.what()) + " or 'transparent'");
  }
}

void run_synth(const SynthArgs& a) {
  if (a.procedural == !a.mesh.empty())
    throw std::runtime_error("synth: give exactly one of --mesh FILE or --procedural");
  validate(a);
  synth::SynthOptions o;
  std::tie(o.width, o.height) = parse_size(a.size);
  o.views = a.views;
  o.yaw_min_deg = a.yaw[0], o.yaw_max_deg = a.yaw[1];
  o.pitch_min_deg = a.pitch[0], o.pitch_max_deg = a.pitch[1];
  o.seed = a.seed;
  o.background = parse_background(a.background);
  o.samples_per_axis = a.samples;
  o.force = a.force;
  o.room = a.room;
  o.fov_y_deg = a.fov;
  o.phone_distance_mm = a.phone_mm;
  o.lighting.specular = a.specular;
  o.wall_mm = a.wall_mm;
  if (!a.wall.empty()) o.wall_rgb = parse_srgb(a.wall, "--wall");
  o.window = a.window;
  if ((!a.wall.empty() || a.wall_mm != 1000.0f || a.window) && a.room != synth::kPlainRoomLayout)
    throw std::runtime_error(fmt::format(
        "--wall, --wall-mm and --window describe the plain room: give --room {}", synth::kPlainRoomLayout));
  if ((!a.skin.empty() || !a.hair.empty()) && !a.procedural)
    throw std::runtime_error(
        "--skin and --hair colour the procedural head: give --procedural (a mesh has its texture)");
  if (a.head_scale != 1.0f && !a.procedural)
    throw std::runtime_error("--head-scale needs the procedural head: give --procedural");
  o.card = a.card;
  synth::HeadParams params = synth::scale_head(synth::random_head_params(a.seed), a.head_scale);
  if (!a.skin.empty()) params.skin = parse_srgb(a.skin, "--skin");
  if (!a.hair.empty()) params.hair = parse_srgb(a.hair, "--hair");
  synth::Subject subject =
      a.procedural
          ? synth::procedural_subject(params, {}, a.room > 0)
          : synth::mesh_subject(a.mesh, a.mesh_mm > 0 ? std::optional<double>(a.mesh_mm) : std::nullopt);
  if (!a.look_at.empty()) subject.look_at = Eigen::Vector3f(a.look_at[0], a.look_at[1], a.look_at[2]);
  if (a.frame_radius > 0.0f) subject.frame_radius = a.frame_radius;
  Progress progress("synth", o.views, "views");
  o.progress = [&](int done, int) { progress.update(done); };
  synth::SynthReport r = synth::synthesize_dataset(subject, a.out, o);
  progress.finish();
  if (a.json) {
    nlohmann::json j = {
        {"directory", r.directory},
        {"views", r.views},
        {"seconds", r.seconds},
        {"render_seconds", r.render_seconds},
        {"source", subject.source},
        {"mm_per_unit", subject.mm_per_unit ? nlohmann::json(*subject.mm_per_unit) : nlohmann::json()}};
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << fmt::format("wrote {} views to {} in {:.1f} s ({:.2f} s per view)\n", r.views, r.directory,
                             r.seconds, r.seconds / std::max(1, r.views));
  }
}

void add_synth(CLI::App& app, GlobalOptions&) {
  auto* cmd = app.add_subcommand(
      "synth", "render a synthetic dataset with exact ground truth (mesh file or procedural head)");
  auto a = std::make_shared<SynthArgs>();
  cmd->add_option("--mesh", a->mesh, "textured mesh (glTF/GLB/OBJ/PLY), +y up, facing +z");
  cmd->add_flag("--procedural", a->procedural, "use the procedural head (seeded by --seed)");
  cmd->add_option("-o,--output", a->out,
                  "output dataset directory (new, empty, or an earlier synth output with --force)")
      ->required();
  cmd->add_option("--views", a->views, "number of views");
  cmd->add_option("--size", a->size, "image size WxH");
  cmd->add_option("--yaw-range", a->yaw, "yaw range in degrees (a b)")->expected(2);
  cmd->add_option("--pitch-range", a->pitch, "pitch range in degrees (a b)")->expected(2);
  cmd->add_option("--seed", a->seed, "seed for the cameras and the procedural head (0 = the default head)");
  cmd->add_option("--background", a->background, "transparent, or r,g,b in 0-255 sRGB");
  cmd->add_option("--samples", a->samples, "anti-aliasing samples per pixel axis");
  cmd->add_option("--mesh-mm-per-unit", a->mesh_mm,
                  "millimetres per mesh unit, when known (ground truth scale)");
  cmd->add_option("--look-at", a->look_at,
                  "point the cameras aim at, dataset units (x y z; default: the subject's)")
      ->expected(3);
  cmd->add_option("--frame-radius", a->frame_radius, "dataset units around --look-at each view must contain");
  cmd->add_option(
      "--room", a->room,
      fmt::format("place the subject in room layout 1..{} ({}: a plain wall, see --wall; RGB images "
                  "without alpha, true mattes in "
                  "mattes/, hand-held phone cameras sweeping --yaw-range; the procedural head gets "
                  "a neck and shoulders)",
                  synth::kRoomLayouts, synth::kPlainRoomLayout));
  cmd->add_option("--fov", a->fov, "with --room: the phone's vertical field of view in degrees (default 60)");
  cmd->add_option("--phone-distance", a->phone_mm,
                  "with --room: camera distance in millimetres (default 480)");
  cmd->add_option("--skin", a->skin,
                  "the procedural head's skin albedo, r,g,b in 0-255 sRGB (e.g. 250,222,205 very pale, "
                  "70,45,35 very dark)");
  cmd->add_option("--hair", a->hair,
                  "the procedural head's hair albedo, r,g,b in 0-255 sRGB (e.g. the --wall colour: hair "
                  "that colour cannot tell from the wall)");
  cmd->add_option("--specular", a->specular,
                  "a white highlight of the key light on the subject (oily skin's sheen), 0 = none");
  cmd->add_option(
      "--wall-mm", a->wall_mm,
      fmt::format("with --room {}: the plain wall's distance behind the eyes in mm (default 1000)",
                  synth::kPlainRoomLayout));
  cmd->add_option(
      "--wall", a->wall,
      fmt::format("with --room {}: the plain wall's colour, r,g,b in 0-255 sRGB (default off-white)",
                  synth::kPlainRoomLayout));
  cmd->add_flag("--window", a->window,
                fmt::format("with --room {}: a window of daylight in the wall behind the head, larger than "
                            "its silhouette and several times the wall's brightness, which lights the "
                            "subject from behind (a dark face with a bright rim)",
                            synth::kPlainRoomLayout));
  cmd->add_option("--head-scale", a->head_scale,
                  "the procedural head's lengths times this (0.85..1.15; irises keep their size)");
  cmd->add_flag("--card", a->card,
                "with --room, and --procedural or --mesh with --mesh-mm-per-unit: the subject holds an "
                "ID-1 card against the forehead in the first half of the sweep, partly under a finger "
                "in some views (ground truth: ground_truth.json \"card\")");
  cmd->add_flag("--force", a->force, "replace an earlier synth output in the output directory");
  cmd->add_flag("--json", a->json, "print one JSON object on stdout");
  cmd->callback([a] { run_synth(*a); });
}

}  // namespace
LGN_REGISTER_COMMAND(40, add_synth);
}  // namespace lorgnette::cli
