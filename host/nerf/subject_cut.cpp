// The seen opacity in a zone, marched on the host (the few rays of a check do not need the marcher's
// kernels); the densities come in batches from the field.
#include "host/nerf/subject_cut.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "host/field/density_at.h"
#include "kernels/march/march_math.h"

namespace lorgnette::nerf {
namespace {
constexpr size_t kCheckViews = 12;
constexpr uint32_t kCheckRays = 64;
}  // namespace

SeenOpacity seen_opacity(const std::vector<Camera>& cameras, const Aabb& box, const SceneNormalisation& norm,
                         float step, const OccupancyGrid& occ, uint32_t stride, const DensityAt& density,
                         int zones, const std::function<int(const Vec3f&)>& zone_of) {
  SeenOpacity seen;
  seen.in_zone.assign(size_t(std::max(zones, 0)), 0.0);
  if (stride == 0 || !(step > 0.0f) || occ.res == 0) return seen;
  struct Sample {
    uint32_t ray;
    int zone;
  };
  for (const Camera& cam : cameras) {
    const uint32_t w = cam.width / stride, h = cam.height / stride;
    std::vector<Sample> samples;
    std::vector<Vec3f> points;
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x) {
        const LgnVec3 o0 = camera_origin(&cam),
                      d = camera_ray_dir(&cam, (x + 0.5f) * stride, (y + 0.5f) * stride);
        const float dir[3] = {d.x, d.y, d.z};
        const float o[3] = {o0.x * norm.scale + norm.offset[0], o0.y * norm.scale + norm.offset[1],
                            o0.z * norm.scale + norm.offset[2]};
        float t0 = 0.0f, t1 = 0.0f;
        if (!march_clip_aabb(box.min.data(), box.max.data(), o[0], o[1], o[2], dir[0], dir[1], dir[2], &t0,
                             &t1))
          continue;
        for (float t = t0 + 0.5f * step; t < t1; t += step) {
          Vec3f q, scene;
          for (int a = 0; a < 3; ++a) {
            const float p = o[a] + t * dir[a];
            q[a] = (p - box.min[a]) / box.extent(a);
            scene[a] = (p - norm.offset[a]) / norm.scale;
          }
          if (!occ_test(occ.bits.data(), occ.res, q[0], q[1], q[2])) continue;
          const int zone = zone_of(scene);
          samples.push_back({y * w + x, zone >= 1 && zone <= zones ? zone : 0});
          points.push_back(q);
        }
      }
    std::vector<float> sigma;
    if (!points.empty()) density(points, sigma);
    std::vector<float> T(size_t(w) * h, 1.0f);
    for (size_t i = 0; i < samples.size(); ++i) {  // in ray order, near to far
      const float s = std::isfinite(sigma[i]) ? std::max(sigma[i], 0.0f) : 0.0f;
      const float a = 1.0f - std::exp(-s * step);
      const double wgt = double(T[samples[i].ray]) * a;
      seen.total += wgt;
      if (samples[i].zone) seen.in_zone[size_t(samples[i].zone - 1)] += wgt;
      T[samples[i].ray] *= 1.0f - a;
    }
    seen.rays += size_t(w) * h;
  }
  return seen;
}

std::string SubjectCutReport::summary() const {
  if (!checked) return "subject volume's edge: not checked";
  return fmt::format(
      "subject volume's edge: {:.3f} % of the opacity the views see lies in its rim above and behind "
      "the head, {:.3f} % at its sides ({} the {:.1f} % that warns)",
      100.0 * rim_share, 100.0 * sides_share, cut() ? "over" : "under", 100.0 * kSubjectCutShare);
}

std::string SubjectCutReport::advice() const {
  if (!cut()) return "";
  std::string where;
  if (rim_share >= kSubjectCutShare)
    where = fmt::format(
        "above or behind the head ({:.2f} % of what the views see lies in the volume's outer 6 mm there)",
        100.0 * rim_share);
  if (sides_share >= kSubjectCutShare)
    where += fmt::format("{}at its sides above the ears ({:.2f} %)", where.empty() ? "" : " and ",
                         100.0 * sides_share);
  return "the head's volume cut the subject " + where +
         ": a hat, a bun or hair that stands out further than the volume allows is cut flat. Train again "
         "with a larger hair allowance to keep it (`lorgnette train ... --hair 100`, up to 300 mm: it raises "
         "the volume's top and back by that much and widens its sides by half as much beyond the standard "
         "30 mm; the renders show how much is cut)";
}

SubjectCutReport check_subject_cut(NerfModel& model, const std::vector<Camera>& cameras,
                                   const SubjectRim& rim) {
  SubjectCutReport r;
  if (rim.empty() || cameras.empty()) return r;
  DensityAt density = [&](const std::vector<Vec3f>& points, std::vector<float>& sigma) {
    sigma = field::density_at(model.field(), model.runtime(), points);
  };
  // At most kCheckViews views, evenly spread over the capture, and about kCheckRays rays across each
  // view's longer side: about a second on two CPU cores.
  std::vector<Camera> picked;
  const size_t n = std::min(cameras.size(), kCheckViews);
  for (size_t i = 0; i < n; ++i) picked.push_back(cameras[i * cameras.size() / n]);
  const uint32_t longest = std::max(picked.front().width, picked.front().height);
  const uint32_t stride = std::max(1u, longest / kCheckRays);
  const SeenOpacity seen =
      seen_opacity(picked, model.aabb(), model.normalisation, model.step(), model.occupancy(), stride,
                   density, 2, [&](const Vec3f& p) { return rim.zone(p); });
  r.checked = seen.total > 0.0;
  r.rim_share = seen.share(1);
  r.sides_share = seen.share(2);
  return r;
}

}  // namespace lorgnette::nerf
