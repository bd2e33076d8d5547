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
  };
  return list;
}

}  // namespace lorgnette::service
