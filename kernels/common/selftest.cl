// Kernels that exercise the runtime layer itself (build, cache, argument binding, launch checks).
#include "common/selftest_types.h"

__kernel void selftest_axpy(const SelftestParams p, __global const float* x, __global float* y) {
  const uint i = get_global_id(0);
  if (i >= p.count) return;
  y[i] = p.scale * x[i] + y[i];
#ifdef LGN_SELFTEST_BREAK
  undefined_name_xyz += 1;  // deliberate compile error for the build-log test
#endif
}
