// Fuzz target: .lnerf snapshot parsing (host/nerf/snapshot.h) with no OpenCL device. A snapshot
// that parses must encode and parse back to the same contents.
#include <cstdint>
#include <cstring>
#include <exception>
#include <string>
#include <string_view>

#include "fuzz/fuzz_check.h"
#include "host/nerf/snapshot.h"

namespace {

bool same_bits(const void* a, const void* b, size_t bytes) {
  return bytes == 0 || std::memcmp(a, b, bytes) == 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace lorgnette::nerf;
  Snapshot s;
  try {
    s = parse_snapshot(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.lnerf");
  } catch (const std::exception&) {
    return 0;  // refused with a message: the expected outcome for a corrupt file
  }
  std::string again = encode_snapshot(s);
  Snapshot t;
  try {
    t = parse_snapshot(again, "re-encoded.lnerf");
  } catch (const std::exception& e) {
    LGN_FUZZ_CHECK(false, e.what());
  }
  LGN_FUZZ_CHECK(t.config == s.config, "field configuration");
  LGN_FUZZ_CHECK(
      t.params.size() == s.params.size() && same_bits(t.params.data(), s.params.data(), s.params.size() * 4),
      "parameters");
  LGN_FUZZ_CHECK(t.occ.res == s.occ.res && t.occ.bits == s.occ.bits, "occupancy bits");
  LGN_FUZZ_CHECK(t.occ.density.size() == s.occ.density.size() &&
                     same_bits(t.occ.density.data(), s.occ.density.data(), s.occ.density.size() * 4),
                 "occupancy density");
  LGN_FUZZ_CHECK(t.aabb.min == s.aabb.min && t.aabb.max == s.aabb.max && t.step == s.step, "box and step");
  LGN_FUZZ_CHECK(t.metadata.seed == s.metadata.seed && t.metadata.dataset_path == s.metadata.dataset_path,
                 "metadata");
  LGN_FUZZ_CHECK(t.view_range.has_value() == s.view_range.has_value() &&
                     (!s.view_range || (t.view_range->yaw_min == s.view_range->yaw_min &&
                                        t.view_range->pitch_max == s.view_range->pitch_max &&
                                        t.view_range->up == s.view_range->up &&
                                        t.view_range->cameras == s.view_range->cameras)),
                 "view range");
  return 0;
}
