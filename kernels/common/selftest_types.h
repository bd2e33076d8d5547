// Parameter struct of the runtime self-test kernels; compiles as C++ and as OpenCL C.
#pragma once
#include "common/cl_compat.h"

typedef struct SelftestParams {
  lgn_uint count;
  float scale;
} SelftestParams;

LGN_STATIC_ASSERT(sizeof(SelftestParams) == 8, "SelftestParams layout");
