// The demo's report: `report.json` (ARCHITECTURE.md: per-stage wall and CPU seconds, the machine, held-out
// PSNR, the fit's placement fields with ok and pd_mm, device, version) and `report.html`, a page that shows
// those numbers next to the pictures the demo wrote (orbit video, contact sheet, fit debug views).
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace lorgnette::demo {

struct StageTime {
  std::string name;
  double seconds = 0.0;      // wall
  double cpu_seconds = 0.0;  // the process's user + system time over all threads (host/util/machine.h)
};

struct DemoReport {
  std::string version;
  std::string device;
  std::string machine;  // CPU, logical CPUs, memory and load at the start (MachineInfo::summary)
  std::vector<StageTime> stages;
  double psnr = 0.0, ssim = 0.0;  // held-out views of the synthetic head
  int heldout_views = 0;
  uint64_t train_steps = 0;
  double train_seconds = 0.0;
  std::string train_budget;  // which budget applied (host/nerf/train_budget.h)
  double model_mb = 0.0;
  nlohmann::json fit;           // placement.json contents (ok, pd_mm, residuals, ...)
  nlohmann::json ground_truth;  // errors of the fit against the synthetic head's known landmarks
  nlohmann::json config;        // what the demo ran with (sizes, steps, frame)
  // Files relative to the report's directory, shown in report.html.
  std::string orbit_mp4, contact_sheet, glasses_preview, loss_chart;
  std::vector<std::string> debug_views, heldout_images;
  bool ok = false;
  std::string message;  // what went wrong when !ok

  nlohmann::json to_json() const;
};

// Writes report.json and report.html into dir (atomically).
void write_report(const std::string& dir, const DemoReport& report);

// The HTML page alone (exposed for tests).
std::string render_report_html(const DemoReport& report);

}  // namespace lorgnette::demo
