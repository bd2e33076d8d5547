// The compositing marcher's host loop: see marcher.h and kernels/march/march.cl.
#include "host/render/marcher.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace lorgnette::render {
namespace {
constexpr uint32_t kMinWave = 4;      // segments per ray and wave when the tile is full
constexpr uint32_t kMaxWave = 64;     // ... and when few rays are left
constexpr uint32_t kScanBlock = 256;  // entries per work-item in the prefix sums
constexpr size_t kLocal = 64;
constexpr uint32_t kFusedTile = 1u << 21;  // rays per fused launch: a 1080p frame in one
}  // namespace

std::array<float, 2> subpixel_offset(uint32_t s) {
  if (s == 0) return {0.5f, 0.5f};
  // R2 sequence (plastic-number based): well spread for any count of passes.
  double u = 0.5 + s * 0.7548776662466927, v = 0.5 + s * 0.5698402909980532;
  return {float(u - std::floor(u)), float(v - std::floor(v))};
}

Marcher::Marcher(cl::Runtime& rt) : rt_(rt) {
  cl_program prog = rt.program("march/march.cl");
  init_ = cl::Kernel(prog, "march_init");
  step_ = cl::Kernel(prog, "march_step");
  scan_blocks_ = cl::Kernel(prog, "march_scan_blocks");
  scan_top_ = cl::Kernel(prog, "march_scan_top");
  scan_apply_ = cl::Kernel(prog, "march_scan_apply");
  compact_ = cl::Kernel(prog, "march_compact");
  gather_ = cl::Kernel(prog, "march_gather");
  composite_ = cl::Kernel(prog, "march_composite");
  occ_dummy_ = cl::Buffer<uint32_t>(rt, 1);
  total_ = cl::Buffer<uint32_t>(rt, 1);
}

void Marcher::ensure_workspace(uint32_t max_batch) {
  if (max_batch == batch_) return;
  if (max_batch < 64 * kMinWave)
    throw std::invalid_argument(fmt::format("field batch capacity {} is too small for the marcher (>= {})",
                                            max_batch, 64 * kMinWave));
  batch_ = max_batch;
  tile_rays_ = max_batch / kMinWave;
  rays_ = cl::Buffer<MarchRay>(rt_, tile_rays_);
  for (auto* b : {&live_, &live_next_, &counts_, &offsets_, &flags_})
    *b = cl::Buffer<uint32_t>(rt_, tile_rays_);
  block_sums_ = cl::Buffer<uint32_t>(rt_, tile_rays_ / kScanBlock + 1);
  seg_ = cl::Buffer<cl_float2>(rt_, batch_);
  pos_ = cl::Buffer<float>(rt_, 3ull * batch_);
  dir_ = cl::Buffer<float>(rt_, 3ull * batch_);
  rgb_ = cl::Buffer<float>(rt_, 3ull * batch_);
  sigma_ = cl::Buffer<float>(rt_, batch_);
}

uint32_t Marcher::scan(uint32_t n, const cl::Buffer<uint32_t>& in, cl::Buffer<uint32_t>& out) {
  uint32_t nblocks = (n + kScanBlock - 1) / kScanBlock;
  scan_blocks_.args(n, kScanBlock, in, block_sums_).launch(rt_, nblocks, kLocal);
  scan_top_.args(nblocks, block_sums_, total_).launch(rt_, 1, 1);
  scan_apply_.args(n, kScanBlock, in, block_sums_, out).launch(rt_, nblocks, kLocal);
  uint32_t total = 0;
  total_.read(rt_, &total, 1);
  return total;
}

void Marcher::march_tile(const VolumeScene& scene, MarchParams p, RenderResult& result) {
  const cl::Buffer<uint32_t>& occ = scene.occupancy.bits ? *scene.occupancy.bits : occ_dummy_;
  init_.args(p, rays_, surf_ca_, surf_depth_, live_).launch(rt_, p.ray_count, kLocal);
  uint32_t n_live = p.ray_count;
  while (n_live > 0) {
    p.live_count = n_live;
    p.samples_per_wave = std::clamp(batch_ / n_live, kMinWave, kMaxWave);
    step_.args(p, rays_, live_, occ, counts_, seg_).launch(rt_, n_live, kLocal);
    uint32_t total = scan(n_live, counts_, offsets_);
    if (total > 0) {
      gather_.args(p, rays_, live_, counts_, offsets_, seg_, pos_, dir_).launch(rt_, n_live, kLocal);
      scene.field->evaluate(pos_, dir_, total, sigma_, rgb_);
    }
    composite_
        .args(p, rays_, live_, counts_, offsets_, seg_, sigma_, rgb_, surf_ca_, surf_filter_, out_rgba_,
              out_depth_, out_samples_, flags_)
        .launch(rt_, n_live, kLocal);
    uint32_t survivors = scan(n_live, flags_, offsets_);
    if (survivors > 0) {
      compact_.args(n_live, flags_, offsets_, live_, live_next_).launch(rt_, n_live, kLocal);
      std::swap(live_, live_next_);
    }
    result.samples_evaluated += total;
    ++result.waves;
    n_live = survivors;
  }
}

bool Marcher::pick_fused(const VolumeScene& scene, const RenderOptions& o) {
  if (o.marcher == MarcherKind::Wavefront) return false;
  if (o.marcher == MarcherKind::Auto && !(rt_.device().is_gpu && FusedMarcher::supports(*scene.field)))
    return false;
  if (!fused_) fused_ = std::make_unique<FusedMarcher>(rt_);
  fused_->prepare(scene);  // throws when the field has no in-kernel form
  return true;
}

void Marcher::march_tile_fused(MarchParams p, const VolumeScene& scene, RenderResult& result) {
  FusedMarchBuffers b;
  b.occupancy = scene.occupancy.bits ? scene.occupancy.bits : &occ_dummy_;
  b.surf_ca = &surf_ca_;
  b.surf_depth = &surf_depth_;
  b.surf_filter = &surf_filter_;
  b.out_rgba = &out_rgba_;
  b.out_depth = &out_depth_;
  b.out_samples = &out_samples_;
  fused_->march(p, b);
  ++result.waves;
}

namespace {
void validate(const VolumeScene& scene, const Camera& cam, const lorgnette::SurfaceBuffers* surfaces,
              const RenderOptions& o) {
  if (!scene.field) throw std::invalid_argument("render: the scene has no field to march");
  if (cam.width == 0 || cam.height == 0 || uint64_t(cam.width) * cam.height > (1ull << 28))
    throw std::invalid_argument(
        fmt::format("render: image size {}x{} is outside 1..2^28 pixels", cam.width, cam.height));
  for (int a = 0; a < 3; ++a)
    if (!(scene.aabb_max[a] > scene.aabb_min[a]))
      throw std::invalid_argument(fmt::format("render: the bounding box is empty along axis {}", a));
  if (!(scene.step > 0.0f) || !(o.step_scale > 0.0f))
    throw std::invalid_argument("render: the marching step and step scale must be positive");
  if (o.spp == 0 || o.spp > 1024) throw std::invalid_argument("render: spp must be in 1..1024");
  if (scene.occupancy.layout != LGN_MARCH_OCC_NONE &&
      (!scene.occupancy.bits || scene.occupancy.resolution == 0))
    throw std::invalid_argument("render: an occupancy layout was given without its grid");
  if (surfaces) {
    if (surfaces->width != int(cam.width) || surfaces->height != int(cam.height) ||
        surfaces->color_alpha.size() != surfaces->pixel_count() * 4 ||
        surfaces->depth.size() != surfaces->pixel_count() ||
        (!surfaces->filter.empty() && surfaces->filter.size() != surfaces->pixel_count() * 3))
      throw std::invalid_argument(
          fmt::format("render: surface buffers are {}x{} but the camera is {}x{}: run the surface pass with "
                      "the same camera",
                      surfaces->width, surfaces->height, cam.width, cam.height));
  }
}
}  // namespace

RenderResult Marcher::render(const VolumeScene& scene, const Camera& cam,
                             const lorgnette::SurfaceBuffers* surfaces, const RenderOptions& o) {
  validate(scene, cam, surfaces, o);
  auto start = std::chrono::steady_clock::now();
  fused_on_ = pick_fused(scene, o);
  ensure_workspace(scene.field->max_batch());
  const uint32_t pixels = cam.width * cam.height;
  if (out_depth_.size() != pixels) {
    out_rgba_ = cl::Buffer<float>(rt_, 4ull * pixels);
    out_depth_ = cl::Buffer<float>(rt_, pixels);
    out_samples_ = cl::Buffer<uint32_t>(rt_, pixels);
  }
  out_rgba_.fill(rt_, 0.0f);
  out_depth_.fill(rt_, 0.0f);
  out_samples_.fill(rt_, 0u);
  if (surfaces) {
    surf_ca_ = cl::Buffer<float>(rt_, surfaces->color_alpha);
    surf_depth_ = cl::Buffer<float>(rt_, surfaces->depth);
    surf_filter_ = surfaces->filter.empty() ? cl::Buffer<float>(rt_, std::vector<float>(3ull * pixels, 1.0f))
                                            : cl::Buffer<float>(rt_, surfaces->filter);
  } else if (surf_ca_.size() == 0) {
    surf_ca_ = cl::Buffer<float>(rt_, 4);
    surf_depth_ = cl::Buffer<float>(rt_, 1);
    surf_filter_ = cl::Buffer<float>(rt_, 3);
  }

  MarchParams p{};
  p.cam = cam;
  for (int a = 0; a < 3; ++a) {
    p.aabb_min[a] = scene.aabb_min[a];
    p.aabb_max[a] = scene.aabb_max[a];
    p.background[a] = o.background[a];
  }
  p.step = scene.step * o.step_scale;
  p.min_transmittance = o.min_transmittance;
  p.sample_weight = 1.0f / float(o.spp);
  p.alpha_mode = o.alpha ? 1u : 0u;
  p.has_surface = surfaces ? 1u : 0u;
  p.occ_layout = scene.occupancy.layout;
  p.occ_res = scene.occupancy.resolution;
  if (o.max_samples_per_ray > 0) {
    p.max_samples = o.max_samples_per_ray;
  } else {  // every step across the box, plus the segments a surface split adds
    double d2 = 0;
    for (int a = 0; a < 3; ++a)
      d2 += double(scene.aabb_max[a] - scene.aabb_min[a]) * (scene.aabb_max[a] - scene.aabb_min[a]);
    p.max_samples = uint32_t(std::min(1e7, std::ceil(std::sqrt(d2) / p.step) + 8.0));
  }
  p.field_stride = batch_;

  RenderResult result;
  for (uint32_t s = 0; s < o.spp; ++s) {
    auto j = subpixel_offset(s);
    p.jitter_u = j[0];
    p.jitter_v = j[1];
    const uint32_t tile = fused_on_ ? kFusedTile : tile_rays_;
    for (uint32_t begin = 0; begin < pixels; begin += tile) {
      p.ray_begin = begin;
      p.ray_count = std::min(tile, pixels - begin);
      if (fused_on_)
        march_tile_fused(p, scene, result);
      else
        march_tile(scene, p, result);
    }
  }
  result.rays = uint64_t(pixels) * o.spp;
  result.rgba = Image(int(cam.width), int(cam.height), 4);
  result.depth = Image(int(cam.width), int(cam.height), 1);
  result.samples = Image(int(cam.width), int(cam.height), 1);
  out_rgba_.read(rt_, result.rgba.pixels.data(), result.rgba.pixels.size());
  out_depth_.read(rt_, result.depth.pixels.data(), pixels);
  std::vector<uint32_t> counts = out_samples_.read(rt_, pixels);
  for (uint32_t i = 0; i < pixels; ++i) {
    result.samples.pixels[i] = float(counts[i]);
    result.samples_composited += counts[i];
  }
  if (fused_on_) result.samples_evaluated = result.samples_composited;  // it evaluates what it composites
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace lorgnette::render
