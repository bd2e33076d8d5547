// The job store's schema as one ordered list of migrations, shared by every store implementation
// (portable SQL: TEXT, BIGINT, DOUBLE PRECISION). A database records the migrations it has had in
// schema_migrations; opening applies the missing ones in order, each in its own transaction, and
// refuses a database made by a newer Lorgnette (version above latest_schema_version()) rather than guess.
#pragma once
#include <string>
#include <vector>

namespace lorgnette::service {

struct Migration {
  int version;
  std::vector<std::string> statements;
};

const std::vector<Migration>& migrations();

// The captures table's columns in the order every store reads and writes them.
inline constexpr const char* kCaptureColumns =
    "id, token_hash, state, stage, message, percent, attempts, upload_kind, created_unix, updated_unix, "
    "queued_unix, executor_job_id, owner, owner_home, heartbeat_ms";
inline int latest_schema_version() { return migrations().back().version; }

}  // namespace lorgnette::service
