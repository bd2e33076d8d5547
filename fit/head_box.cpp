// Head box from posed photos (see head_box.h): detect on an even subset, triangulate, align the mean
// face, place the anthropometric box in the head frame and take its scene-axis bounds.
#include "fit/head_box.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "fit/detect_views.h"
#include "fit/landmark_ids.h"
#include "fit/mean_face.h"

namespace lorgnette::fit {
namespace {

constexpr const char* kWhatToDo =
    "give the box yourself (lorgnette train --aabb minx,miny,minz,maxx,maxy,maxz, or --box cameras), "
    "or capture again with the face visible and unobstructed in more photos";

// The photo shrunk so its longer side is at most max_side; `scale` = original / shrunk pixels.
Image shrink_for_detection(const Image& img, int max_side, double* scale) {
  *scale = 1.0;
  int side = std::max(img.width, img.height);
  if (max_side <= 0 || side <= max_side) return img;
  double s = double(max_side) / side;
  cv::Mat src(img.height, img.width, CV_32FC(img.channels), const_cast<float*>(img.pixels.data()));
  cv::Mat dst;
  cv::resize(
      src, dst,
      cv::Size(std::max(1, int(std::lround(img.width * s))), std::max(1, int(std::lround(img.height * s)))),
      0, 0, cv::INTER_AREA);
  Image out(dst.cols, dst.rows, img.channels);
  std::copy(dst.ptr<float>(), dst.ptr<float>() + out.pixels.size(), out.pixels.begin());
  *scale = double(img.width) / dst.cols;
  return out;
}

// Detects the face of one photo; landmarks in the camera's pixel coordinates.
ViewRecord detect_photo(const PosedPhoto& photo, const LandmarkDetector& det, int max_side) {
  Image loaded;
  const Image* img = photo.image;
  if (!img) {
    if (photo.path.empty()) throw std::runtime_error("head box: a photo has neither an image nor a path");
    loaded = read_image(photo.path);
    img = &loaded;
  }
  if (img->width != int(photo.camera.width) || img->height != int(photo.camera.height))
    throw std::runtime_error(fmt::format("head box: photo '{}' is {}x{} but its camera is {}x{}", photo.path,
                                         img->width, img->height, photo.camera.width, photo.camera.height));
  double scale = 1.0;
  Image small = shrink_for_detection(*img, max_side, &scale);
  ViewRecord v;
  v.camera = photo.camera;
  v.detection = det.detect(small);
  for (auto& p : v.detection.points) p *= scale;  // continuous pixel coordinates scale exactly
  v.detection.box *= scale;
  return v;
}

std::string no_face_message(int tried, int found, int needed) {
  return fmt::format("head box: dlib found a face in {} of the {} photos tried (needs {}): {}", found, tried,
                     needed, kWhatToDo);
}

}  // namespace

std::vector<size_t> even_subset(size_t n, size_t count) {
  std::vector<size_t> out;
  if (n == 0 || count == 0) return out;
  if (count >= n) {
    for (size_t i = 0; i < n; ++i) out.push_back(i);
    return out;
  }
  if (count == 1) return {n / 2};
  for (size_t i = 0; i < count; ++i)
    out.push_back(size_t(std::llround(double(i) * double(n - 1) / double(count - 1))));
  return out;
}

double declared_hair_mm(const HeadExtents& e) { return std::max(0.0, e.hair_mm - HeadExtents{}.hair_mm); }

HeadSpanMm head_box_span_mm(const HeadExtents& e) {
  const double half_x = 0.5 * e.head_breadth_mm + e.side_margin_mm + kSideHairShare * declared_hair_mm(e);
  return {
      {-half_x, -(e.chin_below_eyes_mm + e.neck_mm), -(e.head_length_mm - e.glabella_ahead_mm + e.hair_mm)},
      {half_x, e.vertex_above_eyes_mm + e.hair_mm, e.nose_ahead_mm + e.front_margin_mm}};
}

HeadBox head_box_from_frame(const HeadFrame& head, const Eigen::Vector3d& anchor, const HeadExtents& e) {
  if (!(head.mm_per_unit > 0.0) || !std::isfinite(head.mm_per_unit))
    throw std::runtime_error("head box: the head frame has no valid scale (mm per unit)");
  // Oriented box in head-frame millimetres relative to the anchor (x left, y up, z forward).
  const HeadSpanMm span = head_box_span_mm(e);
  const Eigen::Vector3d &lo = span.lo, &hi = span.hi;
  HeadBox b;
  b.head = head;
  b.axes.col(0) = head.d_eye;
  b.axes.col(1) = head.d_up;
  b.axes.col(2) = head.d_fwd;
  b.half_extent = 0.5 * (hi - lo) / head.mm_per_unit;
  b.anchor = anchor;
  b.extents = e;
  b.center = anchor + b.axes * (0.5 * (hi + lo) / head.mm_per_unit);
  // Scene-axis bounds of the oriented box: |axes| * half extent per axis.
  Eigen::Vector3d r = b.axes.cwiseAbs() * b.half_extent;
  b.min = b.center - r;
  b.max = b.center + r;
  return b;
}

std::string HeadBox::summary() const {
  return fmt::format(
      "head box from dlib landmarks on {} of {} photos ({} landmarks triangulated; {:.1f} mm per unit, PD "
      "{:.1f} mm): [{:.3f} {:.3f} {:.3f}] .. [{:.3f} {:.3f} {:.3f}]",
      faces_found, photos_tried, landmarks_triangulated, head.mm_per_unit, head.pd_mm, min.x(), min.y(),
      min.z(), max.x(), max.y(), max.z());
}

HeadBox estimate_head_box(const std::vector<PosedPhoto>& photos, const HeadBoxOptions& opt) {
  if (photos.empty()) throw std::runtime_error(std::string("head box: no photos given: ") + kWhatToDo);
  if (opt.max_photos < 2 || opt.min_faces < 2)
    throw std::runtime_error("head box: max_photos and min_faces must be at least 2");
  LandmarkDetector detector(opt.detector);
  std::vector<ViewRecord> views;
  int found = 0;
  for (size_t i : even_subset(photos.size(), size_t(opt.max_photos))) {
    views.push_back(detect_photo(photos[i], detector, opt.detect_max_side));
    found += views.back().detection.found;
  }
  const int tried = int(views.size());
  spdlog::info("head box: a face in {} of {} photos", found, tried);
  if (found < opt.min_faces) throw std::runtime_error(no_face_message(tried, found, opt.min_faces));
  std::vector<TriangulatedPoint> pts = triangulate_landmarks(views, opt.triangulate);
  std::vector<Eigen::Vector3d> p;
  std::vector<bool> valid;
  int ok = 0;
  for (const auto& q : pts) p.push_back(q.position), valid.push_back(q.ok), ok += q.ok;
  HeadFrame head;
  try {
    head = estimate_head_frame(p, valid, mean_face_or_builtin(opt.mean_face_path));
  } catch (const std::exception& e) {
    throw std::runtime_error(
        fmt::format("head box: faces in {} of {} photos, but the landmarks do not give a "
                    "head frame ({}): {}",
                    found, tried, e.what(), kWhatToDo));
  }
  // Anchor: the outer-corner midpoint at eye level, at the inner corners' depth. From the triangulated
  // corners: their centroid, moved forward by the mean face's offset between the two depths.
  Face68 mean = mean_face_or_builtin(opt.mean_face_path);
  for (int k : {lm::kEyeOuterR, lm::kEyeInnerR, lm::kEyeInnerL, lm::kEyeOuterL})
    if (!pts[k].ok)
      throw std::runtime_error(
          fmt::format("head box: eye corner landmark {} was not triangulated "
                      "({}): {}",
                      k, pts[k].why, kWhatToDo));
  const double forward_mm = face_anchor(mean).z() - eye_corners_centroid(mean).z();
  Eigen::Vector3d anchor = eye_corners_centroid(p) + head.d_fwd * (forward_mm / head.mm_per_unit);
  HeadBox box = head_box_from_frame(head, anchor, opt.extents);
  box.photos_tried = tried;
  box.faces_found = found;
  box.landmarks_triangulated = ok;
  box.landmarks = p;
  box.landmark_ok = valid;
  if (!box.min.allFinite() || !box.max.allFinite())
    throw std::runtime_error(std::string("head box: the landmarks gave a non-finite box: ") + kWhatToDo);
  return box;
}

}  // namespace lorgnette::fit
