// The job store in SQLite: one file in the data folder, WAL mode (readers never wait for the
// writer), a busy timeout for a second process on the same file, and the schema's migrations applied
// on open (schema.h). One connection behind a mutex: the server's threads share it.
#pragma once
#include <memory>
#include <string>

#include "service/job_store.h"

namespace lorgnette::service {

// Opens (creating when absent) the database at `path`. Throws with the path and SQLite's message
// when it cannot, or when the file was made by a newer Lorgnette.
std::unique_ptr<JobStore> open_sqlite_store(const std::string& path);

}  // namespace lorgnette::service
