// The catalogue's frames as the viewer holds them: each frame's canonical mesh and sizes (loaded once
// at start, with a thumbnail), its placement and where it came from (a file, a fit, or a rough
// stand-in when the fit failed or fitting is off), and the surface passes built from it. A frame with
// no placement is fitted on a worker thread with its own OpenCL runtime and copy of the model (so
// renders go on meanwhile); the worker reports progress through a callback and the fit is cached
// beside the frame (<frame>.placement.json) when that file does not exist yet. A placement file
// that cannot be read, or was fitted for another glasses file (its content hash), is not used: the
// page shows why and the frame is fitted instead (a warning in the server's log would go unseen).
#pragma once
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "fit/fit_job.h"
#include "fit/placement_json.h"
#include "host/cl/runtime.h"
#include "mesh/glasses.h"
#include "mesh/surface_pass.h"
#include "viewer/catalogue.h"
#include "viewer/orbit_control.h"

namespace lorgnette::viewer {

enum class PlacementStatus { kNone, kReady, kFitting };

struct FrameState {
  PlacementStatus status = PlacementStatus::kNone;
  std::shared_ptr<const fit::PlacementFile> placement;  // when kReady
  std::string source;                                   // "file", "fit", "rough (...)"
  uint64_t version = 0;                                 // bumps whenever the placement changes
  std::string message;                                  // last fit message
};

// The viewer's fits: `lorgnette fit`'s settings (fit_options(), fit/fit_job.h), run on the worker
// with its own runtime and copy of the model.
struct FitWorkerConfig {
  bool enabled = true;  // false: frames without a placement get the rough stand-in at once
  fit::FitSettings settings;
  cl::RuntimeOptions runtime;
  std::string model_path;
};

// The words for a fit stage's name (FitOptions::on_stage), as the page shows them; the name itself
// when it has none.
std::string fit_stage_label(const std::string& stage);

// Fit events for the clients: state "started", "progress" (elapsed seconds, the stage's name, its
// words and how many stages have started), "done", "failed".
using FitListener = std::function<void(const nlohmann::json& event, uint32_t frame)>;

class FrameAssets {
 public:
  // Loads every frame (throws naming a frame that cannot be loaded) and renders the thumbnails.
  FrameAssets(std::vector<FrameEntry> catalogue, OrbitFrame orbit, std::array<float, 3> box_min,
              std::array<float, 3> box_max, FitWorkerConfig fit, FitListener listener);
  ~FrameAssets();  // stops the fit worker (waits for a running fit)

  size_t size() const { return entries_.size(); }
  const FrameEntry& entry(size_t i) const { return entries_.at(i); }
  const mesh::Glasses& glasses(size_t i) const { return *glasses_.at(i); }
  const std::vector<uint8_t>& thumbnail_jpeg(size_t i) const { return thumbnails_.at(i); }

  // Current state; the first call for a frame reads its placement file or queues its fit.
  FrameState state(uint32_t i);
  // Name, sizes, PD and placement source of frame i (for the client's state message).
  nlohmann::json describe(uint32_t i);
  nlohmann::json catalogue_json() const;

  // The surface pass for frame i with a nudge, or nullptr while it has no placement. Passes are
  // cached (a few, least recently used) and shared between clients with the same frame and nudge.
  std::shared_ptr<const mesh::SurfacePass> pass(uint32_t i, const Nudge& nudge);

 private:
  void request(uint32_t i);                            // under mutex_
  void set_rough(uint32_t i, const std::string& why);  // under mutex_
  void fit_loop();
  void run_fit(uint32_t i);
  // The fit's outcome for frame i: its placement (cached beside the frame when none is there) or,
  // when it failed, the rough stand-in with the reason; the "fit" message for the listeners.
  nlohmann::json store_fit(uint32_t i, std::future<fit::PlacementFile>& work);

  std::vector<FrameEntry> entries_;
  std::vector<std::unique_ptr<mesh::Glasses>> glasses_;
  std::vector<std::vector<uint8_t>> thumbnails_;
  OrbitFrame orbit_;
  std::array<float, 3> box_min_, box_max_;
  FitWorkerConfig fit_;
  FitListener listener_;

  std::mutex mutex_;
  std::condition_variable cv_;
  std::vector<FrameState> states_;
  std::vector<bool> requested_;
  std::deque<uint32_t> fit_queue_;
  bool stop_ = false;
  struct CachedPass {
    std::string key;
    std::shared_ptr<const mesh::SurfacePass> pass;
  };
  std::deque<CachedPass> passes_;  // most recent first
  std::thread fit_thread_;
};

}  // namespace lorgnette::viewer
