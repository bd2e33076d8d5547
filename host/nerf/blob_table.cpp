#include "host/nerf/blob_table.h"

#include <fmt/format.h>

#include "host/nerf/snapshot.h"

namespace lorgnette::nerf {
namespace {

using nlohmann::json;

uint64_t entry_uint(const json& entry, const char* key) {
  const json& v = entry.at(key);
  if (!v.is_number_unsigned())
    throw BlobTableError(fmt::format("'blobs.{}' must be an integer, found {}", key, v.dump()));
  return v.get<uint64_t>();
}

}  // namespace

std::string checksum_hex(uint64_t checksum) { return fmt::format("{:016x}", checksum); }

json blob_table(const std::vector<BlobRef>& blobs) {
  json table = json::array();
  uint64_t off = 0;
  for (const BlobRef& b : blobs) {
    table.push_back(
        {{"name", b.name},
         {"offset", off},
         {"bytes", b.bytes},
         {"fnv1a64", checksum_hex(snapshot_checksum({static_cast<const char*>(b.data), b.bytes}))}});
    off += b.bytes;
  }
  return table;
}

void append_blobs(std::string& out, const std::vector<BlobRef>& blobs) {
  size_t total = 0;
  for (const BlobRef& b : blobs) total += b.bytes;
  out.reserve(out.size() + total);
  for (const BlobRef& b : blobs) out.append(static_cast<const char*>(b.data), b.bytes);
}

const char* find_blob(std::string_view file, size_t data_start, const json& table, const std::string& name,
                      size_t expected_bytes) {
  if (!table.is_array()) throw BlobTableError("'blobs' must be a list");
  for (const json& b : table) {
    if (!b.is_object()) throw BlobTableError("each entry of 'blobs' must be an object");
    if (b.value("name", "") != name) continue;
    const uint64_t off = entry_uint(b, "offset"), bytes = entry_uint(b, "bytes");
    if (bytes != expected_bytes)
      throw BlobTableError(fmt::format("blob '{}' has {} bytes, the header's configuration needs {}", name,
                                       bytes, expected_bytes));
    if (data_start > file.size() || off > file.size() - data_start || bytes > file.size() - data_start - off)
      throw BlobTableError(fmt::format("file is truncated: blob '{}' ends past the end of the file", name));
    const char* p = file.data() + data_start + off;
    if (checksum_hex(snapshot_checksum({p, bytes})) != b.value("fnv1a64", ""))
      throw BlobTableError(fmt::format("checksum mismatch in blob '{}'", name));
    return p;
  }
  if (expected_bytes == 0) return nullptr;
  throw BlobTableError("blob '" + name + "' is missing");
}

}  // namespace lorgnette::nerf
