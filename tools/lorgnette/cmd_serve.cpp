// `lorgnette serve --data DIR [--catalogue DIR]`: the try-on service (service/serve.h): shoppers'
// captures in, trained heads and fitted frames out, through the /api/v1 JSON API (docs/service.md).
#include <fstream>
#include <sstream>

#include "host/util/bounds.h"
#include "service/serve.h"
#include "service/tokens.h"
#include "tools/lorgnette/command.h"

namespace lorgnette::cli {
namespace {

struct ServeArgs {
  service::ServeOptions o;
  std::string admin_token_file;
  int retention_days = 30;
  int port = 8080;  // wider than the port's type, so 70000 is refused with the range, not wrapped
  uint64_t max_upload_mb = 500;
};

// Every number against host/util/bounds.h before anything is created under --data.
void validate(const ServeArgs& a) {
  namespace b = bounds;
  check_bound(b::kWorkers, a.o.local.slots);
  check_bound(b::kPort, a.port);
  check_bound(b::kRetentionDays, a.retention_days);
  check_bound(b::kMaxUploadMb, double(a.max_upload_mb));
  check_bound(b::kMaxAttempts, a.o.local.max_attempts);
  a.o.api.job.validate();
}

std::string read_admin_token(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read --admin-token-file '" + path + "'");
  std::string token;
  std::getline(in, token);
  if (token.size() < 32)
    throw std::runtime_error("the admin token in '" + path +
                             "' is shorter than 32 characters: use e.g. `openssl rand -hex 32`");
  return token;
}

void run(ServeArgs& a, GlobalOptions& global) {
  validate(a);
  a.o.http.port = uint16_t(a.port);
  if (!a.admin_token_file.empty())
    a.o.api.admin_token_hash = service::sha256_hex(read_admin_token(a.admin_token_file));
  a.o.api.retention_seconds = int64_t(a.retention_days) * 86400;
  a.o.api.max_upload_bytes = a.max_upload_mb << 20;
  if (!global.kernel_cache.empty()) a.o.local.global_flags = {"--kernel-cache", global.kernel_cache};
  if (!global.device.empty())
    a.o.local.global_flags.insert(a.o.local.global_flags.end(), {"--device", global.device});
  service::run_serve(a.o);
}

void add_serve(CLI::App& app, GlobalOptions& global) {
  auto a = std::make_shared<ServeArgs>();
  auto& o = a->o;
  auto* cmd = app.add_subcommand("serve",
                                 "the try-on service: capture uploads -> trained head + fitted frames "
                                 "(JSON API /api/v1, docs/service.md)");
  cmd->add_option("--data", o.data_dir, "data folder: captures (uploads, models, fits) and the job store")
      ->required();
  cmd->add_option("--catalogue", o.api.job.catalogue,
                  "folder of the shop's frames, fitted on every finished head");
  cmd->add_option("--db", o.db,
                  "job store: a SQLite file (default: DATA/jobs.sqlite) or a PostgreSQL connection string "
                  "(postgresql://user@host/db, or 'host=... dbname=...')");
  cmd->add_option("--executor", o.executor,
                  "where jobs run: local (worker processes on this machine) or slurm (one sbatch job each)")
      ->check(CLI::IsMember({"local", "slurm"}))
      ->capture_default_str();
  cmd->add_option("--slurm-partition", o.slurm.partition,
                  "Slurm partition for the jobs (default: the cluster's)");
  cmd->add_option("--slurm-gres", o.slurm.gres,
                  "generic resources per job, passed as sbatch --gres (e.g. gpu:1)");
  cmd->add_option("--slurm-arg", o.slurm.sbatch_args,
                  "one more sbatch option as --name=value (repeatable; e.g. --slurm-arg=--time=02:00:00)")
      ->allow_extra_args(false);
  cmd->add_option("--slurm-bin-dir", o.slurm.bin_dir,
                  "folder of sbatch, squeue, scontrol, scancel (default: $PATH)");
  cmd->add_option("--slurm-poll-seconds", o.slurm.poll_seconds, "how often squeue is asked")
      ->check(CLI::Range(0.1, 600.0))
      ->capture_default_str();
  cmd->add_option("--lease-seconds", o.lease_seconds,
                  "a running job's lease: renewed by its server every sixth of it; once expired (the server "
                  "died) another server on the same database takes the job over")
      ->check(CLI::Range(1.0, 3600.0))
      ->capture_default_str();
  cmd->add_option("--workers", o.local.slots, "local worker slots (one per GPU, or one on a CPU)")
      ->capture_default_str();
  cmd->add_option("--host", o.http.host, "address to bind (anything but loopback: behind a TLS proxy)")
      ->capture_default_str();
  cmd->add_option("--port", a->port, "port (0: any free one)")->capture_default_str();
  cmd->add_option("--port-file", o.port_file, "write the bound port to this file");
  cmd->add_option("--admin-token-file", a->admin_token_file,
                  "file whose first line is the admin token (queue, metrics)");
  cmd->add_option("--retention-days", a->retention_days, "delete captures and all made from them after this")
      ->capture_default_str();
  cmd->add_option("--max-upload-mb", a->max_upload_mb, "largest upload (one video or photo)")
      ->capture_default_str();
  cmd->add_option("--max-attempts", o.local.max_attempts, "worker starts per job before a killed job fails")
      ->capture_default_str();
  cmd->add_option("--train-steps", o.api.job.train_steps,
                  "training budget in steps (0: the product's default)");
  cmd->add_option("--train-batch-log2", o.api.job.train_batch_log2,
                  "log2 samples per step (0: the device's)");
  cmd->add_option("--capture-fps", o.api.job.capture_fps, "video frames sampled per second")
      ->capture_default_str();
  cmd->add_option("--capture-max-side", o.api.job.capture_max_side, "capture frame size (longer side, px)")
      ->capture_default_str();
  cmd->add_option("--fit-views", o.api.job.fit_views, "views rendered per fit")->capture_default_str();
  cmd->add_option("--fit-resolution", o.api.job.fit_resolution, "fit view size (px)")->capture_default_str();
  cmd->add_option("--tryon-views", o.api.job.tryon_views, "try-on views rendered per fitted frame")
      ->capture_default_str();
  cmd->add_option("--tryon-size", o.api.job.tryon_size, "try-on view side (px)")->capture_default_str();
  cmd->callback([a, &global] { run(*a, global); });
}

}  // namespace
LGN_REGISTER_COMMAND(96, add_serve);
}  // namespace lorgnette::cli
