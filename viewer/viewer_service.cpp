// The viewer's engine: clients, messages, the render thread and its round-robin scheduling of
// coarse frames and refinement bands (viewer_service.h).
#include "viewer/viewer_service.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "host/dataset/dataset.h"
#include "host/nerf/model.h"
#include "host/render/render_settings.h"
#include "host/render/renderer.h"
#include "host/render/view_plan.h"
#include "host/util/version.h"
#include "mesh/frame_surfaces.h"

namespace lorgnette::viewer {
namespace fs = std::filesystem;

struct ViewerService::Engine {
  cl::Runtime rt;
  nerf::NerfModel model;
  render::Renderer renderer;
  JpegEncoder jpeg;
  Engine(const cl::RuntimeOptions& o, const std::string& path)
      : rt(o), model(nerf::NerfModel::load(rt, path)), renderer(rt) {}
};

// A frame being refined (full view or snapshot), rendered band by band. Render thread only.
struct Refine {
  bool active = false;
  uint64_t gen = 0;
  Camera cam{};
  std::shared_ptr<const mesh::SurfacePass> pass;
  uint32_t next_row = 0, seq = 0;
  Rgb8 image;
  double seconds = 0;
};

struct ViewerService::Client {
  ClientId id = 0;
  std::shared_ptr<ClientSink> sink;
  std::mutex m;  // guards the fields up to `snapshot_requested`
  OrbitState orbit;
  uint32_t seq = 0, width = 854, height = 480, frame = 0;
  bool interacting = false, glasses_on = true;
  std::map<uint32_t, Nudge> nudges;  // per catalogue frame
  uint64_t gen = 1, coarse_done = 0, full_done = 0;
  Clock::time_point last_input = Clock::now();
  bool snapshot_requested = false;
  Refine full, snap;  // render thread only
};

struct ViewerService::Work {
  enum Kind { kNone, kCoarse, kFull, kSnapshot } kind = kNone;
  std::shared_ptr<Client> client;
  uint64_t gen = 0;
  OrbitState orbit;
  uint32_t width = 0, height = 0, seq = 0, frame = 0;
  bool glasses_on = true;
  Nudge nudge;
};

namespace {

uint32_t rounded_div(uint32_t v, uint32_t d) { return std::max<uint32_t>(16, (v + d / 2) / d); }

}  // namespace

ViewerService::ViewerService(ViewerConfig config) : config_(std::move(config)) {
  if (config_.catalogue.empty())
    throw std::runtime_error("the viewer needs at least one frame (--glasses or --catalogue)");
  engine_ = std::make_unique<Engine>(config_.runtime, config_.model_path);
  device_name_ = engine_->rt.device().name;
  // The orbit is the one every front end requests (render::OrbitSettings, planned by
  // render::plan_model_orbit): it turns in the capture's view-range frame and is clamped to it,
  // server-side (host/render/view_plan.h).
  std::optional<nerf::ViewRange> range = render::model_view_range(engine_->model);
  render::OrbitPlan plan = render::plan_model_orbit(engine_->model, render::OrbitSettings{}, range);
  for (const auto& note : plan.notes) spdlog::info("view: orbit: {}", note);
  orbit_ = make_orbit_frame(plan.spec);
  limits_ = limits_from_range(range);
  spdlog::info("view: orbit limits yaw [{:.0f}, {:.0f}] deg, pitch [{:.0f}, {:.0f}] deg from the {}",
               limits_.yaw_min, limits_.yaw_max, limits_.pitch_min, limits_.pitch_max, limits_.source);
  FitWorkerConfig fit = config_.fit;
  fit.runtime = config_.runtime;
  fit.model_path = config_.model_path;
  const auto& box = engine_->model.aabb();
  assets_ =
      std::make_unique<FrameAssets>(config_.catalogue, orbit_, box.min, box.max, fit,
                                    [this](const nlohmann::json& e, uint32_t i) { broadcast_fit(e, i); });
  thread_ = std::thread([this] { render_loop(); });
}

ViewerService::~ViewerService() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
  assets_.reset();  // joins the fit worker before the clients go
}

nlohmann::json ViewerService::info() const {
  return {{"type", "info"},
          {"version", version_string()},
          {"model", fs::path(config_.model_path).filename().string()},
          {"device", device_name_},
          {"catalogue", assets_->catalogue_json()},
          {"limits", to_json(limits_)},
          {"viewport", {{"width", config_.width}, {"height", config_.height}}},
          {"max_viewport", {{"width", config_.limits.max_width}, {"height", config_.limits.max_height}}},
          {"coarse_divisor", config_.coarse_divisor},
          {"max_message_bytes", kMaxMessageBytes},
          {"client_bytes_bound", client_bytes_bound()}};
}

ViewerStats ViewerService::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  ViewerStats s = stats_;
  s.clients = clients_.size();
  return s;
}

size_t ViewerService::client_bytes_bound() const {
  const size_t px = size_t(config_.limits.max_width) * config_.limits.max_height;
  // State, two refine buffers (3 B/px), and in the connection one view frame + one snapshot in
  // flight and one of each pending (a JPEG/PNG of an RGB image stays under 3 B/px + 1 %).
  return sizeof(Client) + 4096 + 2 * 3 * px + 4 * (3 * px + px / 100 + 1024);
}

ViewerService::ClientId ViewerService::connect(std::shared_ptr<ClientSink> sink) {
  auto c = std::make_shared<Client>();
  c->sink = std::move(sink);
  c->width = config_.width, c->height = config_.height;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    c->id = next_id_++;
    clients_[c->id] = c;
  }
  c->sink->send_text(info().dump());
  std::string state;
  {
    std::lock_guard<std::mutex> lock(c->m);
    state = state_json(*c).dump();
  }
  c->sink->send_text(state);
  cv_.notify_all();
  return c->id;
}

void ViewerService::disconnect(ClientId id) {
  std::lock_guard<std::mutex> lock(mutex_);
  clients_.erase(id);
}

std::shared_ptr<ViewerService::Client> ViewerService::find(ClientId id) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = clients_.find(id);
  return it == clients_.end() ? nullptr : it->second;
}

void ViewerService::reply_error(ClientId id, const ProtocolError& e, const std::string& type) {
  auto c = find(id);
  if (!c) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.errors_sent++;
  }
  c->sink->send_text(error_reply(e, type));
}

void ViewerService::handle_binary(ClientId id, size_t bytes) {
  reply_error(id,
              {"binary",
               fmt::format("binary messages ({} bytes) are not part of the protocol: send JSON text", bytes)},
              "");
}

void ViewerService::handle_text(ClientId id, std::string_view text) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.messages++;
  }
  ParseResult r = parse_client_message(text, config_.limits);
  if (!r.message) return reply_error(id, r.error, r.type);
  auto c = find(id);
  if (!c) return;
  Replies replies;
  try {
    std::lock_guard<std::mutex> lock(c->m);
    apply(*c, *r.message, replies);
  } catch (const std::exception& e) {
    // Never let one client's bad request take the server down: report it and go on.
    return reply_error(id, {"internal", e.what()}, r.type);
  }
  if (replies.errors) {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.errors_sent += replies.errors;
  }
  for (auto& s : replies.texts) c->sink->send_text(std::move(s));
  cv_.notify_all();
}

void ViewerService::apply(Client& c, const ClientMessage& m, Replies& replies) {
  const auto now = Clock::now();
  auto changed = [&] {
    c.gen++;
    c.last_input = now;
  };
  if (auto* cam = std::get_if<CameraMsg>(&m)) {
    c.orbit = clamp_orbit({cam->yaw_deg, cam->pitch_deg, cam->distance, cam->pan_x, cam->pan_y}, limits_);
    c.seq = cam->seq;
    c.interacting = cam->interacting;
    changed();
  } else if (auto* size = std::get_if<SizeMsg>(&m)) {
    c.width = size->width, c.height = size->height;
    changed();
  } else if (auto* g = std::get_if<GlassesMsg>(&m)) {
    c.glasses_on = g->on;
    changed();
    replies.texts.push_back(state_json(c).dump());
  } else if (auto* sel = std::get_if<SelectMsg>(&m)) {
    if (sel->index >= assets_->size()) {
      replies.error(
          error_reply({"invalid", fmt::format("frame {} does not exist: the catalogue has {} (0 to {})",
                                              sel->index, assets_->size(), assets_->size() - 1)},
                      "select"));
      return;
    }
    c.frame = sel->index;
    changed();
    replies.texts.push_back(state_json(c).dump());
  } else if (auto* n = std::get_if<NudgeMsg>(&m)) {
    if (assets_->state(c.frame).status != PlacementStatus::kReady) {
      replies.error(
          error_reply({"busy", "this frame is still being fitted: nudge it when the fit is done"}, "nudge"));
      return;
    }
    c.nudges[c.frame] = accumulate(c.nudges[c.frame], *n);
    changed();
    replies.texts.push_back(state_json(c).dump());
  } else if (auto* s = std::get_if<SaveMsg>(&m)) {
    FrameState fs = assets_->state(c.frame);
    if (fs.status != PlacementStatus::kReady || !fs.placement) {
      replies.error(
          error_reply({"busy", "this frame is still being fitted: save it when the fit is done"}, "save"));
      return;
    }
    const FrameEntry& e = assets_->entry(c.frame);
    SaveResult r = save_placement(e.save_path(), *fs.placement, c.nudges[c.frame], s->overwrite);
    if (!r.ok) {
      replies.error(error_reply(r.error, "save"));
      return;
    }
    spdlog::info("view: saved {}{}", r.path, r.backup.empty() ? "" : " (backup: " + r.backup + ")");
    nlohmann::json j = {
        {"type", "saved"}, {"frame", c.frame}, {"file", fs::path(r.path).filename().string()}};
    if (!r.backup.empty()) j["backup"] = fs::path(r.backup).filename().string();
    replies.texts.push_back(j.dump());
  } else if (std::get_if<SnapshotMsg>(&m)) {
    c.snapshot_requested = true;
  } else if (auto* p = std::get_if<PingMsg>(&m)) {
    replies.texts.push_back(nlohmann::json({{"type", "pong"}, {"seq", p->seq}}).dump());
  }
}

nlohmann::json ViewerService::state_json(Client& c) {
  const Nudge& n = c.nudges[c.frame];
  return {{"type", "state"},
          {"frame", assets_->describe(c.frame)},
          {"glasses_on", c.glasses_on},
          {"nudge", {{"up_mm", n.up_mm}, {"forward_mm", n.forward_mm}, {"tilt_deg", n.tilt_deg}}},
          {"orbit",
           {{"yaw", c.orbit.yaw_deg},
            {"pitch", c.orbit.pitch_deg},
            {"distance", c.orbit.distance},
            {"pan_x", c.orbit.pan_x},
            {"pan_y", c.orbit.pan_y}}},
          {"viewport", {{"width", c.width}, {"height", c.height}}}};
}

void ViewerService::broadcast_fit(const nlohmann::json& event, uint32_t frame) {
  std::vector<std::shared_ptr<Client>> all;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto& [id, c] : clients_) all.push_back(c);
  }
  const bool landed = event.value("state", "") == "done" || event.value("state", "") == "failed";
  for (auto& c : all) {
    c->sink->send_text(event.dump());
    if (!landed) continue;
    std::string state;
    {
      std::lock_guard<std::mutex> lock(c->m);
      if (c->frame != frame) continue;
      c->gen++;  // the glasses appear: render again
      state = state_json(*c).dump();
    }
    c->sink->send_text(state);
  }
  cv_.notify_all();
}

bool ViewerService::pick_work(Work& w, Clock::time_point& wake) {
  const auto now = Clock::now();
  const auto idle = std::chrono::milliseconds(config_.idle_ms);
  std::lock_guard<std::mutex> lock(mutex_);
  if (clients_.empty()) return false;
  // Round-robin: start after the client served last.
  auto start = clients_.upper_bound(rr_);
  for (size_t k = 0; k < clients_.size(); ++k, ++start) {
    if (start == clients_.end()) start = clients_.begin();
    auto& c = start->second;
    std::lock_guard<std::mutex> cl(c->m);
    // A drag whose end never arrived (the page lost the pointer) counts as over after 2 s.
    const bool dragging = c->interacting && now - c->last_input < std::chrono::seconds(2);
    const auto refine_at = c->last_input + (c->interacting ? std::chrono::milliseconds(2000) : idle);
    Work::Kind kind = Work::kNone;
    if (c->gen != c->coarse_done)
      kind = Work::kCoarse;
    else if (c->snap.active || c->snapshot_requested)
      kind = Work::kSnapshot;
    else if (c->full_done != c->gen && !dragging && now >= refine_at)
      kind = Work::kFull;
    else if (c->full_done != c->gen)
      wake = std::min(wake, refine_at);
    if (kind == Work::kNone) continue;
    if (kind == Work::kSnapshot && !c->snap.active) c->snapshot_requested = false;
    w = {kind,      c,      c->gen,   c->orbit,      c->width,
         c->height, c->seq, c->frame, c->glasses_on, c->nudges[c->frame]};
    rr_ = start->first;
    return true;
  }
  return false;
}

void ViewerService::render_loop() {
  for (;;) {
    Work w;
    Clock::time_point wake = Clock::now() + std::chrono::seconds(1);
    {
      std::unique_lock<std::mutex> lock(mutex_);
      if (stop_) return;
    }
    if (!pick_work(w, wake)) {
      std::unique_lock<std::mutex> lock(mutex_);
      cv_.wait_until(lock, wake);
      continue;
    }
    try {
      run_work(w);
    } catch (const std::exception& e) {
      spdlog::error("view: rendering for client {} failed: {}", w.client->id, e.what());
      w.client->sink->send_text(error_reply({"render", std::string("rendering failed: ") + e.what()}));
      std::lock_guard<std::mutex> lock(w.client->m);
      w.client->coarse_done = w.client->full_done = w.client->gen;  // do not retry in a loop
      w.client->snap.active = false;
    }
  }
}

void ViewerService::run_work(Work& w) {
  if (w.kind == Work::kCoarse)
    render_coarse(w);
  else
    render_band(w);
}

std::shared_ptr<const mesh::SurfacePass> ViewerService::glasses_for(const Work& w) {
  return w.glasses_on ? assets_->pass(w.frame, w.nudge) : nullptr;
}

void ViewerService::render_coarse(Work& w) {
  Client& c = *w.client;
  auto t0 = Clock::now();
  Camera cam = orbit_camera(orbit_, w.orbit, rounded_div(w.width, config_.coarse_divisor),
                            rounded_div(w.height, config_.coarse_divisor));
  auto p = glasses_for(w);
  render::GlassesSurfaces g = p ? mesh::frame_surfaces(p) : render::GlassesSurfaces{};
  render::RenderSettings look;  // the render request every front end builds (render_settings.h)
  look.step_scale = config_.coarse_step_scale;
  look.surface_spp = uint32_t(config_.coarse_surface_spp);  // 1 while the user moves
  render::FrameOptions opt = render::frame_options(look);
  render::RenderResult r = engine_->renderer.render_frame(engine_->model, cam, p ? &g : nullptr, opt);
  Rgb8 rgb = to_srgb8(r.rgba);
  FrameHeader h{FrameKind::kCoarseJpeg, w.seq, uint16_t(rgb.width), uint16_t(rgb.height), 0, 0};
  std::vector<uint8_t> jpeg = engine_->jpeg.encode(rgb, config_.jpeg_quality_coarse);
  h.render_us = uint32_t(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
  c.sink->send_frame(FrameKind::kCoarseJpeg, encode_frame(h, jpeg));
  {
    std::lock_guard<std::mutex> lock(c.m);
    if (c.gen == w.gen) c.coarse_done = w.gen;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  stats_.coarse_frames++;
}

void ViewerService::render_band(Work& w) {
  Client& c = *w.client;
  const bool snapshot = w.kind == Work::kSnapshot;
  Refine& f = snapshot ? c.snap : c.full;
  if (!f.active || (!snapshot && f.gen != w.gen)) {
    f = Refine{};
    f.active = true;
    f.gen = w.gen;
    f.seq = w.seq;
    f.cam = orbit_camera(orbit_, w.orbit, w.width, w.height);
    f.pass = glasses_for(w);
    f.image.width = int(w.width), f.image.height = int(w.height);
    f.image.pixels.assign(size_t(w.width) * w.height * 3, 0);
  }
  auto t0 = Clock::now();
  uint32_t rows = std::min(config_.band_rows, f.cam.height - f.next_row);
  Camera band = crop_rows(f.cam, f.next_row, rows);
  render::GlassesSurfaces g = f.pass ? mesh::frame_surfaces(f.pass) : render::GlassesSurfaces{};
  render::RenderSettings look;
  look.surface_spp = uint32_t(snapshot ? config_.snapshot_surface_spp : config_.full_surface_spp);
  if (snapshot) look.spp = config_.snapshot_spp;
  render::FrameOptions opt = render::frame_options(look);
  render::RenderResult r = engine_->renderer.render_frame(engine_->model, band, f.pass ? &g : nullptr, opt);
  paste_rows(f.image, to_srgb8(r.rgba), int(f.next_row));
  f.next_row += rows;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.bands++;
  }
  f.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
  if (f.next_row < f.cam.height) return;
  FrameKind kind = snapshot ? FrameKind::kSnapshotPng : FrameKind::kFullJpeg;
  std::vector<uint8_t> bytes =
      snapshot ? encode_png(f.image) : engine_->jpeg.encode(f.image, config_.jpeg_quality_full);
  FrameHeader h{kind, f.seq, uint16_t(f.image.width), uint16_t(f.image.height), uint32_t(f.seconds * 1e6), 0};
  c.sink->send_frame(kind, encode_frame(h, bytes));
  const uint64_t gen = f.gen;
  f = Refine{};  // frees the image
  {
    std::lock_guard<std::mutex> lock(c.m);
    if (!snapshot && c.gen == gen) c.full_done = gen;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  (snapshot ? stats_.snapshots : stats_.full_frames)++;
}

}  // namespace lorgnette::viewer
