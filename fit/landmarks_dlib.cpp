// dlib adapter (see landmarks_dlib.h). The only translation unit that includes dlib.
#include "fit/landmarks_dlib.h"

#include <dlib/image_processing.h>
#include <dlib/image_processing/frontal_face_detector.h>
#include <dlib/image_transforms.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

namespace lorgnette::fit {

struct LandmarkDetector::Impl {
  dlib::frontal_face_detector detector = dlib::get_frontal_face_detector();
  dlib::shape_predictor predictor;
  int upsample = 0;
  double hog_face_px = 0.0;

  // Face boxes of the HOG detector on `img`, run at about `hog_scale` and mapped back to img's
  // pixels. The shrink is k steps of the detector's own pyramid (pyramid_down<6>, 5/6 per step), k
  // the most that keeps the scale >= hog_scale: the detector's pyramid on the shrunk image is then
  // exactly the full image's pyramid from level k on, so a face found at a level >= k gets the same
  // box (to a pixel of rounding) while the k finest levels, the costly ones, are never scanned.
  std::vector<dlib::rect_detection> faces(const dlib::array2d<dlib::rgb_pixel>& img, double hog_scale) {
    std::vector<dlib::rect_detection> dets;
    const int k = hog_scale < 1.0 ? int(std::floor(std::log(hog_scale) / std::log(5.0 / 6.0) + 1e-9)) : 0;
    if (k <= 0) {
      detector(img, dets, 0.0);
      return dets;
    }
    dlib::pyramid_down<6> pyr;
    dlib::array2d<dlib::rgb_pixel> small, tmp;
    pyr(img, small);
    for (int i = 1; i < k; ++i) {
      pyr(small, tmp);
      dlib::swap(small, tmp);
    }
    detector(small, dets, 0.0);
    for (auto& d : dets) d.rect = box_up(d.rect, k);
    return dets;
  }

  // Maps a box found on the image shrunk by k pyramid steps to the full image exactly as the
  // detector maps its own boxes: it found the integer window R at pyramid level m (its box is
  // round(rect_up(R, m))); R and m are recovered (the window is W0 wide at level 0) and mapped up
  // by m + k levels in one go, as a full-resolution run would. Falls back to a plain map.
  dlib::rectangle box_up(const dlib::rectangle& box, int k) {
    dlib::pyramid_down<6> pyr;
    if (window0 == 0)  // the smallest box the scanner reports (its level-0 window), away from the border
      window0 = detector.get_scanner()
                    .get_best_matching_rect(dlib::centered_rect(dlib::point(1000, 1000), 1, 1))
                    .width();
    int best = -1;
    double best_err = 1e9;
    for (int m = 0; m < 40; ++m) {
      double err = std::abs(pyr.rect_down(dlib::drectangle(box), unsigned(m)).width() - double(window0));
      if (err < best_err) best_err = err, best = m;
    }
    const dlib::rectangle r = pyr.rect_down(dlib::drectangle(box), unsigned(best));
    if (dlib::rectangle(pyr.rect_up(dlib::drectangle(r), unsigned(best))) == box)
      return pyr.rect_up(dlib::drectangle(r), unsigned(best + k));
    return pyr.rect_up(dlib::drectangle(box), unsigned(k));
  }
  unsigned long window0 = 0;  // width of the detector's window at pyramid level 0 (pixels)
};

LandmarkDetector::LandmarkDetector(const DetectorOptions& opt) : impl_(std::make_unique<Impl>()) {
  if (!std::filesystem::is_regular_file(opt.model_path))
    throw std::runtime_error(
        fmt::format("dlib landmark model '{}' not found: install the Debian package libdlib-data "
                    "(apt-get install libdlib-data) or pass its path",
                    opt.model_path));
  try {
    dlib::deserialize(opt.model_path) >> impl_->predictor;
  } catch (const std::exception& e) {
    throw std::runtime_error(
        fmt::format("cannot read the dlib landmark model '{}': {}", opt.model_path, e.what()));
  }
  if (impl_->predictor.num_parts() != 68)
    throw std::runtime_error(fmt::format("'{}' predicts {} points, expected the 68-point model",
                                         opt.model_path, impl_->predictor.num_parts()));
  if (opt.upsample < 0 || opt.upsample > 3) throw std::runtime_error("detector upsample must be 0..3");
  if (opt.hog_face_px != 0.0 && !(opt.hog_face_px >= 80.0))
    throw std::runtime_error(fmt::format(
        "detector hog_face_px must be 0 (off) or >= 80 (dlib's window), got {}", opt.hog_face_px));
  impl_->upsample = opt.upsample;
  impl_->hog_face_px = opt.hog_face_px;
}

LandmarkDetector::LandmarkDetector(DetectFn fn) : fn_(std::move(fn)) {
  if (!fn_) throw std::invalid_argument("LandmarkDetector: empty detector function");
}

LandmarkDetector::~LandmarkDetector() = default;

std::vector<unsigned char> to_srgb8(const Image& img, float background) {
  if (img.channels < 1) throw std::runtime_error("to_srgb8: empty image");
  std::vector<unsigned char> out(size_t(img.width) * img.height * 3);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      for (int c = 0; c < 3; ++c) {
        float v = img.at(x, y, std::min(c, std::min(img.channels - 1, 2)));
        if (img.channels == 4) {
          float a = img.at(x, y, 3);
          v = v + (1.0f - a) * background;  // premultiplied-style composite over the background
        }
        float s = linear_to_srgb(std::clamp(v, 0.0f, 1.0f));
        out[(size_t(y) * img.width + x) * 3 + c] = static_cast<unsigned char>(std::lround(s * 255.0f));
      }
  return out;
}

FaceDetection LandmarkDetector::detect(const Image& image, double face_px) const {
  std::vector<unsigned char> rgb = to_srgb8(image);
  if (!fn_) return detect_srgb8(rgb.data(), image.width, image.height, face_px);
  FaceDetection d = fn_(rgb, image.width, image.height, face_px);
  if (d.found && d.points.size() != 68)
    throw std::runtime_error(
        fmt::format("the landmark detector returned {} points, expected 68 in iBUG order", d.points.size()));
  return d;
}

FaceDetection LandmarkDetector::detect_srgb8(const unsigned char* rgb, int width, int height,
                                             double face_px) const {
  if (!impl_) throw std::logic_error("detect_srgb8: this detector wraps a caller's function, not dlib");
  dlib::array2d<dlib::rgb_pixel> img(height, width);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const unsigned char* p = &rgb[(size_t(y) * width + x) * 3];
      img[y][x] = dlib::rgb_pixel(p[0], p[1], p[2]);
    }
  double factor = 1.0;
  for (int i = 0; i < impl_->upsample; ++i) {
    dlib::pyramid_up(img);
    factor *= 2.0;
  }
  // The face's expected width at the detector's scale (after up-sampling) sets the HOG resize.
  const double hog_scale =
      impl_->hog_face_px > 0.0 && face_px > 0.0 ? impl_->hog_face_px / (face_px * factor) : 1.0;
  std::vector<dlib::rect_detection> dets = impl_->faces(img, hog_scale);
  FaceDetection out;
  out.faces = int(dets.size());
  if (dets.empty()) return out;
  auto best = std::max_element(dets.begin(), dets.end(),
                               [](const auto& a, const auto& b) { return a.rect.area() < b.rect.area(); });
  dlib::full_object_detection shape = impl_->predictor(img, best->rect);
  const dlib::rectangle r = best->rect;
  out.found = shape.num_parts() == 68;
  out.score = best->detection_confidence;
  // dlib's integer pixel (i, j) is the pixel centre: continuous coordinate i + 0.5 at our scale.
  out.box = Eigen::Vector4d(r.left(), r.top(), r.right() + 1, r.bottom() + 1) / factor;
  for (unsigned i = 0; i < shape.num_parts(); ++i)
    out.points.emplace_back((shape.part(i).x() + 0.5) / factor, (shape.part(i).y() + 0.5) / factor);
  return out;
}

}  // namespace lorgnette::fit
