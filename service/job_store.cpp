// Job states by name and the clock the store uses (job_store.h).
#include "service/job_store.h"

#include <chrono>
#include <stdexcept>

namespace lorgnette::service {

const char* to_string(JobState s) {
  switch (s) {
    case JobState::Created:
      return "created";
    case JobState::Queued:
      return "queued";
    case JobState::Running:
      return "running";
    case JobState::Failed:
      return "failed";
    case JobState::Finished:
      return "finished";
  }
  return "unknown";
}

JobState job_state_from_string(const std::string& s) {
  for (JobState v :
       {JobState::Created, JobState::Queued, JobState::Running, JobState::Failed, JobState::Finished})
    if (s == to_string(v)) return v;
  throw std::runtime_error("unknown job state '" + s + "' (created, queued, running, failed, finished)");
}

int64_t unix_now() {
  return std::chrono::duration_cast<std::chrono::seconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace lorgnette::service
