// The room model trained beside the subject's; see background_field.h.
#include "host/nerf/background_field.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "kernels/train/occupancy.h"
#include "kernels/train/render.h"

namespace lorgnette::nerf {
namespace {

Aabb room_box(const NerfModel& subject, const DeviceViews& views, float scale) {
  const std::array<float, 3> c = subject.aabb().center();
  float far = 0.0f;
  for (const Camera& cam : views.cameras()) {
    LgnVec3 o = camera_origin(&cam);
    far = std::max(far, std::sqrt((o.x - c[0]) * (o.x - c[0]) + (o.y - c[1]) * (o.y - c[1]) +
                                  (o.z - c[2]) * (o.z - c[2])));
  }
  const float half = scale * std::max(far, subject.aabb().max_extent());
  Aabb box;
  for (int a = 0; a < 3; ++a) box.min[a] = c[a] - half, box.max[a] = c[a] + half;
  return box;
}

// Every cell allowed except those whose centre lies inside the subject's box grown by `margin`
// (dataset +y is up; the box is not grown downwards).
std::vector<uint32_t> room_mask(const Aabb& room, Aabb subject, float margin, uint32_t res) {
  for (int a = 0; a < 3; ++a) {
    float grow = margin * subject.extent(a);
    if (a != 1) subject.min[a] -= grow;
    subject.max[a] += grow;
  }
  std::vector<uint32_t> mask(occ_word_count(res), 0u);
  for (uint32_t z = 0; z < res; ++z)
    for (uint32_t y = 0; y < res; ++y)
      for (uint32_t x = 0; x < res; ++x) {
        const uint32_t idx[3] = {x, y, z};
        bool inside = true;
        for (int a = 0; a < 3; ++a) {
          float p = room.min[a] + (idx[a] + 0.5f) / float(res) * room.extent(a);
          inside = inside && p > subject.min[a] && p < subject.max[a];
        }
        uint32_t cell = x + res * (y + res * z);
        if (!inside) mask[cell >> 5] |= 1u << (cell & 31u);
      }
  return mask;
}

// The subject's surroundings in the room's normalised positions (kernels/train/train_types.h
// NearRegion): its box grown by keep_far_mm, and below the zones' base only the column of
// keep_far_neck_mm about the base's axis.
NearRegion near_region(const Aabb& room, const Aabb& subject, const BackgroundOptions& o) {
  const float grow = o.keep_far_mm / o.subject->mm_per_unit;
  const std::array<float, 3>&lo = subject.min, &hi = subject.max;
  NearRegion n{};
  const std::array<float, 3> nlo = room.normalise({lo[0] - grow, lo[1] - grow, lo[2] - grow}),
                             nhi = room.normalise({hi[0] + grow, hi[1] + grow, hi[2] + grow});
  for (int a = 0; a < 3; ++a) n.lo[a] = nlo[a], n.hi[a] = nhi[a];
  if (neck_column(o).applies) {
    const SubjectAxis& b = *o.subject->base;
    const std::array<float, 3> p = room.normalise(b.point);
    for (int a = 0; a < 3; ++a) n.base[a] = p[a], n.up[a] = b.up[a];
    n.base_radius = o.keep_far_neck_mm / o.subject->mm_per_unit / room.extent(0);  // the room is a cube
  }
  return n;
}

}  // namespace

float skin_tolerance(const BackgroundOptions& o) {
  return o.neck_clear + (o.subject ? o.subject->skin.spread : 0.0f);
}

bool keep_cells_apply(const BackgroundOptions& o) {
  return o.keep_neck && o.room_clear > 0.0f && o.subject && !o.subject->keep.empty();
}

bool keep_far_applies(const BackgroundOptions& o) {
  return keep_cells_apply(o) && o.keep_far_mm > 0.0f && o.subject->mm_per_unit > 0.0f;
}

NeckColumn neck_column(const BackgroundOptions& o) {
  NeckColumn c;
  if (!o.subject) return c;
  const SkinChroma& skin = o.subject->skin;
  const std::vector<float> chroma = skin.pairs();
  c.patches = skin.beside_neck.size();
  for (const auto& rgb : skin.beside_neck)
    c.skin_like += render_ray_skin_like(rgb.data(), chroma.data(), uint32_t(skin.chroma.size()),
                                        skin_tolerance(o), skin.lum_floor) != 0;
  if (!keep_far_applies(o) || !(o.keep_far_neck_mm > 0.0f) || !o.subject->base) return c;
  const bool no_skin_test = !(o.neck_clear > 0.0f) || skin.chroma.empty();  // any wall may be skin
  c.applies = no_skin_test || c.patches == 0 || 2 * c.skin_like >= c.patches;
  return c;
}

float opacity_prior_share(const BackgroundOptions& o, uint64_t step) {
  const double ramp = std::max<double>(1.0, o.opacity_prior_ramp);
  return float(std::clamp((double(step) - double(o.opacity_prior_start)) / ramp, 0.0, 1.0));
}

BackgroundField::BackgroundField(cl::Runtime& rt, const NerfModel& subject, const DeviceViews& views,
                                 const BackgroundOptions& options, uint32_t max_batch, uint32_t seed)
    : options_(options) {
  Aabb box = room_box(subject, views, options.box_scale);
  field::FieldConfig cfg;
  cfg.levels = options.levels;
  cfg.log2_table_size = options.log2_table;
  cfg.finest_resolution = options.finest_resolution;
  cfg.sh_degree = options.sh_degree;
  cfg.validate();
  const uint32_t room_batch =
      std::max<uint32_t>(64u, uint32_t(std::lround(double(max_batch) * options.batch_scale / 64.0)) * 64u);
  model_ = std::make_unique<NerfModel>(rt, cfg, box, options.occupancy_resolution,
                                       box.diagonal() / float(options.steps_per_diagonal), room_batch,
                                       seed + 7919u, false);
  std::vector<uint32_t> mask =
      options.subject && !options.subject->volume.empty()
          ? room_cutout_mask(box, options.subject->volume,
                             options.volume_cutout_margin * subject.aabb().max_extent(),
                             options.subject->body, options.occupancy_resolution)
          : room_mask(box, subject.aabb(), options.cutout_margin, options.occupancy_resolution);
  OccupancyGrid grid = model_->occupancy();
  for (size_t w = 0; w < grid.bits.size(); ++w) grid.bits[w] &= mask[w];
  model_->set_occupancy(std::move(grid));
  occupancy_ = std::make_unique<OccupancyUpdater>(*model_, OccupancyOptions{}, seed + 7919u, std::move(mask));
  batch_ = std::make_unique<RayBatch>(*model_, model_->field().max_batch());
  if (options.subject && options.neck_clear > 0.0f) skin_chroma_ = options.subject->skin.pairs();
  if (keep_far_applies(options)) near_ = near_region(box, subject.aabb(), options);
  const std::array<float, 3> c = subject.aabb().center();
  near_t_ = 3.0e38f;
  for (const Camera& cam : views.cameras()) {
    LgnVec3 o = camera_origin(&cam);
    near_t_ = std::min(near_t_, std::sqrt((o.x - c[0]) * (o.x - c[0]) + (o.y - c[1]) * (o.y - c[1]) +
                                          (o.z - c[2]) * (o.z - c[2])));
  }
}

BackgroundField::~BackgroundField() = default;

std::string BackgroundField::summary() const {
  const Aabb& b = model_->aabb();
  return fmt::format(
      "room model: box {:.2f} units wide around the subject ({} cut out), {} levels up to {}, "
      "2^{} table, {:.1f} MB, up to {} samples per step (training only)",
      b.extent(0),
      options_.subject && !options_.subject->volume.empty()
          ? (options_.subject->body.empty() ? "the subject's volume"
                                            : "the subject's volume, not what lies below it")
          : "subject box",
      options_.levels, options_.finest_resolution, options_.log2_table,
      double(model_->param_bytes()) / (1024.0 * 1024.0), model_->field().max_batch());
}

uint32_t BackgroundField::count(const SampleParams& subject_params, const DeviceViews& views) {
  params_ = sample_params_for(*model_, views);
  params_.mode = subject_params.mode;
  params_.n_rays = std::min(subject_params.n_rays, batch_->max_rays());
  params_.seed = subject_params.seed;
  params_.iteration = subject_params.iteration;
  params_.near_t = near_t_;
  if (options_.spread_over_rays && params_.n_rays > 0)
    params_.max_samples =
        std::clamp<uint32_t>(model_->field().max_batch() / params_.n_rays, 1u, params_.max_samples);
  batch_->count(params_, views);
  return batch_->fit(0, model_->field().max_batch());
}

void BackgroundField::render_backgrounds(const SampleParams&, const DeviceViews& views, uint32_t end,
                                         RayBatch& subject) {
  cl::Runtime& rt = model_->runtime();
  uint32_t n = batch_->write(params_, views, 0, end);
  written_ = end;
  samples_ += n;
  if (n > 0)
    model_->field().forward(batch_->positions(), batch_->directions(), n, batch_->sigma(), batch_->rgb(),
                            true);
  batch_->render(LOSS_L2_LINEAR, true);
  colors_ = batch_->colors();
  if (end == 0) return;
  // Without the rule the far shares stay as the sampler wrote them (0).
  const std::vector<float> far = near_ ? batch_->far_shares(*near_) : std::vector<float>{};
  std::vector<float> info = subject.ray_info().read(rt, size_t(end) * RAY_INFO_FLOATS);
  for (uint32_t r = 0; r < end; ++r) {
    for (int c = 0; c < 3; ++c) info[size_t(r) * RAY_INFO_FLOATS + 3 + c] = colors_[size_t(r) * 4 + c];
    if (r < far.size()) info[size_t(r) * RAY_INFO_FLOATS + RAY_INFO_FAR] = far[r];
  }
  subject.ray_info_mut().write(rt, info);
}

void BackgroundField::backward(RayBatch& subject, uint32_t loss_kind, const field::AdamConfig& adam,
                               uint32_t step) {
  const std::vector<float> sc = written_ ? subject.colors() : std::vector<float>{};
  teach(
      subject,
      [&](uint32_t r, const float* target, float grad_scale, float* g) {
        const float* color = &sc[size_t(r) * 4];
        render_ray_loss(color, target, loss_kind, grad_scale, g);
        for (int c = 0; c < 3; ++c) g[c] *= 1.0f - color[3];
      },
      adam, step);
}

void BackgroundField::train_alone(RayBatch& subject, const std::vector<uint32_t>& subject_counts,
                                  uint32_t loss_kind, const field::AdamConfig& adam, uint32_t step) {
  // A ray without subject samples renders the room's colour alone (T = 1): the subject's loss with
  // the room's colour for the composite. A ray through the subject's volume, or one whose pixel may
  // be skin, teaches nothing.
  teach(
      subject,
      [&](uint32_t r, const float* target, float grad_scale, float* g) {
        ++alone_rays_;
        if (r >= subject_counts.size() || subject_counts[r] != 0) return;
        ++alone_missed_;
        if (skin_like(target)) return;
        ++alone_taught_;
        render_ray_loss(&colors_[size_t(r) * 4], target, loss_kind, grad_scale, g);
      },
      adam, step);
}

std::string BackgroundField::alone_summary() const {
  const auto pct = [this](uint64_t n) { return alone_rays_ ? 100.0 * double(n) / double(alone_rays_) : 0.0; };
  return fmt::format(
      "the room model trained alone first on {:.1f} % of its rays ({:.1f} % missed the subject's volume, "
      "{:.1f} % of them may be skin and waited for the subject)",
      pct(alone_taught_), pct(alone_missed_),
      alone_missed_ ? 100.0 * double(alone_missed_ - alone_taught_) / double(alone_missed_) : 0.0);
}

bool BackgroundField::skin_like(const float* pixel) const {
  if (skin_chroma_.empty()) return false;
  return render_ray_skin_like(pixel, skin_chroma_.data(), uint32_t(skin_chroma_.size() / 2),
                              skin_tolerance(options_), options_.subject->skin.lum_floor) != 0;
}

void BackgroundField::teach(RayBatch& subject, const RayGradient& gradient, const field::AdamConfig& adam,
                            uint32_t step) {
  cl::Runtime& rt = model_->runtime();
  const uint32_t end = written_;
  if (end > 0) {
    const std::vector<float> sinfo = subject.ray_info().read(rt, size_t(end) * RAY_INFO_FLOATS);
    std::vector<float> info = batch_->ray_info().read(rt, size_t(end) * RAY_INFO_FLOATS);
    const float grad_scale = 1.0f / (3.0f * float(end));
    for (uint32_t r = 0; r < end; ++r) {
      float g[3] = {0.0f, 0.0f, 0.0f};
      gradient(r, &sinfo[size_t(r) * RAY_INFO_FLOATS], grad_scale, g);
      // The room's own L2 loss against this target gives it the gradient g.
      for (int c = 0; c < 3; ++c)
        info[size_t(r) * RAY_INFO_FLOATS + c] =
            colors_[size_t(r) * 4 + c] - (std::isfinite(g[c]) ? g[c] : 0.0f) / (2.0f * grad_scale);
    }
    batch_->ray_info_mut().write(rt, info);
    batch_->render(LOSS_L2_LINEAR, false);
    if (batch_->written_samples() > 0) {
      model_->field().backward(batch_->dsigma(), batch_->drgb(), batch_->written_samples());
      field::AdamConfig a = adam;
      a.lr *= options_.lr_scale;
      model_->field().adam_step(a);
    }
  }
  occupancy_->maybe_update(step);
}

}  // namespace lorgnette::nerf
