// The viewer's engine, independent of the network: the model and catalogue, one render thread that
// owns the OpenCL runtime and serves every client round-robin, and the per-client state.
//
// Progressive rendering, per client:
// - any change (camera, size, glasses, frame, nudge) bumps the client's generation; the next unit of
//   work for it is a coarse frame (1/coarse_divisor resolution, coarser marching step, 1 surface
//   sample per pixel) of the NEWEST state: a slot, not a queue, so latency never piles up;
// - once the client is idle (no input for idle_ms and not dragging) its full frame is rendered in
//   bands of rows (full resolution and step, 4 surface samples), one band per turn, and sent whole;
//   new input drops the partial frame;
// - a snapshot renders the state at request time in bands at higher quality and goes out as PNG.
// Fairness: the render thread takes one unit (a coarse frame or one band) per client in turn.
//
// Memory per client (stated, bounded): its state (< 4 KB), one full frame being refined and one
// snapshot being rendered (3 bytes per pixel each; the viewport is at most 1920x1080), and in the
// connection at most one pending view frame and one pending snapshot besides the one being written
// (frame_bytes_bound()). Surface passes are shared through a small cache (frame_assets.h).
#pragma once
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "host/cl/runtime.h"
#include "viewer/catalogue.h"
#include "viewer/frame_assets.h"
#include "viewer/image_codec.h"
#include "viewer/orbit_control.h"
#include "viewer/protocol.h"

namespace lorgnette::viewer {

// What a connection implements so the service can answer (called from the render, fit and network
// threads; implementations must be thread-safe and must not block).
class ClientSink {
 public:
  virtual ~ClientSink() = default;
  virtual void send_text(std::string text) = 0;
  // A binary frame; kind says whether it may replace a pending one of the same slot.
  virtual void send_frame(FrameKind kind, std::vector<uint8_t> bytes) = 0;
};

struct ViewerConfig {
  std::string model_path;
  std::vector<FrameEntry> catalogue;
  cl::RuntimeOptions runtime;
  uint32_t width = 854, height = 480;  // default viewport
  uint32_t coarse_divisor = 3;
  float coarse_step_scale = 2.0f;
  int coarse_surface_spp = 1, full_surface_spp = 4, snapshot_surface_spp = 16;
  uint32_t snapshot_spp = 2;  // NeRF rays per pixel in snapshots
  uint32_t band_rows = 96;
  int idle_ms = 120;
  int jpeg_quality_coarse = 70, jpeg_quality_full = 90;
  FitWorkerConfig fit;  // runtime and model_path are filled from the fields above
  ProtocolLimits limits{32, 1920, 1080, 10.0, 10.0};
};

struct ViewerStats {
  uint64_t coarse_frames = 0, full_frames = 0, snapshots = 0, bands = 0, errors_sent = 0, messages = 0;
  size_t clients = 0;
};

class ViewerService {
 public:
  using ClientId = uint64_t;
  using Clock = std::chrono::steady_clock;

  // Loads the model and the catalogue's frames (throws with the reason) and starts the render thread.
  explicit ViewerService(ViewerConfig config);
  ~ViewerService();
  ViewerService(const ViewerService&) = delete;
  ViewerService& operator=(const ViewerService&) = delete;

  // A new client gets an id and an "info" message (catalogue, limits, viewport) and a first frame.
  ClientId connect(std::shared_ptr<ClientSink> sink);
  // Drops the client's state and any frame in progress for it (the render thread checks between bands).
  void disconnect(ClientId id);
  // One text message from a client: parsed, validated and acted on; failures answer with an error.
  void handle_text(ClientId id, std::string_view text);
  // Binary messages are not part of the protocol: an error reply.
  void handle_binary(ClientId id, size_t bytes);

  const FrameAssets& assets() const { return *assets_; }
  nlohmann::json info() const;
  ViewerStats stats() const;
  // Upper bound of the bytes one client can hold (state + frames in progress + pending frames).
  size_t client_bytes_bound() const;
  std::string device_name() const { return device_name_; }

 private:
  struct Client;
  struct Work;
  void render_loop();
  bool pick_work(Work& w, Clock::time_point& wake);
  void run_work(Work& w);
  void render_coarse(Work& w);
  void render_band(Work& w);  // one band of a full frame or a snapshot
  std::shared_ptr<const mesh::SurfacePass> glasses_for(const Work& w);
  struct Replies {
    std::vector<std::string> texts;
    uint64_t errors = 0;
    void error(std::string text) { texts.push_back(std::move(text)), errors++; }
  };
  void apply(Client& c, const ClientMessage& m, Replies& replies);
  void broadcast_fit(const nlohmann::json& event, uint32_t frame);
  nlohmann::json state_json(Client& c);
  void reply_error(ClientId id, const ProtocolError& e, const std::string& type);
  std::shared_ptr<Client> find(ClientId id);

  ViewerConfig config_;
  struct Engine;  // the OpenCL runtime, model and renderer (render thread only)
  std::unique_ptr<Engine> engine_;
  std::string device_name_;
  OrbitFrame orbit_;
  OrbitLimits limits_;
  std::unique_ptr<FrameAssets> assets_;

  mutable std::mutex mutex_;  // clients_, rr_, stats_
  std::condition_variable cv_;
  std::map<ClientId, std::shared_ptr<Client>> clients_;
  ClientId next_id_ = 1, rr_ = 0;
  ViewerStats stats_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace lorgnette::viewer
