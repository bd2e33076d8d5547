// The compositing marcher's host loop: see marcher.h and kernels/march/march.cl.
#include "host/render/marcher.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "host/util/bounds.h"

namespace lorgnette::render {
namespace {
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

void Marcher::ensure_workspace(uint32_t max_batch, uint32_t wave_min) {
  if (max_batch == batch_ && wave_min == wave_min_) return;
  if (max_batch < 64 * wave_min)
    throw std::invalid_argument(
        fmt::format("field batch capacity {} is too small for the marcher (>= 64 x wave_min = {})", max_batch,
                    64 * wave_min));
  batch_ = max_batch;
  wave_min_ = wave_min;
  tile_rays_ = max_batch / wave_min;
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

void Marcher::march_tile(const VolumeScene& scene, MarchParams p, const RenderOptions& o,
                         RenderResult& result) {
  const cl::Buffer<uint32_t>& occ = scene.occupancy.bits ? *scene.occupancy.bits : occ_dummy_;
  init_.args(p, rays_, surf_ca_, surf_depth_, live_).launch(rt_, p.ray_count, kLocal);
  uint32_t n_live = p.ray_count;
  while (n_live > 0) {
    p.live_count = n_live;
    p.samples_per_wave = std::clamp(batch_ / n_live, o.wave_min, o.wave_max);
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

namespace {
double box_diagonal(const VolumeScene& scene) {
  double d2 = 0;
  for (int a = 0; a < 3; ++a)
    d2 += double(scene.aabb_max[a] - scene.aabb_min[a]) * (scene.aabb_max[a] - scene.aabb_min[a]);
  return std::sqrt(d2);
}

void validate(const VolumeScene& scene, const Camera& cam, const RenderOptions& o) {
  if (!scene.field) throw std::invalid_argument("render: the scene has no field to march");
  if (cam.width == 0 || cam.height == 0 || uint64_t(cam.width) * cam.height > (1ull << 28))
    throw std::invalid_argument(
        fmt::format("render: image size {}x{} is outside 1..2^28 pixels", cam.width, cam.height));
  for (int a = 0; a < 3; ++a)
    if (!(scene.aabb_max[a] > scene.aabb_min[a]))
      throw std::invalid_argument(fmt::format("render: the bounding box is empty along axis {}", a));
  if (!(scene.step > 0.0f) || !(o.step_scale > 0.0f))
    throw std::invalid_argument("render: the marching step and step scale must be positive");
  // The most samples a ray may march (bounds.h): a tiny step (a damaged model, or a step scale far
  // below 1) would otherwise march for hours without a word.
  const double steps = box_diagonal(scene) / (double(scene.step) * o.step_scale);
  if (!(steps <= bounds::kMaxStepsPerRay))
    throw OutOfRange(fmt::format(
        "render: the marching step {:g} x step scale {:g} gives {:g} steps across the box, more than {:g}: "
        "raise the step scale (--step-scale, Python step_scale) or retrain the model with a larger step",
        scene.step, o.step_scale, steps, bounds::kMaxStepsPerRay));
  if (o.max_samples_per_ray > bounds::kMaxStepsPerRay + 8)
    throw OutOfRange(fmt::format("render: max_samples_per_ray {} is above {:g}", o.max_samples_per_ray,
                                 bounds::kMaxStepsPerRay + 8));
  if (o.spp == 0 || o.spp > 1024) throw std::invalid_argument("render: spp must be in 1..1024");
  if (o.wave_min < 1 || o.wave_max < o.wave_min || o.wave_max > 256)
    throw std::invalid_argument(
        fmt::format("render: segments per wave must satisfy 1 <= wave_min <= wave_max <= 256 (got {} and {})",
                    o.wave_min, o.wave_max));
  if (scene.occupancy.layout != LGN_MARCH_OCC_NONE &&
      (!scene.occupancy.bits || scene.occupancy.resolution == 0))
    throw std::invalid_argument("render: an occupancy layout was given without its grid");
}

void validate_surfaces(const Camera& cam, const lorgnette::SurfaceBuffers* surfaces) {
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
  validate_surfaces(cam, surfaces);
  PendingSurfaces pending;
  if (surfaces) {
    pending.row_begin = 0;
    pending.row_end = cam.height;
    pending.wait = [surfaces]() -> const lorgnette::SurfaceBuffers& { return *surfaces; };
  }
  return render(scene, cam, pending, o);
}

void Marcher::upload_surfaces(const lorgnette::SurfaceBuffers& s, uint32_t begin, uint32_t end) {
  const size_t pixels = s.pixel_count();
  if (surf_depth_.size() != pixels) {
    surf_ca_ = cl::Buffer<float>(rt_, 4 * pixels);
    surf_depth_ = cl::Buffer<float>(rt_, pixels);
    surf_filter_ = cl::Buffer<float>(rt_, 3 * pixels);
  }
  // Only the band is read by the kernels (rows outside it are marched without a surface).
  surf_ca_.write(rt_, s.color_alpha.data() + 4ull * begin, 4ull * (end - begin), 4ull * begin);
  surf_depth_.write(rt_, s.depth.data() + begin, end - begin, begin);
  if (s.filter.empty())
    surf_filter_.fill(rt_, 1.0f, 3ull * begin, 3ull * (end - begin));
  else
    surf_filter_.write(rt_, s.filter.data() + 3ull * begin, 3ull * (end - begin), 3ull * begin);
}

void Marcher::march_pixels(const VolumeScene& scene, MarchParams p, uint32_t begin, uint32_t end,
                           uint32_t spp, const RenderOptions& o, RenderResult& result) {
  for (uint32_t s = 0; s < spp; ++s) {
    auto j = subpixel_offset(s);
    p.jitter_u = j[0];
    p.jitter_v = j[1];
    const uint32_t tile = fused_on_ ? kFusedTile : tile_rays_;
    for (uint32_t first = begin; first < end; first += tile) {
      p.ray_begin = first;
      p.ray_count = std::min(tile, end - first);
      if (fused_on_)
        march_tile_fused(p, scene, result);
      else
        march_tile(scene, p, o, result);
    }
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
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

namespace {

// The frame's march parameters without a surface; its rays end after every step across the box plus
// the segments a surface split adds, unless the options cap them.
MarchParams march_params(const VolumeScene& scene, const Camera& cam, const RenderOptions& o,
                         uint32_t stride) {
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
  p.has_surface = 0u;
  p.occ_layout = scene.occupancy.layout;
  p.occ_res = scene.occupancy.resolution;
  if (o.max_samples_per_ray > 0) {
    p.max_samples = o.max_samples_per_ray;
  } else {  // every step across the box, plus the segments a surface split adds (validate caps it)
    p.max_samples =
        uint32_t(std::min(bounds::kMaxStepsPerRay, std::ceil(box_diagonal(scene) / p.step)) + 8.0);
  }
  p.field_stride = stride;
  return p;
}

}  // namespace

// The output buffers sized for the frame and cleared; the surface buffers bound (and never read)
// while no surface is.
void Marcher::clear_outputs(uint32_t pixels) {
  if (out_depth_.size() != pixels) {
    out_rgba_ = cl::Buffer<float>(rt_, 4ull * pixels);
    out_depth_ = cl::Buffer<float>(rt_, pixels);
    out_samples_ = cl::Buffer<uint32_t>(rt_, pixels);
  }
  out_rgba_.fill(rt_, 0.0f);
  out_depth_.fill(rt_, 0.0f);
  out_samples_.fill(rt_, 0u);
  if (surf_ca_.size() == 0) {
    surf_ca_ = cl::Buffer<float>(rt_, 4);
    surf_depth_ = cl::Buffer<float>(rt_, 1);
    surf_filter_ = cl::Buffer<float>(rt_, 3);
  }
}

void Marcher::read_back(const Camera& cam, uint32_t spp, RenderResult& result) {
  const uint32_t pixels = cam.width * cam.height;
  result.rays = uint64_t(pixels) * spp;
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
  result.fused = fused_on_;
  if (fused_on_) result.samples_evaluated = result.samples_composited;  // it evaluates what it composites
}

RenderResult Marcher::render(const VolumeScene& scene, const Camera& cam, const PendingSurfaces& surfaces,
                             const RenderOptions& o) {
  validate(scene, cam, o);
  auto start = std::chrono::steady_clock::now();
  fused_on_ = pick_fused(scene, o);
  ensure_workspace(scene.field->max_batch(), o.wave_min);
  const uint32_t pixels = cam.width * cam.height;
  clear_outputs(pixels);
  MarchParams p = march_params(scene, cam, o, batch_);

  // The band of rows the surface may cover; each pixel still gets its passes in order s = 0, 1, ...,
  // so the sums (and the image) do not depend on the order of the ranges.
  const bool has_band = bool(surfaces.wait) && surfaces.row_begin < std::min(surfaces.row_end, cam.height);
  const uint32_t band_begin = has_band ? surfaces.row_begin * cam.width : pixels;
  const uint32_t band_end = has_band ? std::min(surfaces.row_end, cam.height) * cam.width : pixels;
  RenderResult result;
  march_pixels(scene, p, 0, band_begin, o.spp, o, result);
  march_pixels(scene, p, band_end, pixels, o.spp, o, result);
  if (has_band) {
    rt_.finish();  // so the wait below is time the device sits idle
    auto t_wait = std::chrono::steady_clock::now();
    const lorgnette::SurfaceBuffers& s = surfaces.wait();
    result.times.surface_wait = seconds_since(t_wait);
    validate_surfaces(cam, &s);
    auto t_up = std::chrono::steady_clock::now();
    upload_surfaces(s, band_begin, band_end);
    result.times.upload = seconds_since(t_up);
    p.has_surface = 1u;
    march_pixels(scene, p, band_begin, band_end, o.spp, o, result);
  }
  rt_.finish();  // the march's last kernels belong to the march, not to the read-back
  auto t_read = std::chrono::steady_clock::now();
  read_back(cam, o.spp, result);
  result.times.readback = seconds_since(t_read);
  result.seconds = seconds_since(start);
  result.times.march =
      result.seconds - result.times.surface_wait - result.times.upload - result.times.readback;
  return result;
}

}  // namespace lorgnette::render
