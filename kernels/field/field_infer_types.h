// Parameters of the field's fused inference kernel (kernels/field/field_infer.cl), shared by host
// and kernel. The kernel runs the whole forward of the Field (hash encoding, SH of the direction,
// density and colour MLPs, sigma) for 32 samples per work-item with every activation in a
// work-group local scratch of `rows` rows x 32 samples, reused from slab to slab. The layered path
// (hashgrid.cl + mlp_sh_encode + mlp_chain.cl) writes all of them to [row][max_batch] buffers of
// about 1 KiB per sample, whose rows lie 1 MiB apart at the usual capacities.
#pragma once
#include "common/cl_compat.h"
#include "hashgrid/hashgrid_types.h"

#define LGN_INFER_SLAB 32u       // samples per work-item (the CPU MLP's two float16 halves)
#define LGN_INFER_MAX_LAYERS 8u  // density 2 + colour up to 6; deeper colour nets use the layered path

typedef struct FieldInferParams {
  HashgridParams hash;  // hash.n: samples; hash.stride: SoA stride of pos, dir and rgb (max_batch)
  lgn_uint n16;         // samples processed: n rounded up to 16 (padded samples carry zeros)
  lgn_uint layers;      // density layers then colour layers
  lgn_uint sh_degree;   // SH degree (sh_count = degree^2 coefficients)
  lgn_uint sh_count;
  lgn_uint enc_rows;  // rows [levels * features, enc_rows) of the encoding are zero
  lgn_uint sh_row;    // first colour-input row: SH, zeros up to sh_row + sh_pad, then geo features
  lgn_uint sh_pad;
  lgn_uint raw_row;  // the raw density (geo feature 0)
  lgn_uint rgb_row;  // the sigmoid RGB (3 rows + 1 padding row)
  lgn_uint rows;     // scratch rows per work-item
  lgn_uint pad0, pad1;
  // Layer l: y rows y_row[l].. = act[l](W x rows x_row[l]..), W at w_offset[l] of [out][in] floats.
  lgn_uint in[LGN_INFER_MAX_LAYERS], out[LGN_INFER_MAX_LAYERS], w_offset[LGN_INFER_MAX_LAYERS];
  lgn_uint act[LGN_INFER_MAX_LAYERS], x_row[LGN_INFER_MAX_LAYERS], y_row[LGN_INFER_MAX_LAYERS];
} FieldInferParams;

LGN_STATIC_ASSERT(sizeof(FieldInferParams) == sizeof(HashgridParams) + 4 * 12 + 6 * 4 * LGN_INFER_MAX_LAYERS,
                  "FieldInferParams layout");
