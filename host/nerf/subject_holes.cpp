// Holes in the trained subject, marched on the host as the subject cut check does (subject_cut.cpp);
// see subject_holes.h.
#include "host/nerf/subject_holes.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "host/field/density_at.h"
#include "kernels/march/march_math.h"

namespace lorgnette::nerf {
namespace {

struct HullRay {
  float x = 0.0f, y = 0.0f;  // pixel
  size_t hull = 0;
};

bool faces_camera(const SolidHull& h, const Camera& cam) {
  if (h.points.empty()) return false;
  Vec3f c{0.0f, 0.0f, 0.0f};
  for (const Vec3f& p : h.points)
    for (int a = 0; a < 3; ++a) c[a] += p[a] / float(h.points.size());
  const LgnVec3 o = camera_origin(&cam);
  const float d[3] = {o.x - c[0], o.y - c[1], o.z - c[2]};
  const float len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  const float fl =
      std::sqrt(h.facing[0] * h.facing[0] + h.facing[1] * h.facing[1] + h.facing[2] * h.facing[2]);
  if (!(len > 0.0f) || !(fl > 0.0f)) return false;
  const float cosang = (d[0] * h.facing[0] + d[1] * h.facing[1] + d[2] * h.facing[2]) / (len * fl);
  return cosang >= std::cos(h.max_view_deg * float(M_PI) / 180.0f);
}

// Pixels every `stride` px inside the hull's projection into `cam`, shrunk towards its centre.
void hull_rays(const SolidHull& h, size_t index, const Camera& cam, uint32_t stride, float shrink,
               std::vector<HullRay>& rays) {
  std::vector<cv::Point2f> px, hull;
  for (const Vec3f& p : h.points) {
    float u = 0.0f, v = 0.0f;
    if (camera_project(&cam, lgn_vec3(p[0], p[1], p[2]), &u, &v) > 0.0f) px.emplace_back(u, v);
  }
  if (px.size() < 3) return;
  cv::convexHull(px, hull);
  cv::Point2f c(0.0f, 0.0f);
  for (const auto& q : hull) c += q * (1.0f / float(hull.size()));
  for (auto& q : hull) q = c + shrink * (q - c);
  const cv::Rect2f r = cv::boundingRect(hull);
  const float s = float(stride);
  for (float y = std::max(0.0f, std::floor(r.y / s) * s) + 0.5f * s;
       y < std::min(r.y + r.height, float(cam.height)); y += s)
    for (float x = std::max(0.0f, std::floor(r.x / s) * s) + 0.5f * s;
         x < std::min(r.x + r.width, float(cam.width)); x += s)
      if (cv::pointPolygonTest(hull, cv::Point2f(x, y), false) >= 0.0) rays.push_back({x, y, index});
}

// Each ray's opacity through the occupied cells of the box (front to back, as seen_opacity marches).
std::vector<float> ray_opacity(const Camera& cam, const std::vector<HullRay>& rays, const Aabb& box,
                               const SceneNormalisation& norm, float step, const OccupancyGrid& occ,
                               const DensityAt& density) {
  std::vector<uint32_t> ray_of;
  std::vector<Vec3f> points;
  const LgnVec3 o0 = camera_origin(&cam);
  const float o[3] = {o0.x * norm.scale + norm.offset[0], o0.y * norm.scale + norm.offset[1],
                      o0.z * norm.scale + norm.offset[2]};
  for (uint32_t r = 0; r < rays.size(); ++r) {
    const LgnVec3 d = camera_ray_dir(&cam, rays[r].x, rays[r].y);
    float t0 = 0.0f, t1 = 0.0f;
    if (!march_clip_aabb(box.min.data(), box.max.data(), o[0], o[1], o[2], d.x, d.y, d.z, &t0, &t1)) continue;
    const float dir[3] = {d.x, d.y, d.z};
    for (float t = t0 + 0.5f * step; t < t1; t += step) {
      Vec3f q;
      for (int a = 0; a < 3; ++a) q[a] = (o[a] + t * dir[a] - box.min[a]) / box.extent(a);
      if (!occ_test(occ.bits.data(), occ.res, q[0], q[1], q[2])) continue;
      ray_of.push_back(r);
      points.push_back(q);
    }
  }
  std::vector<float> sigma, T(rays.size(), 1.0f);
  if (!points.empty()) density(points, sigma);
  for (size_t i = 0; i < points.size(); ++i) {
    const float s = std::isfinite(sigma[i]) ? std::max(sigma[i], 0.0f) : 0.0f;
    T[ray_of[i]] *= std::exp(-s * step);
  }
  for (float& t : T) t = 1.0f - t;
  return T;
}

// The region of each hull: one per distinct name, in the order the names first appear.
std::vector<size_t> name_regions(const std::vector<SolidHull>& hulls, std::vector<RegionHoles>& regions) {
  std::vector<size_t> region_of;
  for (const SolidHull& h : hulls) {
    const std::string name = h.name.empty() ? "region" : h.name;
    size_t g = 0;
    while (g < regions.size() && regions[g].name != name) ++g;
    if (g == regions.size()) regions.push_back({name, 0, 0});
    region_of.push_back(g);
  }
  return region_of;
}

}  // namespace

std::string HoleReport::summary() const {
  if (!checked) return "holes in the face and head: not checked (no face region seen by the views)";
  std::vector<std::string> each;
  for (const RegionHoles& g : regions)
    if (g.rays) each.push_back(fmt::format("{} {:.2f} % of {}", g.name, 100.0 * g.share(), g.rays));
  return fmt::format(
      "holes in the face and head: {:.2f} % of the worst region's rays are transparent (opacity < {:.1f}; "
      "worst of {} views {:.2f} %), {} the {:.1f} % that breaks the head ({})",
      100.0 * holes, kHoleOpacity, views, 100.0 * worst_view, broken() ? "over" : "under",
      100.0 * kSubjectHoleShare, fmt::join(each, ", "));
}

std::string HoleReport::worst_region() const {
  const RegionHoles* worst = nullptr;
  for (const RegionHoles& g : regions)
    if (g.rays && (!worst || g.share() > worst->share())) worst = &g;
  return worst ? worst->name : "face and head";
}

std::string HoleReport::advice() const {
  if (!broken()) return "";
  return fmt::format(
      "the trained head has holes: {:.1f} % of the {} is transparent seen from the capture's "
      "views (worst view {:.1f} %), so the separation took skin for the room behind it. Film again with "
      "more between you and the wall: stand a metre or more in front of it, light your face from the "
      "front, not the wall, and prefer a wall darker or more coloured than your skin; turn slowly from "
      "one ear to the other (not only a small arc), with your own glasses off",
      100.0 * holes, worst_region(), 100.0 * worst_view);
}

HoleReport measure_holes(const std::vector<Camera>& cameras, const Aabb& box, const SceneNormalisation& norm,
                         float step, const OccupancyGrid& occ, const DensityAt& density,
                         const std::vector<SolidHull>& hulls, const HoleCheckOptions& opt) {
  HoleReport rep;
  if (cameras.empty() || hulls.empty() || !(step > 0.0f) || occ.res == 0) return rep;
  const std::vector<size_t> region_of = name_regions(hulls, rep.regions);
  const size_t n = std::min(cameras.size(), std::max<size_t>(opt.max_views, 1));
  for (size_t i = 0; i < n; ++i) {
    const Camera& cam = cameras[i * cameras.size() / n];
    const uint32_t stride = std::max(1u, std::max(cam.width, cam.height) / std::max(1u, opt.rays_across));
    std::vector<HullRay> rays;
    for (size_t h = 0; h < hulls.size(); ++h)
      if (faces_camera(hulls[h], cam))
        hull_rays(hulls[h], h, cam, stride, hulls[h].convex_solid ? 1.0f : opt.shrink, rays);
    if (rays.empty()) continue;
    const std::vector<float> alpha = ray_opacity(cam, rays, box, norm, step, occ, density);
    std::vector<RegionHoles> view(rep.regions.size());
    for (size_t r = 0; r < rays.size(); ++r) {
      RegionHoles& g = view[region_of[rays[r].hull]];
      ++g.rays;
      g.holes += alpha[r] < kHoleOpacity;
    }
    for (size_t g = 0; g < view.size(); ++g) {
      rep.regions[g].rays += view[g].rays, rep.regions[g].holes += view[g].holes;
      if (view[g].rays >= kMinViewRays) rep.worst_view = std::max(rep.worst_view, view[g].share());
    }
    rep.rays += rays.size();
    ++rep.views;
  }
  rep.checked = rep.rays > 0;
  for (const RegionHoles& g : rep.regions) {
    rep.holes = std::max(rep.holes, g.share());
    if (g.holes > 0) rep.where.push_back(fmt::format("{} {:.2f} %", g.name, 100.0 * g.share()));
  }
  rep.worst_view = std::max(rep.worst_view, rep.holes);
  return rep;
}

HoleReport check_subject_holes(NerfModel& model, const std::vector<Camera>& cameras,
                               const std::vector<SolidHull>& hulls, const HoleCheckOptions& options) {
  DensityAt density = [&](const std::vector<Vec3f>& points, std::vector<float>& sigma) {
    sigma = field::density_at(model.field(), model.runtime(), points);
  };
  return measure_holes(cameras, model.aabb(), model.normalisation, model.step(), model.occupancy(), density,
                       hulls, options);
}

}  // namespace lorgnette::nerf
