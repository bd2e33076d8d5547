// Preview sheet rendering (surface pass + OpenCV annotations); see preview.h.
#include "mesh/preview.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "mesh/disney_brdf.h"
#include "mesh/surface_pass.h"

namespace lorgnette::mesh {
namespace {

struct View {
  const char* caption;
  Eigen::Vector3f dir;  // from the target towards the eye
  Eigen::Vector3f up;
};

cv::Mat render_panel(const SurfacePass& pass, const Glasses& g, const View& view, const PreviewOptions& o) {
  Eigen::AlignedBox3f box = pass.scene().bounds();
  Eigen::Vector3f centre = box.center();
  const float dist = 2000.0f, radius = 0.5f * box.sizes().norm();
  float aspect = static_cast<float>(o.panel_width) / o.panel_height;
  float fov = 2.0f * std::atan(0.85f * radius / dist / std::min(1.0f, aspect)) * 180.0f / kPi;
  Camera cam = look_at_camera(centre + dist * view.dir.normalized(), centre, view.up, fov, o.panel_width,
                              o.panel_height);
  SurfaceParams params;
  params.samples_per_pixel = o.samples_per_pixel;
  params.threads = o.threads;
  SurfaceBuffers buf = pass.render(cam, params);
  cv::Mat img(o.panel_height, o.panel_width, CV_8UC3);
  const float bg = 0.75f;
  for (int y = 0; y < o.panel_height; ++y)
    for (int x = 0; x < o.panel_width; ++x) {
      const float* p = &buf.color_alpha[4 * (static_cast<size_t>(y) * o.panel_width + x)];
      for (int k = 0; k < 3; ++k) {
        float c = p[k] + (1.0f - p[3]) * bg;
        img.at<cv::Vec3b>(y, x)[2 - k] = static_cast<uint8_t>(std::lround(255.0f * linear_to_srgb(c)));
      }
    }
  const std::pair<const char*, std::pair<Eigen::Vector3f, cv::Scalar>> marks[] = {
      {"g_c", {g.ref.g_c, cv::Scalar(0, 0, 230)}},
      {"g_l", {g.ref.g_l, cv::Scalar(0, 170, 0)}},
      {"g_r", {g.ref.g_r, cv::Scalar(220, 60, 0)}}};
  for (const auto& [name, mark] : marks) {
    float u, v;
    LgnVec3 p = lgn_vec3(mark.first.x(), mark.first.y(), mark.first.z());
    if (camera_project(&cam, p, &u, &v) <= 0) continue;
    cv::Point pt(static_cast<int>(u), static_cast<int>(v));
    cv::circle(img, pt, 6, cv::Scalar(255, 255, 255), 2, cv::LINE_AA);
    cv::circle(img, pt, 4, mark.second, cv::FILLED, cv::LINE_AA);
    cv::putText(img, name, pt + cv::Point(8, -8), cv::FONT_HERSHEY_SIMPLEX, 0.5, mark.second, 1, cv::LINE_AA);
  }
  cv::putText(img, view.caption, cv::Point(10, 22), cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(20, 20, 20), 1,
              cv::LINE_AA);
  return img;
}

}  // namespace

Image render_glasses_preview(const Glasses& g, const PreviewOptions& o) {
  SurfacePass pass(g.mesh, Eigen::Matrix4f::Identity());
  const View views[] = {{"front (+z), x = wearer's left to the right", {0.0f, 0.0f, 1.0f}, {0, 1, 0}},
                        {"left side (+x), front to the left", {1.0f, 0.0f, 0.0f}, {0, 1, 0}},
                        {"top (+y), front at the bottom", {0.0f, 1.0f, 0.0f}, {0, 0, -1}}};
  std::vector<cv::Mat> panels;
  for (const auto& v : views) panels.push_back(render_panel(pass, g, v, o));
  cv::Mat sheet;
  cv::hconcat(panels, sheet);
  std::string info =
      fmt::format("width {:.1f}  lens {:.1f}  bridge {:.1f}  temple {:.1f} mm", g.metrics.total_width_mm,
                  g.metrics.lens_width_mm, g.metrics.bridge_mm, g.metrics.temple_length_mm);
  cv::putText(sheet, info, cv::Point(10, sheet.rows - 12), cv::FONT_HERSHEY_SIMPLEX, 0.55,
              cv::Scalar(20, 20, 20), 1, cv::LINE_AA);
  Image out(sheet.cols, sheet.rows, 3);
  for (int y = 0; y < sheet.rows; ++y)
    for (int x = 0; x < sheet.cols; ++x)
      for (int k = 0; k < 3; ++k) out.at(x, y, k) = srgb_to_linear(sheet.at<cv::Vec3b>(y, x)[2 - k] / 255.0f);
  return out;
}

}  // namespace lorgnette::mesh
