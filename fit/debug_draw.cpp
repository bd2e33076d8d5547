// Annotated debug views with OpenCV drawing (see debug_draw.h).
#include "fit/debug_draw.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "fit/camera_math.h"
#include "fit/landmark_ids.h"
#include "host/util/file_write.h"

namespace lorgnette::fit {

cv::Mat to_bgr8(const Image& img) {
  std::vector<unsigned char> rgb = to_srgb8(img);
  cv::Mat m(img.height, img.width, CV_8UC3);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const unsigned char* p = &rgb[(size_t(y) * img.width + x) * 3];
      m.at<cv::Vec3b>(y, x) = cv::Vec3b(p[2], p[1], p[0]);
    }
  return m;
}

namespace {

bool is_key(int k) {
  return k == lm::kTempleL || k == lm::kTempleR || k == lm::kNoseBridgeTop || k == lm::kNoseBridge2 ||
         k == lm::kEyeOuterL || k == lm::kEyeOuterR;
}

}  // namespace

void write_debug_views(const std::string& dir, const std::vector<ViewRecord>& views,
                       const std::vector<TriangulatedPoint>& points) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec)
    throw std::runtime_error(fmt::format("cannot create the debug directory '{}': {}", dir, ec.message()));
  std::string index = "view yaw_deg pitch_deg face rms_residual_px\n";
  for (size_t i = 0; i < views.size(); ++i) {
    const ViewRecord& v = views[i];
    if (v.image.empty()) continue;
    cv::Mat m = to_bgr8(v.image);
    const auto& d = v.detection;
    double sum2 = 0;
    int n = 0;
    if (d.found) {
      cv::rectangle(m, cv::Point(int(d.box[0]), int(d.box[1])), cv::Point(int(d.box[2]), int(d.box[3])),
                    cv::Scalar(255, 160, 0), 1);
      for (const auto& p : d.points)
        cv::circle(m, cv::Point2d(p.x() - 0.5, p.y() - 0.5), 2, cv::Scalar(0, 200, 0), -1);
    }
    for (int k = 0; k < int(points.size()); ++k) {
      if (!points[k].ok) continue;
      Eigen::Vector2d uv;
      if (!camera_project(v.camera, points[k].position, &uv)) continue;
      cv::circle(m, cv::Point2d(uv.x() - 0.5, uv.y() - 0.5), is_key(k) ? 4 : 2, cv::Scalar(0, 0, 255), 1);
      if (d.found) sum2 += (uv - d.points[k]).squaredNorm(), ++n;
    }
    double rms = n ? std::sqrt(sum2 / n) : 0.0;
    std::string label = fmt::format("yaw {:.0f} pitch {:.0f} {}", v.yaw_deg, v.pitch_deg,
                                    d.found ? fmt::format("rms {:.2f} px", rms) : std::string("NO FACE"));
    cv::putText(m, label, cv::Point(6, 18), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1,
                cv::LINE_AA);
    std::string path = fmt::format("{}/view_{:02d}.png", dir, i);
    std::vector<uchar> png;
    if (!cv::imencode(".png", m, png)) throw std::runtime_error(fmt::format("cannot encode '{}'", path));
    write_file_atomic(path, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
    index += fmt::format("{} {:.2f} {:.2f} {} {:.3f}\n", i, v.yaw_deg, v.pitch_deg, d.found ? 1 : 0, rms);
  }
  write_text_file_atomic(dir + "/views.txt", index);
}

}  // namespace lorgnette::fit
