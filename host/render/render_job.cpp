// The `lorgnette render` job: see render_job.h.
#include "host/render/render_job.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "host/dataset/media.h"
#include "host/util/bounds.h"
#include "host/util/interrupt.h"
#include "host/util/name_list.h"
#include "host/util/output_folder.h"
#include "host/util/progress.h"

namespace lorgnette::render {
namespace fs = std::filesystem;

static void check_affine(const Mat4& m, const std::string& what) {
  for (float v : m)
    if (!std::isfinite(v)) throw std::invalid_argument(what + ": the matrix has a non-finite entry");
  if (m[12] != 0.0f || m[13] != 0.0f || m[14] != 0.0f || m[15] != 1.0f)
    throw std::invalid_argument(what + ": the last row must be 0 0 0 1 (an affine transform, row-major)");
}

Mat4 matrix_from_json(const nlohmann::json& j, const std::string& what) {
  std::vector<float> v;
  if (j.is_array() && j.size() == 4 && j[0].is_array()) {
    for (const auto& row : j) {
      if (!row.is_array() || row.size() != 4)
        throw std::invalid_argument(what + ": expected 4 rows of 4 numbers");
      for (const auto& x : row) v.push_back(x.get<float>());
    }
  } else if (j.is_array() && j.size() == 16) {
    for (const auto& x : j) v.push_back(x.get<float>());
  } else {
    throw std::invalid_argument(what + ": expected a 4x4 matrix (4 rows of 4 numbers, or 16 numbers)");
  }
  Mat4 m;
  std::copy(v.begin(), v.end(), m.begin());
  check_affine(m, what);
  return m;
}

static nlohmann::json read_json_file(const std::string& path, const char* what) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error(fmt::format("{} '{}' cannot be opened: check the path", what, path));
  try {
    return nlohmann::json::parse(f);
  } catch (const std::exception& e) {
    throw std::runtime_error(fmt::format("{} '{}' is not valid JSON: {}", what, path, e.what()));
  }
}

Camera read_pose(const std::string& path, uint32_t width, uint32_t height, float default_fov_y_deg) {
  nlohmann::json j = read_json_file(path, "pose");
  if (j.contains("frames") && j["frames"].is_array() && !j["frames"].empty()) {
    nlohmann::json top = j;
    j = j["frames"][0];
    for (const char* k : {"fl_x", "fl_y", "cx", "cy", "w", "h"})
      if (!j.contains(k) && top.contains(k)) j[k] = top[k];
  }
  if (!j.contains("transform_matrix"))
    throw std::runtime_error("pose '" + path +
                             "' has no \"transform_matrix\" (4x4 camera-to-world, OpenGL "
                             "convention as in transforms.json)");
  Mat4 m = matrix_from_json(j["transform_matrix"], "pose '" + path + "' transform_matrix");
  Camera c{};
  for (int i = 0; i < 12; ++i) c.c2w[i] = m[i];
  c.width = width;
  c.height = height;
  if (j.contains("fl_x") && j.contains("w") && j.contains("h")) {
    float sx = float(width) / j["w"].get<float>(), sy = float(height) / j["h"].get<float>();
    c.fx = j["fl_x"].get<float>() * sx;
    c.fy = j.value("fl_y", j["fl_x"].get<float>()) * sy;
    c.cx = j.value("cx", 0.5f * j["w"].get<float>()) * sx;
    c.cy = j.value("cy", 0.5f * j["h"].get<float>()) * sy;
  } else {
    float fov = j.value("fov_y_deg", default_fov_y_deg);
    c.fy = c.fx = 0.5f * float(height) / std::tan(0.5f * fov * float(M_PI) / 180.0f);
    c.cx = 0.5f * float(width);
    c.cy = 0.5f * float(height);
  }
  return c;
}

std::array<uint32_t, 2> parse_size(const std::string& text) {
  std::smatch m;
  if (!std::regex_match(text, m, std::regex("([0-9]{1,5})x([0-9]{1,5})")))
    throw std::invalid_argument("--size '" + text + "': expected WIDTHxHEIGHT, e.g. 1280x720");
  uint32_t w = std::stoul(m[1]), h = std::stoul(m[2]);
  if (w == 0 || h == 0 || w > 8192 || h > 8192)
    throw std::invalid_argument("--size '" + text + "': width and height must be in 1..8192");
  return {w, h};
}

void check_outputs_free(const std::string& dir, const std::vector<std::string>& names, bool force) {
  if (force) return;
  std::vector<std::string> taken;
  for (const auto& n : names)
    if (fs::exists(fs::path(dir) / n)) taken.push_back(n);
  if (taken.empty()) return;
  throw std::runtime_error(
      fmt::format("'{}' already holds {}: choose another -o directory or pass --force to overwrite", dir,
                  name_list(taken)));
}

std::vector<std::string> render_job_outputs(const RenderJob& job) {
  std::vector<std::string> names;
  for (size_t i = 0; i < job.cameras.size(); ++i) {
    names.push_back(fmt::format("frame_{:04d}.png", i));
    names.push_back(fmt::format("depth_{:04d}.exr", i));
  }
  if (job.video && job.cameras.size() > 1) names.push_back("orbit.mp4");
  if (job.contact_sheet) names.push_back("contact_sheet.png");
  names.push_back("render.json");
  return names;
}

Image to_output_image(const Image& rgba, bool alpha) {
  Image out(rgba.width, rgba.height, alpha ? 4 : 3);
  const size_t n = size_t(rgba.width) * rgba.height;
  for (size_t i = 0; i < n; ++i) {
    const float* p = &rgba.pixels[4 * i];
    float* q = &out.pixels[i * out.channels];
    // The marcher's alpha-mode colour is premultiplied; image files want straight alpha.
    float inv = (alpha && p[3] > 1e-6f) ? 1.0f / p[3] : 1.0f;
    for (int c = 0; c < 3; ++c) q[c] = std::min(std::max(p[c] * inv, 0.0f), 1.0f);
    if (alpha) q[3] = std::min(std::max(p[3], 0.0f), 1.0f);
  }
  return out;
}

namespace {
// Up to `k` evenly spaced view indices for the contact sheet.
std::vector<size_t> sheet_indices(size_t n, size_t k) {
  std::vector<size_t> idx;
  for (size_t i = 0; i < std::min(n, k); ++i) idx.push_back(n <= k ? i : i * n / k);
  return idx;
}

// The orbit's MP4 writer, or none (one view, or no video asked for).
std::unique_ptr<dataset::Mp4Writer> open_video(const RenderJob& job, const fs::path& dir) {
  if (!job.video || job.cameras.size() < 2) return nullptr;
  dataset::VideoOptions vo;
  vo.fps = job.fps;
  vo.background = job.options.background;
  return std::make_unique<dataset::Mp4Writer>((dir / "orbit.mp4").string(), int(job.cameras[0].width),
                                              int(job.cameras[0].height), vo);
}
}  // namespace

nlohmann::json run_render_job(
    RenderJob& job,
    const std::function<RenderResult(const Camera&, const lorgnette::SurfaceBuffers*)>& render) {
  if (job.cameras.empty()) throw std::invalid_argument("render: no camera to render");
  check_outputs_free(job.out_dir, render_job_outputs(job), job.force);
  // Declared first, so it is undone last: a failed job leaves no folder or file of its own.
  NewOutputs outputs(job.out_dir, render_job_outputs(job));
  const fs::path dir(job.out_dir);
  const size_t n = job.cameras.size();
  std::vector<size_t> sheet = sheet_indices(n, 16);
  std::vector<Image> sheet_images;
  std::vector<std::string> sheet_labels;
  std::unique_ptr<dataset::Mp4Writer> video = open_video(job, dir);
  nlohmann::json frames = nlohmann::json::array();
  std::vector<double> ms;
  double samples = 0, rays = 0;
  Progress progress("render", double(n), "views");
  for (size_t i = 0; i < n; ++i) {
    if (interrupted()) {
      // A stop asked for keeps the whole views written so far (docs/input-limits.md); an error does not.
      if (i > 0) outputs.keep();
      throw std::runtime_error("interrupted: the frames written so far are complete files");
    }
    const Camera& cam = job.cameras[i];
    lorgnette::SurfaceBuffers surf;
    double surface_ms = 0;
    if (job.surfaces) {
      auto t0 = std::chrono::steady_clock::now();
      surf = job.surfaces(cam);
      surface_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    }
    RenderResult r = render(cam, job.surfaces ? &surf : nullptr);
    Image img = to_output_image(r.rgba, job.options.alpha);
    write_image((dir / fmt::format("frame_{:04d}.png", i)).string(), img);
    write_image((dir / fmt::format("depth_{:04d}.exr", i)).string(), r.depth);
    if (video) video->add(img);
    if (std::find(sheet.begin(), sheet.end(), i) != sheet.end()) {
      sheet_images.push_back(img);
      sheet_labels.push_back(fmt::format("view {}", i));
    }
    ms.push_back(r.seconds * 1e3);
    samples += double(r.samples_composited);
    rays += double(r.rays);
    frames.push_back({{"index", i},
                      {"march_ms", r.seconds * 1e3},
                      {"surface_ms", surface_ms},
                      {"samples_per_ray", r.samples_per_ray()},
                      {"samples_evaluated", r.samples_evaluated}});
    progress.update(double(i + 1), fmt::format("{:.0f} ms/frame", r.seconds * 1e3));
  }
  progress.finish();
  nlohmann::json out = {{"views", n},
                        {"width", job.cameras[0].width},
                        {"height", job.cameras[0].height},
                        {"spp", job.options.spp},
                        {"step_scale", job.options.step_scale},
                        {"alpha", job.options.alpha},
                        {"glasses", bool(job.surfaces)},
                        {"samples_per_ray", rays > 0 ? samples / rays : 0.0},
                        {"frames", frames}};
  if (video) {
    video->finish();
    out["video"] = "orbit.mp4";
    out["video_codec"] = video->codec();
  }
  if (job.contact_sheet) {
    dataset::ContactSheetOptions so;
    so.background = job.options.background;
    dataset::write_contact_sheet((dir / "contact_sheet.png").string(), sheet_images, sheet_labels, so);
    out["contact_sheet"] = "contact_sheet.png";
  }
  std::sort(ms.begin(), ms.end());
  out["median_march_ms"] = ms[ms.size() / 2];
  write_text_file_atomic((dir / "render.json").string(), out.dump(2) + "\n");
  outputs.keep();
  return out;
}

}  // namespace lorgnette::render
