// Progress display; see progress.h.
#include "host/util/progress.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lorgnette {
namespace {
std::string format_seconds(double s) {
  if (!std::isfinite(s) || s < 0) return "--:--";
  int t = static_cast<int>(s + 0.5);
  return t >= 3600 ? fmt::format("{}:{:02}:{:02}", t / 3600, t / 60 % 60, t % 60)
                   : fmt::format("{:02}:{:02}", t / 60, t % 60);
}
}  // namespace

Progress::Progress(std::string label, double total, std::string unit)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      total_(total),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_),
      tty_(isatty(2) != 0) {}

double Progress::elapsed_seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::update(double done, const std::string& info) {
  auto now = std::chrono::steady_clock::now();
  double since = std::chrono::duration<double>(now - last_draw_).count();
  if (drawn_ && since < (tty_ ? 0.1 : 5.0)) return;
  last_draw_ = now;
  draw(done, info, false);
}

void Progress::finish(const std::string& info) { draw(total_, info, true); }

void Progress::draw(double done, const std::string& info, bool final_line) {
  drawn_ = true;
  double el = elapsed_seconds();
  double frac = total_ > 0 ? std::clamp(done / total_, 0.0, 1.0) : 0.0;
  double eta = frac > 0 ? el * (1 - frac) / frac : NAN;
  const int width = 24;
  int filled = static_cast<int>(frac * width);
  std::string bar = std::string(filled, '#') + std::string(width - filled, '.');
  std::string line = fmt::format("{:<8} [{}] {:3.0f}% {}/{} {} | {} elapsed, ETA {} | {}", label_, bar,
                                 100 * frac, static_cast<long long>(done), static_cast<long long>(total_),
                                 unit_, format_seconds(el), format_seconds(eta), info);
  if (tty_) {
    std::fprintf(stderr, "\r\033[2K%s%s", line.c_str(), final_line ? "\n" : "");
  } else {
    std::fprintf(stderr, "%s\n", line.c_str());
  }
  std::fflush(stderr);
}

}  // namespace lorgnette
