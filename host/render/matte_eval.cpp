// Matte scores of a render against a synthetic capture's truth; see matte_eval.h.
#include "host/render/matte_eval.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "host/render/hole_eval.h"

namespace lorgnette::render {
namespace {

// The face points in front of the camera, projected to pixel coordinates.
std::vector<Eigen::Vector2d> project_face(const Camera& cam, const std::vector<Eigen::Vector3f>& pts) {
  std::vector<Eigen::Vector2d> px;
  for (const auto& p : pts) {
    float u, v;
    if (camera_project(&cam, lgn_vec3(p.x(), p.y(), p.z()), &u, &v) > 0.0f) px.emplace_back(u, v);
  }
  return px;
}

double psnr_of(double squared_error_sum, long pixels) {
  return pixels ? -10.0 * std::log10(std::max(squared_error_sum / (3.0 * double(pixels)), 1e-12)) : 0.0;
}

}  // namespace

void score_face(const Image& pred, const Image& truth, const Image& matte,
                const std::vector<Eigen::Vector2d>& hull_px, MatteScore& s) {
  cv::Mat mask = cv::Mat::zeros(matte.height, matte.width, CV_8U);
  if (hull_px.size() >= 3) {
    std::vector<cv::Point> px, hull;
    for (const auto& p : hull_px) px.emplace_back(int(std::lround(p.x())), int(std::lround(p.y())));
    cv::convexHull(px, hull);
    cv::fillConvexPoly(mask, hull, cv::Scalar(255));
  }
  double se = 0.0, se_in = 0.0;
  long n = 0, n_in = 0;
  for (int y = 0; y < matte.height; ++y)
    for (int x = 0; x < matte.width; ++x) {
      if (!mask.at<uint8_t>(y, x)) continue;
      double px = 0.0;
      for (int c = 0; c < 3; ++c) {
        const double e = linear_to_srgb(pred.at(x, y, c)) - linear_to_srgb(truth.at(x, y, c));
        px += e * e;
      }
      se += px, ++n;
      if (matte.at(x, y, 0) >= 0.999f) se_in += px, ++n_in;
    }
  s.face_pixels = n;
  s.face_psnr = psnr_of(se, n);
  s.face_subject_pixels = n_in;
  s.face_psnr_subject = psnr_of(se_in, n_in);
}

bool judged_pixel(const Camera& camera, const Image& matte, const Image* depth, int x, int y,
                  const nerf::Aabb& box) {
  if (!depth || matte.at(x, y, 0) < 0.5f) return true;
  const float d = depth->at(x, y, 0);
  if (!std::isfinite(d)) return true;
  const LgnVec3 o = camera_origin(&camera), dir = camera_ray_dir(&camera, x + 0.5f, y + 0.5f);
  const float p[3] = {o.x + d * dir.x, o.y + d * dir.y, o.z + d * dir.z};
  for (int k = 0; k < 3; ++k)
    if (!(p[k] >= box.min[k] && p[k] <= box.max[k])) return false;
  return true;
}

MatteScore score_matte(const MatteView& v, const nerf::Aabb& box) {
  const Image& pred = *v.prediction;
  const Image& matte = *v.matte;
  const int w = matte.width, h = matte.height;
  if (pred.width != w || pred.height != h || pred.channels != 4)
    throw std::runtime_error("score_matte: the prediction must be RGBA of the matte's size");
  long inter = 0, uni = 0, subject = 0;
  double leak = 0.0, excess = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float m = matte.at(x, y, 0), a = pred.at(x, y, 3);
      if (!judged_pixel(v.camera, matte, v.depth, x, y, box)) continue;  // subject outside the box
      const bool t = m >= 0.5f, p = a >= 0.5f;
      inter += t && p;
      uni += t || p;
      subject += t;
      leak += double(a) * (1.0 - m);
      excess += std::max(0.0, double(a) - double(m));
    }
  MatteScore s;
  s.iou = uni ? double(inter) / double(uni) : 1.0;
  s.leak = subject ? leak / double(subject) : 0.0;
  s.leak_excess = subject ? excess / double(subject) : 0.0;
  s.subject_pixels = subject;
  s.holes = s.holes_worst = head_interior_holes(pred, matte).share;
  if (!v.face_points.empty() && v.truth)
    score_face(pred, *v.truth, matte, project_face(v.camera, v.face_points), s);
  return s;
}

MatteScore mean_score(const std::vector<MatteScore>& scores) {
  MatteScore m;
  int faces = 0, covered = 0;
  for (const auto& s : scores) {
    m.iou += s.iou / double(scores.size());
    m.leak += s.leak / double(scores.size());
    m.leak_excess += s.leak_excess / double(scores.size());
    m.subject_pixels += s.subject_pixels;
    m.holes += s.holes / double(scores.size());
    m.holes_worst = std::max(m.holes_worst, s.holes_worst);
    if (s.face_pixels) m.face_psnr += s.face_psnr, m.face_pixels += s.face_pixels, ++faces;
    if (s.face_subject_pixels)
      m.face_psnr_subject += s.face_psnr_subject, m.face_subject_pixels += s.face_subject_pixels, ++covered;
  }
  if (faces) m.face_psnr /= faces;
  if (covered) m.face_psnr_subject /= covered;
  return m;
}

}  // namespace lorgnette::render
