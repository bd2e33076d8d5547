// The card step on a posed dataset; see dataset_card.h.
#include "capture/dataset_card.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "host/dataset/dataset.h"
#include "host/dataset/metric_scale.h"
#include "host/util/interrupt.h"

namespace lorgnette::capture {
namespace {

// The frames are kept in memory at this size for the card's look (a 43 x 27 px patch of 2 mm pixels;
// a card at a face spans 60-200 px of a 512 px frame), so a long capture costs ~0.25 MB a frame.
constexpr int kSmallSide = 512;

cv::Mat shrunk(const cv::Mat& grey) {
  const double s = double(kSmallSide) / std::max(grey.cols, grey.rows);
  if (s >= 1.0) return grey;
  cv::Mat out;
  cv::resize(grey, out, cv::Size(), s, s, cv::INTER_AREA);
  return out;
}

}  // namespace

DatasetCardResult measure_dataset_card(const std::string& dataset_dir, const CardDetectOptions& detect,
                                       const CardScaleOptions& scale, const CardIgnoreOptions& ignore) {
  const auto t0 = std::chrono::steady_clock::now();
  dataset::LoadOptions lo;
  lo.load_images = false;
  const dataset::Dataset ds = dataset::load_dataset(dataset_dir, lo);
  std::vector<CardView> views;
  std::vector<cv::Mat> small;  // each frame at most kSmallSide px, for the card's look (card_ignore.h)
  for (const auto& f : ds.frames) {
    if (interrupted()) throw std::runtime_error("interrupted while looking for the card");
    cv::Mat grey = cv::imread(f.image_path, cv::IMREAD_GRAYSCALE);
    if (grey.empty()) throw std::runtime_error(fmt::format("cannot read frame '{}'", f.image_path));
    if (grey.cols != int(f.camera.width) || grey.rows != int(f.camera.height))
      throw std::runtime_error(fmt::format("frame '{}' is {}x{} but its camera says {}x{}", f.image_path,
                                           grey.cols, grey.rows, f.camera.width, f.camera.height));
    views.push_back({f.name, f.camera, detect_card_quads(grey, detect)});
    small.push_back(shrunk(grey));
    for (const auto& q : views.back().candidates)
      spdlog::debug(
          "card: {} quad ({:.2f} {:.2f}) ({:.2f} {:.2f}) ({:.2f} {:.2f}) ({:.2f} {:.2f}) support {:.2f}",
          f.name, q.corners[0].x(), q.corners[0].y(), q.corners[1].x(), q.corners[1].y(), q.corners[2].x(),
          q.corners[2].y(), q.corners[3].x(), q.corners[3].y(), q.edge_support);
  }
  DatasetCardResult r;
  r.scale = measure_card_scale(views, scale);
  const std::filesystem::path dir(dataset_dir);
  if (r.scale.found) {
    dataset::write_scale_json(dataset_dir,
                              {"card", r.scale.mm_per_unit, r.scale.uncertainty, r.scale.frames});
    r.scale_written = true;
  } else {
    std::filesystem::remove(dir / dataset::kScaleFile);
  }
  const std::vector<dataset::FrameIgnore> regions = card_ignore_regions(views, small, r.scale, ignore);
  if (!regions.empty())
    dataset::write_ignore_regions(dataset_dir, {"card", ignore.margin_mm, regions});
  else
    std::filesystem::remove(dir / dataset::kIgnoreRegionsFile);
  r.ignore_frames = int(regions.size());
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace lorgnette::capture
