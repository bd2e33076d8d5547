// One idempotent stage of a job: it writes into a temporary folder beside its output and renames
// that folder into place when it succeeds. An output that exists is complete (rename is atomic), so
// a stage run again after success is skipped, and a stage killed halfway leaves only the temporary
// folder, which the next run removes before starting over.
#pragma once
#include <filesystem>
#include <functional>

namespace lorgnette::service {

// The temporary folder run_stage uses for `output`.
std::filesystem::path partial_path(const std::filesystem::path& output);

// Runs `work(temporary folder)` and renames the folder to `output`; returns false (and runs nothing)
// when `output` already exists. When `work` throws, the temporary folder is removed and the
// exception passes on; `output` is never created half-written.
bool run_stage(const std::filesystem::path& output,
               const std::function<void(const std::filesystem::path&)>& work);

}  // namespace lorgnette::service
