// The subject's skin colours from its training photos (see skin_colours.h).
#include "capture/skin_colours.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "capture/face_hull.h"
#include "fit/camera_math.h"
#include "kernels/train/train_types.h"

namespace lorgnette::capture {
namespace {

using Rgb = std::array<float, 3>;

// A sampled region's point on the face (scene), from the triangulated landmarks (ibug 68): each
// cheek midway between the lower eyelid and the mouth's corner, 10 mm further out (beside the
// nose's wing, on the cheek's flat), and the chin 15 mm below the lower lip's middle (above the
// chin's point, whose landmark is the outline's, not the skin's). None when a landmark is missing.
std::optional<Eigen::Vector3d> region_point(const fit::HeadBox& box, int region) {
  const auto ok = [&](std::initializer_list<int> ids) {
    for (int i : ids)
      if (i >= int(box.landmarks.size()) || i >= int(box.landmark_ok.size()) || !box.landmark_ok[i])
        return false;
    return true;
  };
  const double mm = box.head.mm_per_unit > 0.0 ? 1.0 / box.head.mm_per_unit : 0.0;
  const Eigen::Vector3d left = box.axes.col(0), up = box.axes.col(1);
  const auto& L = box.landmarks;
  if (region == 2) {
    if (!ok({57})) return std::nullopt;
    return Eigen::Vector3d(L[57] - 15.0 * mm * up);
  }
  const int lid_a = region == 0 ? 40 : 46, lid_b = region == 0 ? 41 : 47, corner = region == 0 ? 48 : 54;
  if (!ok({lid_a, lid_b, corner, 27})) return std::nullopt;
  const Eigen::Vector3d p = 0.25 * (L[lid_a] + L[lid_b]) + 0.5 * L[corner];
  const double side = (p - L[27]).dot(left) >= 0.0 ? 1.0 : -1.0;  // 27: the nose's bridge, mid face
  return Eigen::Vector3d(p + side * 10.0 * mm * left);
}

// The points beside the neck (scene) where SkinChroma::beside_neck is sampled: both sides of the
// neck's base (head_neck_base), at each of the options' distances out and heights above it.
std::vector<std::optional<Eigen::Vector3d>> beside_neck_points(const fit::HeadBox& box,
                                                               const SkinSampleOptions& o) {
  const nerf::SubjectAxis base = head_neck_base(box);
  const Eigen::Vector3d at(base.point[0], base.point[1], base.point[2]),
      up(base.up[0], base.up[1], base.up[2]);
  const Eigen::Vector3d left = box.axes.col(0).normalized();
  const double unit = 1.0 / box.head.mm_per_unit;
  std::vector<std::optional<Eigen::Vector3d>> points;
  for (double side : {-1.0, 1.0})
    for (double out : o.beside_neck_out_mm)
      for (double above : o.beside_neck_up_mm)
        points.push_back(Eigen::Vector3d(at + (side * out * left + above * up) * unit));
  return points;
}

// The median colour (per channel) of the patch of `radius` px about (u, v); none when it leaves the image.
std::optional<Rgb> patch_median(const Image& img, double u, double v, int radius) {
  const int cx = int(std::floor(u)), cy = int(std::floor(v));
  if (img.channels < 3 || cx - radius < 0 || cy - radius < 0 || cx + radius >= img.width ||
      cy + radius >= img.height)
    return std::nullopt;
  Rgb out{};
  std::vector<float> values;
  for (int c = 0; c < 3; ++c) {
    values.clear();
    for (int y = cy - radius; y <= cy + radius; ++y)
      for (int x = cx - radius; x <= cx + radius; ++x) values.push_back(img.at(x, y, c));
    std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
    out[c] = values[values.size() / 2];
  }
  return out;
}

std::array<float, 2> chromaticity(const Rgb& c) {
  const float sum = std::max(c[0] + c[1] + c[2], 1e-6f);
  return {c[0] / sum, c[1] / sum};
}

float luminance(const Rgb& c) { return 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2]; }

// Every region's samples in one photo (appended to samples[region]) when it sees the face within the
// options' angle of its front.
void sample_photo(const fit::HeadBox& box, const fit::PosedPhoto& photo, const SkinSampleOptions& o,
                  const std::vector<std::optional<Eigen::Vector3d>>& points,
                  std::vector<std::vector<Rgb>>& samples) {
  const Eigen::Vector3d to_cam = (fit::camera_center(photo.camera) - box.anchor).normalized();
  if (to_cam.dot(box.axes.col(2)) < std::cos(o.max_view_angle_deg * M_PI / 180.0)) return;
  Image loaded;
  const Image* img = photo.image;
  if (!img) loaded = read_image(photo.path), img = &loaded;
  for (size_t r = 0; r < points.size(); ++r) {
    Eigen::Vector2d uv;
    if (!points[r] || !fit::camera_project(photo.camera, *points[r], &uv)) continue;
    const double depth =
        (*points[r] - fit::camera_center(photo.camera)).dot(fit::camera_forward(photo.camera));
    const double radius_px =
        photo.camera.fx * o.patch_radius_mm / box.head.mm_per_unit / std::max(depth, 1e-9);
    if (auto c = patch_median(*img, uv.x(), uv.y(), std::max(1, int(std::lround(radius_px)))))
      samples[r].push_back(*c);
  }
}

float nearest(const std::vector<std::array<float, 2>>& refs, const std::array<float, 2>& c) {
  float best = 1e30f;
  for (const auto& r : refs) best = std::min(best, std::hypot(c[0] - r[0], c[1] - r[1]));
  return best;
}

float median_of(std::vector<float> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Whether each sample lies within max(min_cut, 4 x their median distance) of their median
// chromaticity: a patch that missed the skin (an eye, a lip, the room behind a landmark misplaced in
// one photo) lies far from the rest, while a face's own skin varies by about 0.03 (a cheek's blush
// against the chin).
std::vector<bool> skin_majority(const std::vector<std::array<float, 2>>& samples, float min_cut) {
  std::array<float, 2> median{};
  for (int c = 0; c < 2; ++c) {
    std::vector<float> v;
    for (const auto& s : samples) v.push_back(s[c]);
    median[c] = median_of(v);
  }
  std::vector<float> d;
  for (const auto& s : samples) d.push_back(nearest({median}, s));
  const float cut = std::max(min_cut, 4.0f * median_of(d));
  std::vector<bool> out;
  for (float x : d) out.push_back(x <= cut);
  return out;
}

// At most `count` of the samples' chromaticities, the first sample and then each time the one
// farthest from those chosen, so every sample lies near one: a face's chromaticity varies by region
// and view (a cheek's blush, the chin's shade) more than one mean says.
std::vector<std::array<float, 2>> farthest_first(const std::vector<std::array<float, 2>>& samples,
                                                 size_t count) {
  std::vector<std::array<float, 2>> refs{samples[0]};
  while (refs.size() < count) {
    size_t far = 0;
    for (size_t k = 1; k < samples.size(); ++k)
      if (nearest(refs, samples[k]) > nearest(refs, samples[far])) far = k;
    if (!(nearest(refs, samples[far]) > 0.0f)) break;
    refs.push_back(samples[far]);
  }
  return refs;
}

}  // namespace

nerf::SkinChroma skin_colours(const fit::HeadBox& box, const std::vector<fit::PosedPhoto>& photos,
                              const SkinSampleOptions& options) {
  nerf::SkinChroma skin;
  if (box.landmarks.empty() || !(box.head.mm_per_unit > 0.0)) return skin;
  std::vector<std::optional<Eigen::Vector3d>> points;
  for (int r = 0; r < 3; ++r) points.push_back(region_point(box, r));
  const size_t face_regions = points.size();
  for (const auto& p : beside_neck_points(box, options)) points.push_back(p);
  std::vector<std::vector<Rgb>> by_region(points.size());
  for (const fit::PosedPhoto& photo : photos) sample_photo(box, photo, options, points, by_region);
  std::vector<Rgb> all;
  for (size_t r = 0; r < face_regions; ++r) all.insert(all.end(), by_region[r].begin(), by_region[r].end());
  if (all.size() < size_t(std::max(1, options.min_samples))) return skin;
  std::vector<std::array<float, 2>> chroma;
  for (const Rgb& x : all) chroma.push_back(chromaticity(x));
  const std::vector<bool> kept = skin_majority(chroma, float(options.outlier_cut));
  std::vector<std::array<float, 2>> skin_chroma;
  float darkest = 1e30f;
  for (size_t k = 0; k < all.size(); ++k)
    if (kept[k]) skin_chroma.push_back(chroma[k]), darkest = std::min(darkest, luminance(all[k]));
  chroma = std::move(skin_chroma);
  skin.chroma = farthest_first(chroma, SKIN_REFS_MAX);
  skin.spread = 0.0f;
  for (const auto& c : chroma) skin.spread = std::max(skin.spread, nearest(skin.chroma, c));
  skin.lum_floor = float(options.dark_share) * darkest;
  for (size_t r = face_regions; r < by_region.size(); ++r)
    skin.beside_neck.insert(skin.beside_neck.end(), by_region[r].begin(), by_region[r].end());
  return skin;
}

}  // namespace lorgnette::capture
