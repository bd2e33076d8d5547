// Which kernel variant the field builds: the device's own (Auto: the GPU variants on a GPU, the
// CPU variants otherwise), or a forced one, so the GPU variants are tested on a CPU device too.
// CPU variants vectorise across 16 samples per work-item (PoCL cannot vectorise across work-items
// with loops in the body); GPU variants run one sample (and level) per work-item.
#pragma once
#include "host/cl/runtime.h"

namespace lorgnette::field {

enum class KernelVariant { Auto, Cpu, Gpu };

inline bool use_gpu_variant(const cl::Runtime& rt, KernelVariant v) {
  return v == KernelVariant::Auto ? rt.device().is_gpu : v == KernelVariant::Gpu;
}

}  // namespace lorgnette::field
