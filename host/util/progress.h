// A one-line progress display for long work on standard error: bar, count, rate, ETA and free
// text (loss, PSNR). Redrawn at most 10 times a second; plain lines when stderr is not a terminal.
#pragma once
#include <chrono>
#include <string>

namespace lorgnette {

class Progress {
 public:
  Progress(std::string label, double total, std::string unit = "");
  // done: work completed so far (same unit as total); info: e.g. "loss 0.0123  PSNR 27.1 dB".
  void update(double done, const std::string& info = "");
  void finish(const std::string& info = "");
  double elapsed_seconds() const;

 private:
  void draw(double done, const std::string& info, bool final_line);
  std::string label_, unit_;
  double total_;
  std::chrono::steady_clock::time_point start_, last_draw_;
  bool tty_;
  bool drawn_ = false;
};

}  // namespace lorgnette
