// The density of a trained field at points the host holds: for host-side probes of a model (the
// subject cut check, the head volume benchmark), which march or sample on the host and need sigma at
// a list of points. Training and rendering keep their points on the device and call Field directly.
#pragma once
#include <array>
#include <vector>

#include "host/cl/runtime.h"
#include "host/field/field.h"

namespace lorgnette::field {

// sigma[i] = the field's density at unit_points[i] (positions in the field's unit cube, [0, 1]^3,
// as Field::density takes them), in batches of the field's max_batch(): one upload, one launch and
// one read per batch.
std::vector<float> density_at(Field& field, cl::Runtime& rt,
                              const std::vector<std::array<float, 3>>& unit_points);

}  // namespace lorgnette::field
