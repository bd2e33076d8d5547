// Fuzz target: placement.json reading (fit/placement_json.h), as `render` reads it. A file that is
// accepted must write (to_json) and read back with the same landmarks and temple spread.
#include <cstdint>
#include <exception>
#include <nlohmann/json.hpp>
#include <string>

#include "fit/placement_json.h"
#include "fuzz/fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace lorgnette::fit;
  PlacementFile p;
  try {
    p = placement_from_json(nlohmann::json::parse(data, data + size));
  } catch (const std::exception&) {
    return 0;  // not JSON, or refused with a message
  }
  PlacementFile q;
  try {
    q = placement_from_json(nlohmann::json::parse(to_json(p).dump(2)));
  } catch (const std::exception& e) {
    LGN_FUZZ_CHECK(false, e.what());
  }
  LGN_FUZZ_CHECK(q.transform == p.transform, "transform");
  LGN_FUZZ_CHECK(q.landmarks.size() == p.landmarks.size() && q.residuals_px == p.residuals_px, "landmarks");
  LGN_FUZZ_CHECK(q.has_temples == p.has_temples, "temples");
  if (p.has_temples)
    LGN_FUZZ_CHECK(q.temples.bend.left.spread_deg == p.temples.bend.left.spread_deg &&
                       q.temples.bend.right.hinge == p.temples.bend.right.hinge,
                   "temple spread");
  return 0;
}
