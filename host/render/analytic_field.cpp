// Analytic volumes: see analytic_field.h.
#include "host/render/analytic_field.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "kernels/march/march_math.h"

namespace lorgnette::render {

AnalyticPrimitive analytic_box(Vec3f min, Vec3f max, float sigma, Vec3f rgb) {
  AnalyticPrimitive p{};
  p.kind = LGN_ANALYTIC_BOX;
  p.sigma = sigma;
  for (int a = 0; a < 3; ++a) {
    p.rgb[a] = rgb[a];
    p.a[a] = min[a];
    p.b[a] = max[a];
  }
  return p;
}

AnalyticPrimitive analytic_sphere(Vec3f centre, float radius, float sigma, Vec3f rgb) {
  AnalyticPrimitive p{};
  p.kind = LGN_ANALYTIC_SPHERE;
  p.sigma = sigma;
  for (int a = 0; a < 3; ++a) {
    p.rgb[a] = rgb[a];
    p.a[a] = centre[a];
  }
  p.b[0] = radius;
  return p;
}

std::vector<AnalyticPrimitive> analytic_head_primitives() {
  return {analytic_sphere({0.0f, 0.0f, 0.0f}, 0.5f, 60.0f, {0.80f, 0.60f, 0.50f}),
          analytic_sphere({0.0f, -0.05f, 0.52f}, 0.09f, 60.0f, {0.85f, 0.55f, 0.45f}),
          analytic_box({-0.2f, -0.9f, -0.25f}, {0.2f, -0.35f, 0.2f}, 40.0f, {0.75f, 0.55f, 0.45f}),
          analytic_sphere({0.0f, 0.25f, -0.05f}, 0.5f, 8.0f, {0.25f, 0.15f, 0.10f})};  // hair, semi-dense
}

AnalyticField::AnalyticField(cl::Runtime& rt, Vec3f aabb_min, Vec3f aabb_max,
                             const std::vector<AnalyticPrimitive>& prims, uint32_t max_batch)
    : rt_(rt), max_batch_((max_batch + 63u) / 64u * 64u) {
  if (prims.size() > LGN_ANALYTIC_MAX_PRIMS)
    throw std::invalid_argument("analytic field: " + std::to_string(prims.size()) +
                                " primitives given, at most " + std::to_string(LGN_ANALYTIC_MAX_PRIMS));
  for (int a = 0; a < 3; ++a) {
    if (!(aabb_max[a] > aabb_min[a]))
      throw std::invalid_argument("analytic field: the bounding box is empty along axis " +
                                  std::to_string(a));
    params_.aabb_min[a] = aabb_min[a];
    params_.aabb_max[a] = aabb_max[a];
  }
  params_.prim_count = static_cast<uint32_t>(prims.size());
  std::copy(prims.begin(), prims.end(), params_.prims);
  params_.stride = max_batch_;
  kernel_ = cl::Kernel(rt.program("march/analytic_field.cl"), "analytic_field_eval");
}

void AnalyticField::evaluate(const cl::Buffer<float>& pos, const cl::Buffer<float>& /*dir*/, uint32_t n,
                             cl::Buffer<float>& sigma, cl::Buffer<float>& rgb) {
  if (n > max_batch_ || pos.size() < 3ull * max_batch_ || sigma.size() < max_batch_ ||
      rgb.size() < 3ull * max_batch_)
    throw std::invalid_argument("analytic field: " + std::to_string(n) +
                                " samples or buffer sizes exceed "
                                "the batch capacity " +
                                std::to_string(max_batch_));
  if (n == 0) return;
  AnalyticFieldParams p = params_;
  p.count = n;
  kernel_.args(p, pos, sigma, rgb).launch(rt_, n, 64);
}

namespace {
bool overlaps(const AnalyticPrimitive& q, const float lo[3], const float hi[3]) {
  if (!(q.sigma > 0.0f)) return false;
  if (q.kind == LGN_ANALYTIC_SPHERE) {
    float d2 = 0.0f;
    for (int a = 0; a < 3; ++a) {
      float c = std::clamp(q.a[a], lo[a], hi[a]) - q.a[a];
      d2 += c * c;
    }
    return d2 <= q.b[0] * q.b[0];
  }
  for (int a = 0; a < 3; ++a)
    if (q.b[a] < lo[a] || q.a[a] > hi[a]) return false;
  return true;
}
}  // namespace

std::vector<uint32_t> AnalyticField::occupancy_bits(uint32_t res) const {
  if (res == 0 || res > 1024) throw std::invalid_argument("occupancy resolution must be in 1..1024");
  size_t cells = static_cast<size_t>(res) * res * res;
  std::vector<uint32_t> bits((cells + 31) / 32, 0u);
  float cell[3];
  for (int a = 0; a < 3; ++a) cell[a] = (params_.aabb_max[a] - params_.aabb_min[a]) / float(res);
  for (uint32_t z = 0; z < res; ++z)
    for (uint32_t y = 0; y < res; ++y)
      for (uint32_t x = 0; x < res; ++x) {
        uint32_t c[3] = {x, y, z};
        float lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {  // grown by a margin: the grid must never hide density
          lo[a] = params_.aabb_min[a] + (float(c[a]) - 0.01f) * cell[a];
          hi[a] = params_.aabb_min[a] + (float(c[a]) + 1.01f) * cell[a];
        }
        bool occ = false;
        for (uint32_t i = 0; i < params_.prim_count && !occ; ++i) occ = overlaps(params_.prims[i], lo, hi);
        if (occ) {
          size_t idx = x + size_t(res) * (y + size_t(res) * z);
          bits[idx >> 5] |= 1u << (idx & 31u);
        }
      }
  return bits;
}

AnalyticHeadScene::AnalyticHeadScene(cl::Runtime& rt, uint32_t max_batch)
    : field_(rt, analytic_head_min, analytic_head_max, analytic_head_primitives(), max_batch),
      occupancy_(rt, field_.occupancy_bits(64)) {
  scene_.aabb_min = analytic_head_min;
  scene_.aabb_max = analytic_head_max;
  scene_.step = 1.7f / 1024.0f;
  scene_.occupancy = {LGN_MARCH_OCC_LINEAR, 64, &occupancy_};
  scene_.field = &field_;
}

}  // namespace lorgnette::render
