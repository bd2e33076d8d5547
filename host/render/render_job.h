// The `lorgnette render` job as a library: camera poses (an orbit framing the head's box, or a pose
// JSON; the glasses' placement transform is fit/placement_transform.h's), and the
// outputs (colour PNGs, linear depth EXRs, an MP4 of the orbit, a contact sheet, render.json),
// never overwriting existing files unless forced. The glasses' surface pass comes in as a
// callback so this library does not depend on the mesh module.
#pragma once
#include <array>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "host/render/marcher.h"
#include "host/render/orbit.h"
#include "host/util/surface_buffers.h"

namespace lorgnette::nerf {
class NerfModel;
}

namespace lorgnette::render {

using Mat4 = std::array<float, 16>;  // row-major 4x4 (a camera pose)

// 16 numbers (row-major) from a JSON array (flat or 4x4 nested); an affine transform.
Mat4 matrix_from_json(const nlohmann::json& j, const std::string& what);

// One camera from a pose JSON: {"transform_matrix": 4x4 camera-to-world (OpenGL, as
// transforms.json)} plus optional "fl_x", "fl_y", "cx", "cy", "w", "h" (scaled to the requested
// size) or "fov_y_deg". Throws naming the file and the missing/bad key.
Camera read_pose(const std::string& path, uint32_t width, uint32_t height, float default_fov_y_deg);

// "1280x720" -> {1280, 720}; throws on anything else.
std::array<uint32_t, 2> parse_size(const std::string& text);

// Throws when any of `names` exists in `dir` and !force (lists them; suggests --force or another -o).
void check_outputs_free(const std::string& dir, const std::vector<std::string>& names, bool force);

using SurfacePass = std::function<lorgnette::SurfaceBuffers(const Camera&)>;

struct RenderJob {
  std::vector<Camera> cameras;
  RenderOptions options;
  SurfacePass surfaces;  // empty: the head alone
  std::string out_dir;
  bool force = false;
  bool video = true;  // the MP4 (when there is more than one view and media support)
  bool contact_sheet = true;
  double fps = 24.0;
};

// Renders every camera, writes the outputs and returns the summary written to render.json.
nlohmann::json run_render_job(
    RenderJob& job,
    const std::function<RenderResult(const Camera&, const lorgnette::SurfaceBuffers*)>& render);

// File names the job writes for n views (frame_0000.png, depth_0000.exr, ..., orbit.mp4, ...).
std::vector<std::string> render_job_outputs(const RenderJob& job);

// The linear colour image as written: RGB over the background, or straight-alpha RGBA when alpha.
Image to_output_image(const Image& rgba, bool alpha);

}  // namespace lorgnette::render
