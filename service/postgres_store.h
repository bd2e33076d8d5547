// The job store in PostgreSQL, for deployments where several servers (hosts) share one queue:
// libpq, the same schema and migrations as SQLite (schema.h), and a claim that takes the oldest
// queued row with FOR UPDATE SKIP LOCKED in one statement, so two servers never take the same job
// and neither waits on a row the other is claiming. One connection behind a mutex per store.
#pragma once
#include <memory>
#include <string>

#include "service/job_store.h"

namespace lorgnette::service {

// Opens the database named by a libpq connection string: a URI (postgresql://user@host/db,
// postgres://...) or keywords ("host=/run/postgresql dbname=lorgnette"). Migrates it; migrations
// of several servers starting at once are serialised by an advisory lock. Throws with the
// connection's description (never its password) and PostgreSQL's message when it cannot.
std::unique_ptr<JobStore> open_postgres_store(const std::string& conninfo);

// The connection string's database, host and user, for logs and errors: never the password.
std::string describe_conninfo(const std::string& conninfo);

}  // namespace lorgnette::service
