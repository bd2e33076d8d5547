// What every executor shares (see executor.h).
#include "service/executor.h"

#include <signal.h>

#include "service/progress.h"

namespace lorgnette::service {

void refresh_progress(CaptureRecord& r, const std::filesystem::path& capture_folder) {
  if (auto p = read_progress(capture_folder / "progress.json")) {
    r.stage = p->stage;
    r.percent = p->percent;
    r.message = p->message;
  }
}

bool retryable_signal(int sig) { return sig == SIGKILL || sig == SIGTERM || sig == SIGINT; }

}  // namespace lorgnette::service
