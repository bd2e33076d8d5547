// `lorgnette serve`: the job store, the executor (local or Slurm), the API and its HTTP server wired
// together, and the loop that drives them: the executor's tick (workers started, ended, progress recorded)
// several times a second and the retention sweep every minute. On SIGINT/SIGTERM it stops accepting,
// asks the workers to stop after their current step (their jobs go back to the queue) and waits up
// to `grace_seconds` for them; whatever still runs then is killed and reconciled at the next start.
#pragma once
#include <cstdint>
#include <string>

#include "service/api.h"
#include "service/http_server.h"
#include "service/local_executor.h"
#include "service/slurm_executor.h"

namespace lorgnette::service {

struct ServeOptions {
  std::string data_dir;
  std::string db;  // SQLite file or PostgreSQL connection string (store_selection.h); "" = <data>/jobs.sqlite
  std::string executor = "local";  // local | slurm
  HttpOptions http;
  LocalExecutorOptions local;  // its data_dir is set from data_dir
  SlurmExecutorOptions slurm;  // its data_dir, max_attempts, worker_exe and global_flags are local's
  ApiOptions api;              // its data_dir is set from data_dir
  std::string port_file;       // when set, the bound port is written there (for --port 0)
  double grace_seconds = 20.0;
  double lease_seconds = 60.0;  // a running job's lease (LeaseSettings in executor.h)
};

// Runs until interrupted; throws with the reason when it cannot start.
void run_serve(ServeOptions options);

}  // namespace lorgnette::service
