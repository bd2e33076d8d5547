// The fused marcher's program choice, field description and launch: see fused_marcher.h.
#include "host/render/fused_marcher.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cstring>
#include <stdexcept>

#include "host/field/field.h"
#include "host/field/hashgrid.h"
#include "host/field/mlp.h"
#include "host/render/marcher.h"

namespace lorgnette::render {
namespace {
constexpr size_t kLocal = 64;             // rays per work-group (they share the staged weights)
constexpr uint64_t kLocalReserve = 1024;  // local memory left to the compiler's own use

// The NeRF field as the fused kernel sees it: the encoding's levels, the chain's layers with
// weight offsets relative to the first MLP weight, and the -D defines of the layer widths.
std::string describe_nerf(const field::Field& f, MarchFusedField& d) {
  const field::FieldConfig& cfg = f.config();
  const field::ParamLayout& lay = f.layout();
  d.hash = field::make_hashgrid_params(cfg, lay, 0);
  d.mlp = field::plan_chain(lay, 0).chain;
  d.mlp_begin = uint32_t(lay.mlp_offset);
  d.mlp_count = uint32_t(lay.total - lay.mlp_offset);
  for (uint32_t l = 0; l < d.mlp.layers; ++l) d.mlp.w_offset[l] -= d.mlp_begin;
  const uint32_t sh_degree = cfg.sh_degree;
  return fmt::format(
      "-DLGN_FUSED_FIELD=LGN_FUSED_NERF -DLGN_FUSED_LEVELS={}u -DLGN_FUSED_FEATURES={}u -DLGN_FUSED_ENC={}u "
      "-DLGN_FUSED_DENSITY_HIDDEN={}u -DLGN_FUSED_GEO={}u -DLGN_FUSED_SH_PAD={}u -DLGN_FUSED_SH_DEGREE={}u "
      "-DLGN_FUSED_COLOR_HIDDEN={}u -DLGN_FUSED_COLOR_LAYERS={}u",
      cfg.levels, cfg.features_per_level, lay.enc_pad, lay.density[0].out_pad, lay.density[1].out_pad,
      field::pad4(lay.sh_count), sh_degree, lay.color[0].out_pad, uint32_t(lay.color.size()));
}
}  // namespace

MarcherKind parse_marcher_kind(const std::string& word) {
  if (word == "auto") return MarcherKind::Auto;
  if (word == "wavefront") return MarcherKind::Wavefront;
  if (word == "fused") return MarcherKind::Fused;
  throw std::invalid_argument(fmt::format("marcher '{}': expected auto, wavefront or fused", word));
}

bool FusedMarcher::supports(RadianceSource& source) {
  InKernelField k = source.in_kernel();
  return k.analytic || k.nerf;
}

void FusedMarcher::prepare(const VolumeScene& scene) {
  InKernelField k = scene.field->in_kernel();
  std::memset(&desc_, 0, sizeof(desc_));
  std::string options;
  local_bytes_ = 0;
  if (k.nerf) {
    options = describe_nerf(*k.nerf, desc_);
    params_ = &k.nerf->params();
    // The weights go to local memory when a work-group's share fits (about 38 KB for the default
    // field against 48 KB on NVIDIA GPUs); otherwise every work-item reads them from global memory.
    const uint64_t bytes = uint64_t(desc_.mlp_count) * sizeof(float);
    const bool local = allow_local_ && bytes + kLocalReserve <= rt_.device().local_mem_bytes;
    options += fmt::format(" -DLGN_FUSED_LOCAL_WEIGHTS={}", local ? 1 : 0);
    if (local) local_bytes_ = bytes;
  } else if (k.analytic) {
    desc_.analytic = *k.analytic;
    options = "-DLGN_FUSED_FIELD=LGN_FUSED_ANALYTIC -DLGN_FUSED_LOCAL_WEIGHTS=0";
    if (no_params_.size() == 0) no_params_ = cl::Buffer<float>(rt_, 1);
    params_ = &no_params_;
  } else {
    throw std::invalid_argument(
        "render: the fused marcher evaluates the field inside its kernel and this radiance source has no "
        "in-kernel form; use the wavefront marcher (--marcher wavefront)");
  }
  if (options != options_ || !kernel_.get()) {
    kernel_ = cl::Kernel(rt_.program("march/march_fused.cl", options), "march_fused");
    options_ = options;
    spdlog::debug("fused marcher: {}", options_);
  }
  if (desc_buffer_.size() == 0) desc_buffer_ = cl::Buffer<MarchFusedField>(rt_, 1, CL_MEM_READ_ONLY);
  desc_buffer_.write(rt_, &desc_, 1);
}

void FusedMarcher::march(const MarchParams& p, const FusedMarchBuffers& b) {
  if (!params_) throw std::logic_error("FusedMarcher::march before prepare()");
  kernel_
      .args(p, desc_buffer_, *params_, *b.occupancy, *b.surf_ca, *b.surf_depth, *b.surf_filter, *b.out_rgba,
            *b.out_depth, *b.out_samples, cl::LocalBytes{local_bytes_ > 0 ? local_bytes_ : sizeof(float)})
      .launch(rt_, p.ray_count, kLocal);
  // Wait here: the march is the launch, so the frame's time split (FrameTimes) counts it as marching
  // rather than as the read-back that would otherwise be the first to wait for it.
  rt_.finish();
}

}  // namespace lorgnette::render
