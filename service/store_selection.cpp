// Store selection for `serve --db` (store_selection.h).
#include "service/store_selection.h"

#include <regex>

#include "service/postgres_store.h"
#include "service/sqlite_store.h"

namespace lorgnette::service {

bool is_postgres_conninfo(const std::string& db) {
  // libpq's two forms: a URI with either of its schemes, or "keyword = value" pairs.
  static const std::regex keywords(R"(^\s*[A-Za-z_]+\s*=)");
  return db.rfind("postgresql://", 0) == 0 || db.rfind("postgres://", 0) == 0 ||
         std::regex_search(db, keywords);
}

std::unique_ptr<JobStore> open_job_store(const std::string& db) {
  return is_postgres_conninfo(db) ? open_postgres_store(db) : open_sqlite_store(db);
}

std::string describe_job_store(const std::string& db) {
  return is_postgres_conninfo(db) ? describe_conninfo(db) : "sqlite '" + db + "'";
}

}  // namespace lorgnette::service
