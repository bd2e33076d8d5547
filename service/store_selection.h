// `serve --db`: which job store a value names. A PostgreSQL connection string (a postgresql:// or
// postgres:// URI, or libpq keywords such as "host=... dbname=...") opens the PostgreSQL store;
// anything else is the SQLite file's path (the default, DATA/jobs.sqlite). A file whose name
// starts like "word=" is written as ./word=... to read as a path.
#pragma once
#include <memory>
#include <string>

#include "service/job_store.h"

namespace lorgnette::service {

bool is_postgres_conninfo(const std::string& db);
std::unique_ptr<JobStore> open_job_store(const std::string& db);
// For logs: the SQLite path, or the PostgreSQL database without its password.
std::string describe_job_store(const std::string& db);

}  // namespace lorgnette::service
