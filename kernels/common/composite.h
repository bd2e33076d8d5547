// Front-to-back emission-absorption compositing of one segment, written once for the training
// loss (kernels/train/render.h, forward and backward) and the inference marcher
// (kernels/march/march_math.h), so the two paths cannot drift apart; compiles as OpenCL C and C++
// (the host tests use it as their oracle).
#pragma once
#include "common/cl_compat.h"

// A segment of length dt and density sigma seen through transmittance *T: returns its weight
// w = T (1 - e^{-sigma dt}), the share of the pixel its colour gets, and attenuates *T by
// e^{-sigma dt} (multiplying by the exponential itself, not by 1 - alpha, keeps small T accurate).
LGN_INLINE float lgn_composite_segment(float* T, float sigma, float dt) {
  const float att = exp(-sigma * dt);
  const float w = *T * (1.0f - att);
  *T *= att;
  return w;
}
