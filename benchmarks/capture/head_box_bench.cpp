// head_box_bench: the head box (fit/head_box.h) on real head captures. For each dataset: the time to
// detect, triangulate and box, the faces found, the estimated scale and PD, the box in millimetres,
// its volume against the automatic camera box that training used before, and overlay PNGs of the
// oriented box (projected with the photo's camera, distortion included) on three photos so the box
// can be checked by eye. Writes head_box.csv and <name>_box_<i>.png to --out.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "capture/subject_box.h"
#include "fit/camera_math.h"
#include "fit/landmarks_dlib.h"
#include "host/nerf/sizing.h"
#include "host/util/chart.h"

namespace fs = std::filesystem;
using namespace lorgnette;

namespace {

// The 8 corners of the oriented box (scene).
std::vector<Eigen::Vector3d> corners(const fit::HeadBox& b) {
  std::vector<Eigen::Vector3d> c;
  for (int i = 0; i < 8; ++i) {
    Eigen::Vector3d s((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1);
    c.push_back(b.center + b.axes * s.cwiseProduct(b.half_extent));
  }
  return c;
}

// Draws the box's 12 edges (sampled, so distortion bends them correctly) on the photo.
void write_overlay(const dataset::Frame& f, const fit::HeadBox& b, const std::string& path) {
  std::vector<unsigned char> rgb = fit::to_srgb8(f.image);
  cv::Mat img(f.image.height, f.image.width, CV_8UC3, rgb.data());
  cv::Mat bgr;
  cv::cvtColor(img, bgr, cv::COLOR_RGB2BGR);
  auto c = corners(b);
  for (int i = 0; i < 8; ++i)
    for (int bit : {1, 2, 4}) {
      int j = i | bit;
      if (j == i) continue;
      Eigen::Vector2d prev;
      bool have = false;
      for (int s = 0; s <= 32; ++s) {
        Eigen::Vector3d p = c[i] + (c[j] - c[i]) * (s / 32.0);
        Eigen::Vector2d uv;
        bool ok = fit::camera_project(f.camera, p, &uv);
        if (ok && have)
          cv::line(bgr, cv::Point2d(prev.x() - 0.5, prev.y() - 0.5), cv::Point2d(uv.x() - 0.5, uv.y() - 0.5),
                   bit == 4 ? cv::Scalar(0, 200, 255) : cv::Scalar(255, 220, 0), 2, cv::LINE_AA);
        prev = uv, have = ok;
      }
    }
  cv::imwrite(path, bgr);
}

// The automatic camera box (host/nerf/sizing.h, no masks): a cube around the look-at point with
// half-size aabb_scale * 0.5 * median camera distance.
double camera_box_volume(const dataset::Dataset& ds) {
  std::vector<Camera> cams;
  for (const auto& f : ds.frames) cams.push_back(f.camera);
  auto la = nerf::cameras_look_at(cams);
  std::vector<double> d;
  for (const auto& c : cams)
    d.push_back((fit::camera_center(c) - Eigen::Vector3d(la[0], la[1], la[2])).norm());
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  double side = ds.aabb_scale * d[d.size() / 2];
  return side * side * side;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"head box on real head captures"};
  std::string out = "head_box_bench";
  std::vector<std::string> inputs = {std::string(LORGNETTE_DATA_DIR) + "/heads/in2n-face",
                                     std::string(LORGNETTE_DATA_DIR) + "/heads/fangzhou-frontal"};
  app.add_option("--out", out, "output directory");
  app.add_option("datasets", inputs, "dataset directories (default: the two real head captures)");
  CLI11_PARSE(app, argc, argv);
  fs::create_directories(out);
  std::vector<std::vector<std::string>> rows;
  for (const auto& in : inputs) {
    std::string name = fs::path(in).filename().string();
    dataset::Dataset ds = dataset::load_dataset(in);
    auto t0 = std::chrono::steady_clock::now();
    fit::HeadBox b = fit::estimate_head_box(capture::posed_photos(ds));
    double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    Eigen::Vector3d mm = 2.0 * b.half_extent * b.head.mm_per_unit;
    double vol = (b.max - b.min).prod(), cam_vol = camera_box_volume(ds);
    spdlog::info("{}: {} in {:.1f} s; box volume {:.3g} vs camera box {:.3g} ({:.1f}x smaller)", name,
                 b.summary(), sec, vol, cam_vol, cam_vol / vol);
    rows.push_back({name, std::to_string(ds.split(dataset::Split::Train).size()),
                    std::to_string(b.photos_tried), std::to_string(b.faces_found),
                    std::to_string(b.landmarks_triangulated), fmt::format("{:.1f}", b.head.mm_per_unit),
                    fmt::format("{:.1f}", b.head.pd_mm), fmt::format("{:.2f}", sec),
                    fmt::format("{:.0f}x{:.0f}x{:.0f}", mm.x(), mm.y(), mm.z()), fmt::format("{:.4g}", vol),
                    fmt::format("{:.4g}", cam_vol)});
    auto train = ds.split(dataset::Split::Train);
    for (size_t k : fit::even_subset(train.size(), 3))
      write_overlay(*train[k], b, (fs::path(out) / fmt::format("{}_box_{}.png", name, k)).string());
  }
  write_csv((fs::path(out) / "head_box.csv").string(),
            {"dataset", "train_photos", "tried", "faces", "landmarks", "mm_per_unit", "pd_mm", "seconds",
             "box_mm_lr_x_ud_x_fb", "aabb_volume", "camera_box_volume"},
            rows);
  return 0;
}
