// Lets one header be valid OpenCL C and C++: fixed-width scalar names, a static_assert that
// vanishes in OpenCL, and LGN_INLINE for small helpers shared by host and device (write the math
// once; the host build is the test oracle for the kernels).
#pragma once

#ifdef __OPENCL_C_VERSION__
typedef uint lgn_uint;
typedef int lgn_int;
#define LGN_STATIC_ASSERT(cond, msg)
#define LGN_INLINE inline
#define LGN_GLOBAL __global
#else
#include <cmath>
#include <cstdint>
typedef uint32_t lgn_uint;
typedef int32_t lgn_int;
#define LGN_STATIC_ASSERT(cond, msg) static_assert(cond, msg)
#define LGN_INLINE inline
#define LGN_GLOBAL
#endif

#ifndef __OPENCL_C_VERSION__
// Host spellings of the OpenCL built-ins the shared headers use.
using std::exp;
using std::fabs;
using std::floor;
using std::fma;
using std::fmax;
using std::fmin;
using std::sqrt;
using std::tan;
#endif
