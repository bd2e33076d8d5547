// Rendering and landmark detection of a set of views, and triangulation of their landmarks (see
// detect_views.h).
#include "fit/detect_views.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <stdexcept>

#include "fit/landmark_ids.h"

namespace lorgnette::fit {

namespace {

// The centred part of a view that render_cropped renders: [x0, x0 + w) x [y0, y0 + h).
struct CropRect {
  int x0 = 0, y0 = 0, w = 0, h = 0;
};

CropRect crop_rect(const Camera& cam, double keep) {
  CropRect r;
  r.w = std::clamp(int(std::lround(keep * cam.width)), 1, int(cam.width));
  r.h = std::clamp(int(std::lround(keep * cam.height)), 1, int(cam.height));
  r.x0 = (int(cam.width) - r.w) / 2, r.y0 = (int(cam.height) - r.h) / 2;
  return r;
}

bool cropping(double keep) { return keep > 0.0 && keep < 1.0; }

// True when the face was not found in a cropped view or reaches within a HOG cell (8 px) of the
// crop's edge: the crop may have changed what the detector saw, so the view is redone in full.
bool needs_full_view(const FaceDetection& d, const CropRect& r) {
  if (!d.found) return true;
  const double m = 8.0;
  auto inside = [&](double x, double y) {
    return x >= r.x0 + m && x <= r.x0 + r.w - m && y >= r.y0 + m && y <= r.y0 + r.h - m;
  };
  if (!inside(d.box[0], d.box[1]) || !inside(d.box[2], d.box[3])) return true;
  for (const auto& p : d.points)
    if (!inside(p.x(), p.y())) return true;
  return false;
}

}  // namespace

Image render_cropped(ViewSource& source, const Camera& cam, double keep) {
  if (!cropping(keep)) return source.render(cam);
  if (cam.k1 != 0.0f || cam.k2 != 0.0f || cam.p1 != 0.0f || cam.p2 != 0.0f)
    throw std::runtime_error(
        "render_cropped: the camera has lens distortion; render the whole view (crop 0)");
  const int w = int(cam.width), h = int(cam.height);
  const CropRect r = crop_rect(cam, keep);
  const int cw = r.w, ch = r.h, x0 = r.x0, y0 = r.y0;
  Camera sub = cam;
  sub.width = lgn_uint(cw), sub.height = lgn_uint(ch);
  sub.cx -= float(x0), sub.cy -= float(y0);
  Image part = source.render(sub);
  const int nc = part.channels;
  Image full(w, h, nc, 1.0f);
  if (nc == 4)
    for (size_t i = 0; i < size_t(w) * h; ++i) full.pixels[i * 4 + 3] = 0.0f;
  for (int y = 0; y < ch; ++y)
    std::copy_n(&part.pixels[size_t(y) * cw * nc], size_t(cw) * nc,
                &full.pixels[(size_t(y + y0) * w + x0) * nc]);
  return full;
}

std::vector<ViewRecord> detect_views(ViewSource& source, const LandmarkDetector& detector,
                                     const std::vector<Camera>& cameras, const ViewDetectOptions& opt) {
  std::vector<ViewRecord> out(cameras.size());
  // The cap's views are framed on the face (front search): its expected width lets the detector
  // run its HOG stage on a smaller image (DetectorOptions::hog_face_px).
  auto detect = [&](size_t i, Image img) {
    out[i].detection = detector.detect(img, opt.face_fraction * cameras[i].width);
    if (opt.keep_images) out[i].image = std::move(img);
  };
  // One detection in flight at most (the detector is not thread-safe); the future's destructor
  // waits for it when rendering throws.
  std::future<void> pending;
  for (size_t i = 0; i < cameras.size(); ++i) {
    out[i].camera = cameras[i];
    Image img = render_cropped(source, cameras[i], opt.detector.render_crop);
    if (!opt.detector.overlap_render) {
      detect(i, std::move(img));
      continue;
    }
    if (pending.valid()) pending.get();
    pending = std::async(std::launch::async, detect, i, std::move(img));
  }
  if (pending.valid()) pending.get();
  // Cropped views where the face is missing or touches the crop: redone in full (rare by design).
  const double keep = opt.detector.render_crop;
  for (size_t i = 0; i < cameras.size() && cropping(keep); ++i)
    if (needs_full_view(out[i].detection, crop_rect(cameras[i], keep))) detect(i, source.render(cameras[i]));
  return out;
}

std::vector<TriangulatedPoint> triangulate_landmarks(const std::vector<ViewRecord>& views,
                                                     const TriangulateOptions& options) {
  std::vector<TriangulatedPoint> pts(lm::kCount);
  std::vector<int> view_of;  // observation -> view index (views without a face give none)
  for (size_t i = 0; i < views.size(); ++i)
    if (views[i].detection.found) view_of.push_back(int(i));
  for (int k = 0; k < lm::kCount; ++k) {
    std::vector<Observation> obs;
    for (int i : view_of) obs.push_back({&views[i].camera, views[i].detection.points[k]});
    pts[k] = triangulate_point(obs, options);
    // Inliers and residuals by view, as the surface casts keep them (surface_landmarks.h).
    std::vector<double> px(views.size(), -1.0);
    for (size_t o = 0; o < obs.size() && o < pts[k].reprojection_px.size(); ++o)
      px[view_of[o]] = pts[k].reprojection_px[o];
    pts[k].reprojection_px = std::move(px);
    for (int& o : pts[k].inliers) o = view_of[o];
  }
  return pts;
}

}  // namespace lorgnette::fit
