// The parameter struct of the fused marcher (march_fused.cl), shared by host and kernels: what the
// kernel needs to evaluate the field itself, per sample, instead of handing batches to the field's
// own kernels. MarchParams (march_types.h) still describes the march; this describes the field and
// lives in a __constant buffer (it is larger than some devices' kernel-argument limit).
//
// Which field the program evaluates, and the widths of the NeRF's layers, are compile-time -D
// defines (host/render/fused_marcher.cpp), so a GPU keeps the activations in registers:
//   LGN_FUSED_FIELD           LGN_FUSED_ANALYTIC or LGN_FUSED_NERF
//   LGN_FUSED_LEVELS, _FEATURES, _ENC (levels * features padded to 4)
//   LGN_FUSED_DENSITY_HIDDEN, _GEO, _SH, _SH_PAD, _SH_DEGREE, _COLOR_HIDDEN, _COLOR_LAYERS
//   LGN_FUSED_LOCAL_WEIGHTS   1: the MLP weights are staged in local memory per work-group
#pragma once
#include "hashgrid/hashgrid_types.h"
#include "march/march_types.h"
#include "mlp/mlp_types.h"

#define LGN_FUSED_ANALYTIC 0
#define LGN_FUSED_NERF 1

typedef struct MarchFusedField {
  AnalyticFieldParams analytic;  // LGN_FUSED_ANALYTIC: the primitives (count, stride unused)
  HashgridParams hash;           // LGN_FUSED_NERF: the encoding's levels (n, stride unused)
  MlpChainParams mlp;            // LGN_FUSED_NERF: w_offset relative to mlp_begin, act per layer
  lgn_uint mlp_begin;            // first MLP weight in the parameter vector
  lgn_uint mlp_count;            // MLP weights (what is staged in local memory)
  lgn_uint pad[2];
} MarchFusedField;

LGN_STATIC_ASSERT(sizeof(MarchFusedField) ==
                      sizeof(AnalyticFieldParams) + sizeof(HashgridParams) + sizeof(MlpChainParams) + 16,
                  "MarchFusedField layout is shared with OpenCL");
