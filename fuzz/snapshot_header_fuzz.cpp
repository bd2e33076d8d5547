// Fuzz target: the .lnerf JSON header alone (host/nerf/snapshot.h). The whole-file target rarely
// gets a mutated header past the header's checksum; here the input is the header's text, and the
// target builds a file around it that the checksums cannot stop: blobs of zeros where the header
// lists them (their sizes, offsets and checksums set to match), and the header sealed (seal_header).
// The values, their ranges and the version logic are what is fuzzed. A header that parses must
// encode and parse back to the same box, step and normalisation.
#include <fmt/format.h>

#include <cstdint>
#include <cstring>
#include <exception>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "fuzz/fuzz_check.h"
#include "host/nerf/snapshot.h"

namespace {

using nlohmann::json;
using namespace lorgnette::nerf;

constexpr uint64_t kMaxBlobBytes = 1 << 22;  // zeros the target is willing to write per blob

// The header text with its blob table made consistent with zero-filled blobs; `zeros` gets their
// total size. Text that is not a JSON object is returned as it is.
std::string consistent_header(std::string_view text, uint64_t& zeros) {
  json h = json::parse(std::string(text), nullptr, false);
  zeros = 0;
  if (!h.is_object()) return std::string(text);
  auto it = h.find("blobs");
  if (it != h.end() && it->is_array()) {
    for (json& b : *it) {
      if (!b.is_object() || !b.contains("bytes") || !b["bytes"].is_number_unsigned()) continue;
      uint64_t n = b["bytes"].get<uint64_t>();
      if (n > kMaxBlobBytes) continue;
      std::string blob(n, '\0');
      b["offset"] = zeros;
      b["fnv1a64"] = fmt::format("{:016x}", snapshot_checksum(blob));
      zeros += n;
    }
  }
  return seal_header(h.dump());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  uint64_t zeros = 0;
  std::string header = consistent_header(std::string_view(reinterpret_cast<const char*>(data), size), zeros);
  uint64_t hlen = header.size();
  std::string file = "LGNNERF\n";
  file.append(reinterpret_cast<const char*>(&hlen), 8);
  file += header;
  file.append(zeros, '\0');
  Snapshot s;
  try {
    s = parse_snapshot(file, "fuzz.lnerf");
  } catch (const std::exception&) {
    return 0;  // refused with a message
  }
  Snapshot t;
  try {
    t = parse_snapshot(encode_snapshot(s), "re-encoded.lnerf");
  } catch (const std::exception& e) {
    LGN_FUZZ_CHECK(false, e.what());
  }
  LGN_FUZZ_CHECK(t.aabb.min == s.aabb.min && t.aabb.max == s.aabb.max && t.step == s.step, "box and step");
  LGN_FUZZ_CHECK(
      t.normalisation.scale == s.normalisation.scale && t.normalisation.offset == s.normalisation.offset,
      "normalisation");
  LGN_FUZZ_CHECK(t.config == s.config && t.occ.res == s.occ.res, "configuration");
  return 0;
}
