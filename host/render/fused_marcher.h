// The fused marcher's host side (kernels/march/march_fused.cl): one launch marches a whole tile of
// rays, each work-item evaluating the field itself, per sample, with the occupancy skipping, the
// Eq. 7 surface insertion and early termination of the wavefront marcher (marcher.h) and the same
// sample sequence. It is the GPU-shaped path: Marcher picks it for RenderOptions::marcher = Fused,
// or Auto on a GPU device, and keeps the wavefront kernels on CPUs, where they are faster.
// Programs are built per field shape (the layer widths are -D defines, so a GPU keeps the
// activations in registers) and cached by the runtime.
#pragma once
#include <cstdint>
#include <string>

#include "host/cl/kernel.h"
#include "host/render/radiance_source.h"
#include "kernels/march/march_fused_types.h"

namespace lorgnette::render {

struct VolumeScene;

// Which marcher renders (RenderOptions::marcher): Auto takes the fused one on a GPU device when the
// field can be evaluated in a kernel, the wavefront one otherwise; the others force a path (tests
// run the fused one on PoCL, `render` and `bench frames` take --marcher).
enum class MarcherKind { Auto, Wavefront, Fused };

// "auto", "wavefront" or "fused"; throws std::invalid_argument naming the accepted words.
MarcherKind parse_marcher_kind(const std::string& word);

// The buffers one launch reads and adds into (owned by the caller).
struct FusedMarchBuffers {
  const cl::Buffer<uint32_t>* occupancy = nullptr;
  const cl::Buffer<float>*surf_ca = nullptr, *surf_depth = nullptr, *surf_filter = nullptr;
  cl::Buffer<float>*out_rgba = nullptr, *out_depth = nullptr;
  cl::Buffer<uint32_t>* out_samples = nullptr;
};

class FusedMarcher {
 public:
  // local_weights: stage the MLP weights in local memory when they fit the device (false: always
  // read them from global memory, the path of fields too large for local memory; tests force it).
  explicit FusedMarcher(cl::Runtime& rt, bool local_weights = true) : rt_(rt), allow_local_(local_weights) {}
  // Whether the source can be evaluated inside the kernel (an analytic field or the NeRF field).
  static bool supports(RadianceSource& source);
  // Builds (or takes from the cache) the program for the scene's field and uploads its description.
  // Throws std::invalid_argument when the field cannot be evaluated in a kernel.
  void prepare(const VolumeScene& scene);
  // Marches rays p.ray_begin .. + p.ray_count of the prepared scene in one launch, adding each
  // ray's share into the outputs; returns when the launch has finished.
  void march(const MarchParams& p, const FusedMarchBuffers& b);
  // The -D defines of the last prepare() (for logs and tests).
  const std::string& options() const { return options_; }
  bool local_weights() const { return local_bytes_ > 0; }

 private:
  cl::Runtime& rt_;
  cl::Kernel kernel_;
  std::string options_;
  MarchFusedField desc_{};
  cl::Buffer<MarchFusedField> desc_buffer_;
  cl::Buffer<float> no_params_;
  const cl::Buffer<float>* params_ = nullptr;
  size_t local_bytes_ = 0;
  bool allow_local_ = true;
};

}  // namespace lorgnette::render
