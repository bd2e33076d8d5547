// How cleanly models trained on synthetic room captures (`lorgnette synth --room`) separate the
// subject (issue 13): per case (a .lnerf and its dataset), the held-out views are rendered and scored
// against their true mattes with the product's metric (host/render/matte_eval.h: IoU, leak, face
// PSNR, and the holes in the head's interior, host/render/hole_eval.h: the mean over views and the
// worst view's), and the leak is split by where it lies, so its cause can be read off:
//   edge   opacity within 2 px of the true matte's outline (anti-aliasing, a soft silhouette);
//   below  farther out, below the chin (the lowest of the 68 true landmarks): haze under the jaw;
//   other  farther out elsewhere (floaters, room density left in the box).
// edge is also split into the outline's own anti-aliased pixels (0 < matte < 1) and the room pixels
// (matte 0) within 2 px; beside the product's leak (opacity x (1 - matte)) it reports the leak beyond
// the matte's coverage (max(0, opacity - matte), MatteScore::leak_excess), which a render whose
// opacity equals the anti-aliased matte does not pay, and the mean opacity against the distance from
// the matte's outline (room_matte_profile.csv / .png), which tells a 1-px soft silhouette from haze.
// --min-alpha a,b,...: also score the model with every occupancy cell whose density gives less than
// that opacity over one marching step cleared (the subject region's threshold at extraction; 0 =
// the model as saved), to see which threshold the metric supports.
// --judge-box MODEL.lnerf: judge every case in that model's box instead of its own (score_matte judges
// only the matte pixels whose subject point lies in the box), so arms whose boxes differ (train --hair)
// are scored over one region; a model whose box is smaller then pays for what it cut.
// Usage: bench_room_matte OUT_DIR --case NAME MODEL.lnerf DATASET [--case ...] [--min-alpha 0,0.1]
//        [--sheet-views N] [--judge-box MODEL.lnerf]
// Writes OUT_DIR/room_matte.csv (one row per case and threshold), OUT_DIR/room_matte_profile.csv
// and .png (opacity by distance from the outline) and OUT_DIR/<case>_sheet.png
// (per held-out view: prediction over white | photo | opacity error: red = opacity where the
// matte is room, blue = subject the prediction misses).
#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "fit/landmarks_dlib.h"
#include "host/dataset/dataset.h"
#include "host/render/matte_eval.h"
#include "host/render/renderer.h"
#include "host/util/chart.h"
#include "synth/matte.h"

using namespace lorgnette;
namespace fs = std::filesystem;

namespace {

struct Case {
  std::string name, model, dataset;
};

struct HeldOut {
  const dataset::Frame* frame = nullptr;
  Image matte, depth;
};

struct LeakSplit {
  double edge = 0, below = 0, other = 0;  // fractions of the subject's pixels, like MatteScore::leak
  // edge = outline + ring: the outline's own pixels (0 < matte < 1, the anti-aliased ones) and the
  // room pixels (matte 0) within 2 px of the matte.
  double outline = 0, ring = 0;
  double floor = 0;  // the leak of a render whose opacity equals the matte (its anti-aliased outline)
  // max(0, opacity - matte) (MatteScore::leak_excess) within 2 px of the matte, and farther out
  double excess_edge = 0, excess_far = 0;
};

// Opacity against the signed distance (px) from the true matte's outline (matte >= 0.5): negative
// inside the subject, positive in the room; one bin per pixel of distance, summed over views.
constexpr int kProfileMin = -4, kProfileMax = 10;
struct Profile {
  struct Bin {
    long pixels = 0;
    double opacity = 0, matte = 0, leak = 0, excess = 0;
  };
  std::vector<Bin> bins = std::vector<Bin>(kProfileMax - kProfileMin + 1);
  long subject_pixels = 0;
};

// True where the matte's subject point lies outside the model's box (score_matte does not judge it).
bool outside_box(const HeldOut& h, const nerf::Aabb& box, int x, int y) {
  const float d = h.depth.at(x, y, 0);
  if (!std::isfinite(d) || h.matte.at(x, y, 0) < 0.5f) return false;
  const LgnVec3 o = camera_origin(&h.frame->camera),
                dir = camera_ray_dir(&h.frame->camera, x + 0.5f, y + 0.5f);
  const float p[3] = {o.x + d * dir.x, o.y + d * dir.y, o.z + d * dir.z};
  for (int k = 0; k < 3; ++k)
    if (p[k] < box.min[k] || p[k] > box.max[k]) return true;
  return false;
}

// The leak of one view, split by where it lies (see the file comment), and its opacity profile
// across the outline. Same region rule as score_matte: matte pixels whose subject point lies
// outside the model's box are not judged.
LeakSplit split_leak(const Image& pred, const HeldOut& h, const nerf::Aabb& box,
                     const std::vector<Eigen::Vector3f>& face, long subject_pixels, Profile& profile) {
  const Camera& cam = h.frame->camera;
  const int w = h.matte.width, ht = h.matte.height;
  cv::Mat inside(ht, w, CV_8U), room(ht, w, CV_8U);
  for (int y = 0; y < ht; ++y)
    for (int x = 0; x < w; ++x) {
      const bool t = h.matte.at(x, y, 0) >= 0.5f;
      inside.at<uint8_t>(y, x) = t ? 255 : 0;
      room.at<uint8_t>(y, x) = t ? 0 : 255;
    }
  cv::Mat near, dist_out, dist_in;
  cv::dilate(inside, near, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(5, 5)));
  cv::distanceTransform(room, dist_out, cv::DIST_L2, cv::DIST_MASK_PRECISE);   // room px to the subject
  cv::distanceTransform(inside, dist_in, cv::DIST_L2, cv::DIST_MASK_PRECISE);  // subject px to the room
  float chin_v = -1e30f;
  for (const auto& p : face) {
    float u, v;
    if (camera_project(&cam, lgn_vec3(p.x(), p.y(), p.z()), &u, &v) > 0.0f) chin_v = std::max(chin_v, v);
  }
  LeakSplit s;
  for (int y = 0; y < ht; ++y)
    for (int x = 0; x < w; ++x) {
      if (outside_box(h, box, x, y)) continue;
      const double m = h.matte.at(x, y, 0), a = pred.at(x, y, 3);
      const double leak = a * (1.0 - m), excess = std::max(0.0, a - m);
      const float d = m >= 0.5 ? -dist_in.at<float>(y, x) : dist_out.at<float>(y, x);
      const int bin = std::clamp(int(std::lround(d)), kProfileMin, kProfileMax) - kProfileMin;
      Profile::Bin& b = profile.bins[size_t(bin)];
      ++b.pixels, b.opacity += a, b.matte += m, b.leak += leak, b.excess += excess;
      s.floor += m * (1.0 - m);
      const bool is_near = near.at<uint8_t>(y, x) != 0;
      (is_near ? s.excess_edge : s.excess_far) += excess;
      if (leak <= 0.0) continue;
      if (is_near)
        (m > 0.0 ? s.outline : s.ring) += leak;
      else if (y + 0.5f > chin_v)
        s.below += leak;
      else
        s.other += leak;
    }
  profile.subject_pixels += subject_pixels;
  const double n = subject_pixels ? double(subject_pixels) : 1.0;
  s.outline /= n, s.ring /= n, s.below /= n, s.other /= n, s.floor /= n;
  s.excess_edge /= n, s.excess_far /= n;
  s.edge = s.outline + s.ring;
  return s;
}

// prediction over white | photo | opacity error (grey: not judged, the body below the box), one
// row per view.
cv::Mat sheet_row(const Image& pred, const HeldOut& view, const nerf::Aabb& box) {
  const Image &photo = view.frame->image, &matte = view.matte;
  const int w = pred.width, h = pred.height;
  cv::Mat row(h, 3 * w, CV_8UC3);
  auto px = [](float linear) {
    return uint8_t(std::lround(255.0f * std::clamp(linear_to_srgb(linear), 0.f, 1.f)));
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float a = pred.at(x, y, 3), m = matte.at(x, y, 0);
      cv::Vec3b p, t, e;
      for (int c = 0; c < 3; ++c) {
        p[2 - c] = px(pred.at(x, y, c) + (1.0f - a));  // premultiplied colour over white
        t[2 - c] = px(photo.at(x, y, c));
      }
      const float extra = std::max(0.0f, a - m), missing = std::max(0.0f, m - a);
      e = cv::Vec3b(uint8_t(255 * (1 - extra)), uint8_t(255 * (1 - extra - missing)),
                    uint8_t(255 * (1 - missing)));
      if (outside_box(view, box, x, y)) e = cv::Vec3b(200, 200, 200);
      row.at<cv::Vec3b>(y, x) = p, row.at<cv::Vec3b>(y, x + w) = t, row.at<cv::Vec3b>(y, x + 2 * w) = e;
    }
  return row;
}

// Face PSNRs when the dataset has no true landmarks (a mesh subject such as the scan): the hull of
// dlib's 68 landmarks on the photo (render::score_face); nullopt when dlib finds no face.
std::optional<render::MatteScore> detected_face_psnr(const Image& pred, const Image& photo,
                                                     const Image& matte, const fit::LandmarkDetector& dlib) {
  fit::FaceDetection d = dlib.detect(photo);
  if (!d.found) return std::nullopt;
  render::MatteScore s;
  render::score_face(pred, photo, matte, d.points, s);
  if (!s.face_pixels) return std::nullopt;
  return s;
}

// Clears occupancy cells whose density gives less than `alpha` opacity over one step.
void threshold_occupancy(nerf::NerfModel& model, const nerf::OccupancyGrid& saved, float alpha) {
  nerf::OccupancyGrid g = saved;
  if (alpha > 0.0f && !g.density.empty()) {
    const float sigma = -std::log(1.0f - alpha) / model.step();
    for (size_t c = 0; c < g.density.size(); ++c)
      if (g.density[c] < sigma) g.bits[c >> 5] &= ~(1u << (c & 31u));
  }
  model.set_occupancy(std::move(g));
}

}  // namespace

static int run(int argc, char** argv) {
  if (argc < 4) {
    std::cerr << "usage: bench_room_matte OUT_DIR --case NAME MODEL DATASET [...] [--min-alpha 0,0.1] "
                 "[--sheet-views N] [--judge-box MODEL.lnerf]\n";
    return 2;
  }
  const std::string out = argv[1];
  std::vector<Case> cases;
  std::vector<float> alphas = {0.0f};
  int sheet_views = 2;
  std::string judge_model;
  for (int i = 2; i < argc; ++i) {
    if (std::strcmp(argv[i], "--case") == 0 && i + 3 < argc)
      cases.push_back({argv[i + 1], argv[i + 2], argv[i + 3]}), i += 3;
    else if (std::strcmp(argv[i], "--min-alpha") == 0 && i + 1 < argc) {
      alphas.clear();
      for (char* tok = std::strtok(argv[++i], ","); tok; tok = std::strtok(nullptr, ","))
        alphas.push_back(std::strtof(tok, nullptr));
    } else if (std::strcmp(argv[i], "--sheet-views") == 0 && i + 1 < argc)
      sheet_views = std::atoi(argv[++i]);
    else if (std::strcmp(argv[i], "--judge-box") == 0 && i + 1 < argc)
      judge_model = argv[++i];
    else
      return std::cerr << "unknown argument " << argv[i] << "\n", 2;
  }
  fs::create_directories(out);
  cl::Runtime rt;
  std::optional<nerf::Aabb> judge_box;
  if (!judge_model.empty()) judge_box = nerf::NerfModel::load(rt, judge_model).aabb();
  render::Renderer renderer(rt);
  std::unique_ptr<fit::LandmarkDetector> dlib;  // loaded for the first case without true landmarks
  std::vector<std::vector<std::string>> csv, profile_csv;
  std::vector<ChartSeries> profile_series;  // mean opacity by distance from the outline, one per case
  ChartSeries matte_series{"true matte (first case)", {}, {}};
  for (const Case& c : cases) {
    nerf::NerfModel model = nerf::NerfModel::load(rt, c.model);
    const nerf::Aabb box = judge_box ? *judge_box : model.aabb();  // the judged region
    dataset::LoadOptions lo;
    lo.splits = {dataset::Split::Holdout};
    dataset::Dataset ds = dataset::load_dataset(c.dataset, lo);
    nlohmann::json gt = nlohmann::json::parse(std::ifstream(c.dataset + "/ground_truth.json"));
    const std::map<std::string, synth::EvalFiles> by_stem = synth::eval_files_by_stem(c.dataset);
    if (by_stem.empty())
      throw std::runtime_error(c.dataset + " has no true mattes: make it with synth --room");
    std::vector<Eigen::Vector3f> face;
    for (const auto& p : gt.at("ibug68"))
      face.emplace_back(p[0].get<float>(), p[1].get<float>(), p[2].get<float>());
    std::vector<HeldOut> held;
    for (const dataset::Frame* f : ds.require_split(dataset::Split::Holdout)) {
      auto it = by_stem.at(fs::path(f->image_path).stem().string());
      held.push_back(
          {f, synth::read_matte(c.dataset + "/" + it.matte), read_image(c.dataset + "/" + it.depth)});
    }
    const nerf::OccupancyGrid saved = model.occupancy();
    for (float alpha : alphas) {
      threshold_occupancy(model, saved, alpha);
      std::vector<render::MatteScore> scores;
      LeakSplit leak;
      Profile profile;
      std::vector<cv::Mat> rows;
      double dlib_psnr = 0.0, dlib_psnr_subject = 0.0;
      int dlib_faces = 0;
      if (face.empty() && !dlib) dlib = std::make_unique<fit::LandmarkDetector>();
      for (const HeldOut& h : held) {
        render::RenderOptions ro;
        Image pred = renderer.render(model, h.frame->camera, nullptr, ro).rgba;
        render::MatteView v{h.frame->camera, &pred, &h.frame->image, &h.matte, &h.depth, face};
        scores.push_back(render::score_matte(v, box));
        if (face.empty())
          if (auto f = detected_face_psnr(pred, h.frame->image, h.matte, *dlib))
            dlib_psnr += f->face_psnr, dlib_psnr_subject += f->face_psnr_subject, ++dlib_faces;
        LeakSplit s = split_leak(pred, h, box, face, scores.back().subject_pixels, profile);
        const double k = 1.0 / double(held.size());
        leak.edge += k * s.edge, leak.below += k * s.below, leak.other += k * s.other;
        leak.outline += k * s.outline, leak.ring += k * s.ring, leak.floor += k * s.floor;
        leak.excess_edge += k * s.excess_edge, leak.excess_far += k * s.excess_far;
        if (int(rows.size()) < sheet_views && alpha == alphas.front())
          rows.push_back(sheet_row(pred, h, box));
      }
      render::MatteScore m = render::mean_score(scores);
      if (face.empty()) {
        m.face_psnr = dlib_faces ? dlib_psnr / dlib_faces : 0.0;
        m.face_psnr_subject = dlib_faces ? dlib_psnr_subject / dlib_faces : 0.0;
      }
      const std::string face_region =
          face.empty() ? fmt::format("dlib on the photo ({}/{} views)", dlib_faces, held.size())
                       : "68 true landmarks";
      const uint64_t occupied = model.occupancy().occupied_count();
      std::cerr << fmt::format(
          "{} min-alpha {:.3f}: IoU {:.4f}, leak {:.2f} % (edge {:.2f}, below chin {:.2f}, other {:.2f}; "
          "the matte's own {:.2f}); beyond the matte's coverage {:.2f} % (edge {:.2f}, farther {:.2f}); "
          "face PSNR {:.2f} dB ({}; {:.2f} dB where the subject covers the pixel); holes {:.2f} % of the "
          "head's interior (worst view {:.2f} %), {} views, {} occupied cells\n",
          c.name, alpha, m.iou, 100 * m.leak, 100 * leak.edge, 100 * leak.below, 100 * leak.other,
          100 * leak.floor, 100 * m.leak_excess, 100 * leak.excess_edge, 100 * leak.excess_far, m.face_psnr,
          face_region, m.face_psnr_subject, 100 * m.holes, 100 * m.holes_worst, scores.size(), occupied);
      csv.push_back({c.name,
                     fmt::format("{:.3f}", alpha),
                     fmt::format("{:.4f}", m.iou),
                     fmt::format("{:.4f}", m.leak),
                     fmt::format("{:.4f}", leak.edge),
                     fmt::format("{:.4f}", leak.below),
                     fmt::format("{:.4f}", leak.other),
                     fmt::format("{:.4f}", leak.floor),
                     fmt::format("{:.3f}", m.face_psnr),
                     face_region,
                     std::to_string(scores.size()),
                     std::to_string(occupied),
                     std::to_string(model.metadata.steps),
                     fmt::format("{:.1f}", model.metadata.train_seconds),
                     fmt::format("{:.4f}", m.leak_excess),
                     fmt::format("{:.4f}", leak.excess_edge),
                     fmt::format("{:.4f}", leak.excess_far),
                     fmt::format("{:.4f}", leak.outline),
                     fmt::format("{:.4f}", leak.ring),
                     fmt::format("{:.3f}", m.face_psnr_subject),
                     fmt::format("{:.4f}", m.holes),
                     fmt::format("{:.4f}", m.holes_worst)});
      ChartSeries opacity_series{c.name, {}, {}};
      for (int b = 0; b < int(profile.bins.size()); ++b) {
        const Profile::Bin& bin = profile.bins[size_t(b)];
        if (!bin.pixels) continue;
        const double n = double(bin.pixels), subj = double(std::max(1L, profile.subject_pixels));
        profile_csv.push_back({c.name, fmt::format("{:.3f}", alpha), std::to_string(b + kProfileMin),
                               std::to_string(bin.pixels), fmt::format("{:.4f}", bin.opacity / n),
                               fmt::format("{:.4f}", bin.matte / n), fmt::format("{:.5f}", bin.leak / subj),
                               fmt::format("{:.5f}", bin.excess / subj)});
        opacity_series.x.push_back(b + kProfileMin), opacity_series.y.push_back(bin.opacity / n);
        if (profile_series.empty())
          matte_series.x.push_back(b + kProfileMin), matte_series.y.push_back(bin.matte / n);
      }
      if (alpha == alphas.front()) profile_series.push_back(std::move(opacity_series));
      if (!rows.empty()) {
        cv::Mat sheet;
        cv::vconcat(rows, sheet);
        cv::imwrite(out + "/" + c.name + "_sheet.png", sheet);
      }
    }
  }
  write_csv(out + "/room_matte.csv",
            {"case",
             "min_alpha",
             "iou",
             "leak",
             "leak_edge",
             "leak_below_chin",
             "leak_other",
             "leak_of_true_matte",
             "face_psnr_db",
             "face_region",
             "views",
             "occupied_cells",
             "steps",
             "train_seconds",
             "leak_excess",
             "leak_excess_edge",
             "leak_excess_far",
             "leak_outline",
             "leak_ring",
             "face_psnr_subject_db",
             "holes",
             "holes_worst_view"},
            csv);
  // Summed over views: leak and leak_excess are the bin's share of the subject's pixels.
  write_csv(
      out + "/room_matte_profile.csv",
      {"case", "min_alpha", "distance_px", "pixels", "mean_opacity", "mean_matte", "leak", "leak_excess"},
      profile_csv);
  if (!profile_series.empty()) {
    profile_series.push_back(matte_series);
    write_chart(out + "/room_matte_profile.png",
                {"opacity across the true matte's outline (held-out views, model as saved)",
                 "px from the outline (< 0: subject; 10: 10 and farther)", "mean opacity"},
                profile_series);
  }
  return 0;
}

int main(int argc, char** argv) {
  // A missing model, dataset or glasses file is a message and exit status 1, not an abort.
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "bench_room_matte: " << e.what() << "\n";
    return 1;
  }
}
