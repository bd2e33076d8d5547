// The blob table of Lorgnette's binary files (the .lnerf snapshot, snapshot.h, and the training
// checkpoint, checkpoint.h): after the JSON header come the blobs, which the header lists as
// {"name", "offset" (from the end of the header), "bytes", "fnv1a64" (16 hex digits)}. One owner for
// writing and reading that table, so both formats check sizes, bounds and checksums alike; each
// format keeps its own prefix, header and error message (it wraps BlobTableError's reason).
#pragma once
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace lorgnette::nerf {

struct BlobRef {
  std::string name;
  const void* data;
  size_t bytes;
};

// Why a blob cannot be read (missing, of the wrong size, past the file's end, a checksum mismatch,
// a malformed entry); the format's reader turns it into its own "corrupt" message.
struct BlobTableError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A checksum as the tables and headers store it: 16 lower-case hex digits.
std::string checksum_hex(uint64_t checksum);

// The table for `blobs` laid out one after another in this order.
nlohmann::json blob_table(const std::vector<BlobRef>& blobs);
// `blobs` appended to `out` in the table's order.
void append_blobs(std::string& out, const std::vector<BlobRef>& blobs);

// The blob `name` of `file` (its data starting at `data_start`), checked to hold `expected_bytes`,
// to lie inside the file and to match its checksum; nullptr when the table has no such blob and
// expected_bytes is 0. Throws BlobTableError otherwise.
const char* find_blob(std::string_view file, size_t data_start, const nlohmann::json& table,
                      const std::string& name, size_t expected_bytes);

}  // namespace lorgnette::nerf
