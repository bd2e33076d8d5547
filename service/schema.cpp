// The migrations (schema.h). Append new ones; never edit one that has shipped.
#include "service/schema.h"

namespace lorgnette::service {

const std::vector<Migration>& migrations() {
  static const std::vector<Migration> list = {
      {1,
       {"CREATE TABLE captures ("
        " id TEXT PRIMARY KEY,"
        " token_hash TEXT NOT NULL,"
        " state TEXT NOT NULL,"
        " stage TEXT NOT NULL DEFAULT '',"
        " message TEXT NOT NULL DEFAULT '',"
        " percent DOUBLE PRECISION NOT NULL DEFAULT 0,"
        " attempts INTEGER NOT NULL DEFAULT 0,"
        " upload_kind TEXT NOT NULL DEFAULT '',"
        " created_unix BIGINT NOT NULL,"
        " updated_unix BIGINT NOT NULL,"
        " queued_unix BIGINT NOT NULL DEFAULT 0)",
        "CREATE INDEX captures_by_state ON captures (state, queued_unix)",
        "CREATE INDEX captures_by_age ON captures (created_unix)"}},
      // The id of a job's worker in an external scheduler (a Slurm job id), so that a restarted
      // server re-attaches the running worker instead of starting a second one.
      {2, {"ALTER TABLE captures ADD COLUMN executor_job_id TEXT NOT NULL DEFAULT ''"}},
      // Who runs a job and until when (job_store.h: owner, home, lease), so that several servers
      // share one database: rows from before have no owner and a lease long expired, so the first
      // server to start adopts them, as every server did before.
      {3,
       {"ALTER TABLE captures ADD COLUMN owner TEXT NOT NULL DEFAULT ''",
        "ALTER TABLE captures ADD COLUMN owner_home TEXT NOT NULL DEFAULT ''",
        "ALTER TABLE captures ADD COLUMN heartbeat_ms BIGINT NOT NULL DEFAULT 0"}},
  };
  return list;
}

}  // namespace lorgnette::service
