// region_psnr: PSNR of `lorgnette eval` outputs restricted to the head region (or the face), for comparing
// models of one capture trained in different boxes or with different poses. A model trained in a head box
// renders nothing outside it, so whole-image PSNR mostly scores the room; here a pixel counts when
// its ray (through the holdout camera of each --mask dataset, distortion included) meets that
// dataset's box in every mask, i.e. the intersection of the boxes' footprints. Frames are matched by
// holdout order (the datasets must list the same images). Reads the prediction|truth|error PNGs that
// `lorgnette eval -o DIR` writes; prints and writes CSV (per model: full and region PSNR, mask share).
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "fit/camera_math.h"
#include "fit/landmarks_dlib.h"
#include "host/dataset/dataset.h"
#include "host/util/chart.h"

namespace fs = std::filesystem;
using namespace lorgnette;

namespace {

struct MaskSpec {
  std::vector<Camera> holdout;
  Eigen::Vector3d lo, hi;
};

// "DATASET@minx,miny,minz,maxx,maxy,maxz"
MaskSpec parse_mask(const std::string& arg) {
  auto at = arg.find('@');
  if (at == std::string::npos) throw std::runtime_error("--mask needs DATASET@minx,miny,minz,maxx,maxy,maxz");
  MaskSpec m;
  dataset::LoadOptions lo;
  lo.load_images = false;
  lo.splits = {dataset::Split::Holdout};
  dataset::Dataset ds = dataset::load_dataset(arg.substr(0, at), lo);
  for (const auto* f : ds.split(dataset::Split::Holdout)) m.holdout.push_back(f->camera);
  std::stringstream ss(arg.substr(at + 1));
  double v[6];
  char c;
  for (int i = 0; i < 6; ++i) {
    if (!(ss >> v[i])) throw std::runtime_error("--mask: six box numbers expected after '@'");
    if (i < 5) ss >> c;
  }
  m.lo = {v[0], v[1], v[2]}, m.hi = {v[3], v[4], v[5]};
  return m;
}

bool ray_hits_box(const fit::Ray& r, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  double t0 = 0.0, t1 = 1e30;
  for (int a = 0; a < 3; ++a) {
    double inv = 1.0 / r.dir[a];
    double ta = (lo[a] - r.origin[a]) * inv, tb = (hi[a] - r.origin[a]) * inv;
    t0 = std::max(t0, std::min(ta, tb)), t1 = std::min(t1, std::max(ta, tb));
  }
  return t0 <= t1;
}

cv::Mat region_mask(const std::vector<MaskSpec>& masks, size_t frame, int w, int h) {
  cv::Mat m(h, w, CV_8U, cv::Scalar(1));
  for (const auto& s : masks) {
    if (frame >= s.holdout.size())
      throw std::runtime_error("a --mask dataset has fewer holdout frames than the eval");
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        if (!ray_hits_box(fit::camera_ray(s.holdout[frame], {x + 0.5, y + 0.5}), s.lo, s.hi))
          m.at<uint8_t>(y, x) = 0;
  }
  return m;
}

// With --face: the mask also keeps only the convex hull of dlib's 68 landmarks on the truth photo
// (the face from jaw to brows: the part the try-on shows). Empty when no face is found.
// erode_px > 0 shrinks the hull by that many pixels: dlib's jaw contour lies on the silhouette, so
// the hull's rim holds background pixels, which score the room behind the face instead of the face.
void restrict_to_face(const cv::Mat& trip, const fit::LandmarkDetector& det, int erode_px, cv::Mat& mask) {
  int w = trip.cols / 3;
  cv::Mat truth = trip(cv::Rect(w, 0, w, trip.rows));
  Image img(w, trip.rows, 3);
  for (int y = 0; y < trip.rows; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = srgb_to_linear(truth.at<cv::Vec3b>(y, x)[2 - c] / 255.0f);
  fit::FaceDetection d = det.detect(img);
  cv::Mat face(mask.size(), CV_8U, cv::Scalar(0));
  if (d.found) {
    std::vector<cv::Point> pts, hull;
    for (const auto& p : d.points)
      pts.emplace_back(int(std::lround(p.x() - 0.5)), int(std::lround(p.y() - 0.5)));
    cv::convexHull(pts, hull);
    cv::fillConvexPoly(face, hull, cv::Scalar(1));
  }
  if (erode_px > 0)
    cv::erode(face, face,
              cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * erode_px + 1, 2 * erode_px + 1)));
  mask &= face;
}

// Squared-error sums over sRGB [0,1] RGB of the whole image and of the masked region.
void accumulate(const cv::Mat& trip, const cv::Mat& mask, double* se_all, double* n_all, double* se_in,
                double* n_in) {
  int w = trip.cols / 3;
  for (int y = 0; y < trip.rows; ++y)
    for (int x = 0; x < w; ++x) {
      cv::Vec3b p = trip.at<cv::Vec3b>(y, x), t = trip.at<cv::Vec3b>(y, x + w);
      double se = 0;
      for (int c = 0; c < 3; ++c) se += std::pow((p[c] - t[c]) / 255.0, 2);
      *se_all += se, *n_all += 3;
      if (mask.at<uint8_t>(y, x)) *se_in += se, *n_in += 3;
    }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"PSNR of eval outputs inside the head boxes' footprint"};
  std::vector<std::string> mask_args, evals;
  std::string csv;
  bool face = false, per_view = false;
  int erode_px = 0;
  std::string mask_dir;
  app.add_option("--mask", mask_args, "DATASET@minx,miny,minz,maxx,maxy,maxz (repeatable; intersected)")
      ->required();
  app.add_option("--eval", evals, "NAME=EVAL_DIR from lorgnette eval -o (repeatable)")->required();
  app.add_option("--csv", csv, "CSV file to write");
  app.add_flag("--face", face, "also restrict to the landmark hull of the face on the truth photo");
  app.add_option("--erode", erode_px, "with --face: shrink the face hull by this many pixels (default 0)")
      ->check(CLI::Range(0, 200));
  app.add_flag("--per-view", per_view, "print each view's region PSNR");
  app.add_option("--mask-dir", mask_dir, "write each view's region as NAME_<view>_region.png here");
  CLI11_PARSE(app, argc, argv);
  try {
    std::vector<MaskSpec> masks;
    for (const auto& a : mask_args) masks.push_back(parse_mask(a));
    std::vector<std::vector<std::string>> rows;
    std::unique_ptr<fit::LandmarkDetector> det;
    if (face) det = std::make_unique<fit::LandmarkDetector>();
    for (const auto& e : evals) {
      auto eq = e.find('=');
      std::string name = e.substr(0, eq), dir = e.substr(eq + 1);
      // Mean over views of each view's PSNR (as lorgnette eval reports it).
      double full = 0, region = 0, n_all = 0, n_in = 0;
      size_t k = 0;
      for (;; ++k) {
        fs::path p = fs::path(dir) / fmt::format("{:03d}_pred_truth_error.png", k);
        if (!fs::exists(p)) break;
        cv::Mat trip = cv::imread(p.string(), cv::IMREAD_COLOR);
        cv::Mat mask = region_mask(masks, k, trip.cols / 3, trip.rows);
        if (det) restrict_to_face(trip, *det, erode_px, mask);
        double sa = 0, na = 0, si = 0, ni = 0;
        accumulate(trip, mask, &sa, &na, &si, &ni);
        if (ni == 0)
          throw std::runtime_error(fmt::format("view {} of '{}' has an empty head region", k, dir));
        full += -10 * std::log10(sa / na), region += -10 * std::log10(si / ni), n_all += na, n_in += ni;
        if (per_view)
          std::cout << fmt::format("{:<20} view {:3d}: region {:.2f} dB ({:.0f} pixels)\n", name, k,
                                   -10 * std::log10(si / ni), ni / 3);
        if (!mask_dir.empty())
          cv::imwrite((fs::path(mask_dir) / fmt::format("{}_{:03d}_region.png", name, k)).string(),
                      mask * 255);
      }
      if (k == 0) throw std::runtime_error("no eval images in '" + dir + "'");
      full /= double(k), region /= double(k);
      std::cout << fmt::format(
          "{:<20} {} views: PSNR full {:.2f} dB, head region {:.2f} dB ({:.0f}% of pixels)\n", name, k, full,
          region, 100 * n_in / n_all);
      rows.push_back({name, std::to_string(k), fmt::format("{:.3f}", full), fmt::format("{:.3f}", region),
                      fmt::format("{:.3f}", n_in / n_all)});
    }
    if (!csv.empty())
      write_csv(csv, {"model", "views", "psnr_full_db", "psnr_head_region_db", "region_fraction"}, rows);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
