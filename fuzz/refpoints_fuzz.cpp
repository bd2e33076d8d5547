// Fuzz target: the reference-point sidecar (<frame>.refpoints.json, mesh/refpoints.h) as
// load_glasses reads it. A sidecar that is accepted holds finite points within bounds::kMeshCoord
// and an mm_per_unit of 0 or within its range, and writes and reads back to the same values.
#include <cmath>
#include <cstdint>
#include <exception>
#include <string>
#include <string_view>

#include "fuzz/fuzz_check.h"
#include "host/util/bounds.h"
#include "mesh/refpoints.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace lorgnette;
  mesh::RefPointsSidecar s;
  try {
    s = mesh::parse_refpoints_sidecar(std::string_view(reinterpret_cast<const char*>(data), size),
                                      "fuzz.refpoints.json");
  } catch (const std::exception&) {
    return 0;  // refused with a message
  }
  for (const auto* p : {&s.points.g_c, &s.points.g_l, &s.points.g_r})
    LGN_FUZZ_CHECK(p->allFinite() && p->cwiseAbs().maxCoeff() <= bounds::kMeshCoord, "point in range");
  LGN_FUZZ_CHECK(s.mm_per_unit == 0.0 ||
                     (s.mm_per_unit >= bounds::kMmPerUnit.lo && s.mm_per_unit <= bounds::kMmPerUnit.hi),
                 "mm_per_unit in range");
  mesh::RefPointsSidecar t;
  try {
    t = mesh::parse_refpoints_sidecar(mesh::refpoints_sidecar_text(s), "re-written.refpoints.json");
  } catch (const std::exception& e) {
    LGN_FUZZ_CHECK(false, e.what());
  }
  LGN_FUZZ_CHECK(t.points.g_c == s.points.g_c && t.points.g_l == s.points.g_l && t.points.g_r == s.points.g_r,
                 "points");
  LGN_FUZZ_CHECK(t.mm_per_unit == s.mm_per_unit && t.space == s.space, "units and space");
  return 0;
}
