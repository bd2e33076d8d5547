// The card step on a posed dataset; see dataset_card.h.
#include "capture/dataset_card.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

#include "host/dataset/dataset.h"
#include "host/dataset/metric_scale.h"
#include "host/util/interrupt.h"

namespace lorgnette::capture {

DatasetCardResult measure_dataset_card(const std::string& dataset_dir, const CardDetectOptions& detect,
                                       const CardScaleOptions& scale) {
  const auto t0 = std::chrono::steady_clock::now();
  dataset::LoadOptions lo;
  lo.load_images = false;
  const dataset::Dataset ds = dataset::load_dataset(dataset_dir, lo);
  std::vector<CardView> views;
  for (const auto& f : ds.frames) {
    if (interrupted()) throw std::runtime_error("interrupted while looking for the card");
    cv::Mat grey = cv::imread(f.image_path, cv::IMREAD_GRAYSCALE);
    if (grey.empty()) throw std::runtime_error(fmt::format("cannot read frame '{}'", f.image_path));
    if (grey.cols != int(f.camera.width) || grey.rows != int(f.camera.height))
      throw std::runtime_error(fmt::format("frame '{}' is {}x{} but its camera says {}x{}", f.image_path,
                                           grey.cols, grey.rows, f.camera.width, f.camera.height));
    views.push_back({f.name, f.camera, detect_card_quads(grey, detect)});
    for (const auto& q : views.back().candidates)
      spdlog::debug(
          "card: {} quad ({:.2f} {:.2f}) ({:.2f} {:.2f}) ({:.2f} {:.2f}) ({:.2f} {:.2f}) support {:.2f}",
          f.name, q.corners[0].x(), q.corners[0].y(), q.corners[1].x(), q.corners[1].y(), q.corners[2].x(),
          q.corners[2].y(), q.corners[3].x(), q.corners[3].y(), q.edge_support);
  }
  DatasetCardResult r;
  r.scale = measure_card_scale(views, scale);
  const std::filesystem::path file = std::filesystem::path(dataset_dir) / dataset::kScaleFile;
  if (r.scale.found) {
    dataset::write_scale_json(dataset_dir,
                              {"card", r.scale.mm_per_unit, r.scale.uncertainty, r.scale.frames});
    r.scale_written = true;
  } else {
    std::filesystem::remove(file);
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace lorgnette::capture
