// `lorgnette job run <capture folder>`: one process per job runs its stages in order, capture ->
// train -> fit (one per catalogue frame), each through run_stage (stage.h) so a stage already done
// is skipped and a killed one leaves nothing half-written, and reports progress.json as it goes.
// The product's own error message (e.g. "film from ear to ear") becomes the failed job's message.
#pragma once
#include <filesystem>

#include "host/cl/runtime.h"

namespace lorgnette::service {

// How `job run` ends, as its exit status: the executor retries only Interrupted (and workers that
// died by a signal), never Failed, which is the capture's own problem.
enum class JobOutcome : int { Finished = 0, Failed = 1, Interrupted = 75 };

// Runs (or resumes) the job in `folder` with the settings in its job.json. Never throws: a failure is
// written to progress.json (state "failed", its message) and returned.
JobOutcome run_job(const std::filesystem::path& folder, const cl::RuntimeOptions& runtime);

}  // namespace lorgnette::service
