// `lorgnette job run FOLDER`: runs (or resumes) one service job in its capture folder (service/);
// the server's executors start it as a child process so a crash fails one job, never the server.
// Exit status 0 finished, 1 failed (progress.json says why), 75 interrupted (the job can run again).
#include "service/job_runner.h"
#include "tools/lorgnette/command.h"

namespace lorgnette::cli {
namespace {

void add_job(CLI::App& app, GlobalOptions& global) {
  auto* job = app.add_subcommand("job", "service jobs (run by `lorgnette serve`'s executors)");
  job->require_subcommand(1);
  auto folder = std::make_shared<std::string>();
  auto* run = job->add_subcommand("run",
                                  "run a capture folder's job: capture -> train -> fit, resuming "
                                  "after its last finished stage; progress in progress.json");
  run->add_option("FOLDER", *folder, "the capture's folder (holds job.json and upload/)")
      ->required()
      ->check(CLI::ExistingDirectory);
  run->callback([folder, &global] {
    const service::JobOutcome outcome = service::run_job(*folder, global.runtime());
    if (outcome != service::JobOutcome::Finished) throw ExitStatus{static_cast<int>(outcome)};
  });
}

}  // namespace
LGN_REGISTER_COMMAND(95, add_job);
}  // namespace lorgnette::cli
