// Analytic volumes for tests and benchmarks: up to four constant-density boxes or spheres
// (kernels/march/analytic_field.cl), evaluated through the RadianceSource interface in place of
// the NeRF field, plus an exact occupancy bitfield for them so empty-space skipping is exercised,
// and the analytic head scene the frame-time benchmarks march when no trained model is given.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "host/cl/kernel.h"
#include "host/render/marcher.h"
#include "host/render/radiance_source.h"
#include "kernels/march/march_types.h"

namespace lorgnette::render {

using Vec3f = std::array<float, 3>;

AnalyticPrimitive analytic_box(Vec3f min, Vec3f max, float sigma, Vec3f rgb);
AnalyticPrimitive analytic_sphere(Vec3f centre, float radius, float sigma, Vec3f rgb);

// A head-sized stand-in for benchmarks when no trained model is at hand: a skull sphere, a nose and
// a neck (constant densities), inside the box analytic_head_min/max (scene units ~ decimetres).
std::vector<AnalyticPrimitive> analytic_head_primitives();
constexpr Vec3f analytic_head_min{-0.6f, -0.9f, -0.6f}, analytic_head_max{0.6f, 0.6f, 0.7f};

class AnalyticField : public RadianceSource {
 public:
  // Throws std::invalid_argument for more than LGN_ANALYTIC_MAX_PRIMS primitives or an empty box.
  AnalyticField(cl::Runtime& rt, Vec3f aabb_min, Vec3f aabb_max, const std::vector<AnalyticPrimitive>& prims,
                uint32_t max_batch = 1u << 16);
  uint32_t max_batch() const override { return max_batch_; }
  void evaluate(const cl::Buffer<float>& pos, const cl::Buffer<float>& dir, uint32_t n,
                cl::Buffer<float>& sigma, cl::Buffer<float>& rgb) override;
  InKernelField in_kernel() override { return {&params_, nullptr}; }
  const AnalyticFieldParams& params() const { return params_; }

  // res^3 bitfield (LGN_MARCH_OCC_LINEAR) marking every cell a primitive overlaps (conservative).
  std::vector<uint32_t> occupancy_bits(uint32_t res) const;

 private:
  cl::Runtime& rt_;
  cl::Kernel kernel_;
  AnalyticFieldParams params_{};
  uint32_t max_batch_;
};

// The analytic head as the frame-time benchmarks march it (`lorgnette bench frames` and
// benchmarks/march without --model): the field, its exact 64^3 occupancy grid and a NeRF-like step
// (sqrt(3)/1024 over a unit box). Not copyable or movable: scene() points at the members.
class AnalyticHeadScene {
 public:
  explicit AnalyticHeadScene(cl::Runtime& rt, uint32_t max_batch = 1u << 18);
  AnalyticHeadScene(const AnalyticHeadScene&) = delete;
  AnalyticHeadScene& operator=(const AnalyticHeadScene&) = delete;
  const VolumeScene& scene() const { return scene_; }

 private:
  AnalyticField field_;
  cl::Buffer<uint32_t> occupancy_;
  VolumeScene scene_;
};

}  // namespace lorgnette::render
