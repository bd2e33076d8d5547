// Frames, placements, thumbnails, cached surface passes and the fit worker (frame_assets.h).
#include "viewer/frame_assets.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <future>
#include <map>

#include "fit/fit_job.h"
#include "fit/glasses_input.h"
#include "host/nerf/model.h"
#include "mesh/placed_glasses.h"
#include "mesh/temple_bend.h"
#include "viewer/image_codec.h"

namespace lorgnette::viewer {
namespace fs = std::filesystem;
namespace {

constexpr size_t kPassCache = 8;

// A front view of the canonical frame over a light grey background, as a small JPEG.
std::vector<uint8_t> render_thumbnail(const mesh::Glasses& g) {
  const int w = 192, h = 96;
  Eigen::Vector3f lo(1e9f, 1e9f, 1e9f), hi(-1e9f, -1e9f, -1e9f);
  for (const auto& p : g.mesh.positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  Eigen::Vector3f c = 0.5f * (lo + hi);
  float half_w = 0.55f * std::max(hi.x() - lo.x(), 1.0f), half_h = 0.55f * std::max(hi.y() - lo.y(), 1.0f);
  const float fov = 20.0f, t = std::tan(0.5f * fov * 3.14159265f / 180.0f);
  float dist = std::max(half_h / t, half_w / (t * float(w) / float(h))) + hi.z();
  Camera cam = mesh::look_at_camera(Eigen::Vector3f(c.x(), c.y(), dist + c.z()), c, Eigen::Vector3f(0, 1, 0),
                                    fov, w, h);
  mesh::SurfacePass pass(g.mesh, Eigen::Matrix4f::Identity());
  mesh::SurfaceParams sp;
  sp.samples_per_pixel = 4;
  lorgnette::SurfaceBuffers s = pass.render(cam, sp);
  Image img(w, h, 3);
  const float bg = 0.86f;
  for (size_t i = 0; i < s.pixel_count(); ++i)
    for (int k = 0; k < 3; ++k)
      img.pixels[i * 3 + k] = s.color_alpha[i * 4 + k] + (1.0f - s.color_alpha[i * 4 + 3]) * bg;
  JpegEncoder jpeg;
  return jpeg.encode(to_srgb8(img), 85);
}

std::string nudge_key(uint32_t i, uint64_t version, const Nudge& n) {
  return fmt::format("{}/{}/{:.3f}/{:.3f}/{:.3f}", i, version, n.up_mm, n.forward_mm, n.tilt_deg);
}

}  // namespace

FrameAssets::FrameAssets(std::vector<FrameEntry> catalogue, OrbitFrame orbit, std::array<float, 3> box_min,
                         std::array<float, 3> box_max, FitWorkerConfig fit, FitListener listener)
    : entries_(std::move(catalogue)),
      orbit_(orbit),
      box_min_(box_min),
      box_max_(box_max),
      fit_(std::move(fit)),
      listener_(std::move(listener)) {
  for (const auto& e : entries_) {
    try {
      glasses_.push_back(std::make_unique<mesh::Glasses>(mesh::load_glasses(e.path)));
    } catch (const std::exception& ex) {
      throw std::runtime_error(fmt::format("catalogue frame '{}': {}", e.path, ex.what()));
    }
    thumbnails_.push_back(render_thumbnail(*glasses_.back()));
  }
  states_.resize(entries_.size());
  requested_.assign(entries_.size(), false);
  fit_thread_ = std::thread([this] { fit_loop(); });
}

FrameAssets::~FrameAssets() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    fit_queue_.clear();
  }
  cv_.notify_all();
  if (fit_thread_.joinable()) fit_thread_.join();
}

FrameState FrameAssets::state(uint32_t i) {
  std::lock_guard<std::mutex> lock(mutex_);
  request(i);
  return states_.at(i);
}

void FrameAssets::request(uint32_t i) {
  if (requested_.at(i)) return;
  requested_[i] = true;
  if (auto file = existing_placement(entries_[i])) {
    try {
      auto p = std::make_shared<fit::PlacementFile>(fit::read_placement(*file));
      if (std::string why = fit::glasses_mismatch(*p, entries_[i].path); !why.empty())
        throw std::runtime_error(fmt::format("{}: {}", *file, why));
      states_[i].placement = p;
      states_[i].status = PlacementStatus::kReady;
      states_[i].source = "file";
      states_[i].version++;
      return;
    } catch (const std::exception& e) {
      spdlog::warn("view: {}: {}; fitting it instead", entries_[i].name, e.what());
      states_[i].message = e.what();
    }
  }
  if (!fit_.enabled) {
    set_rough(i, "fitting is off");
    return;
  }
  states_[i].status = PlacementStatus::kFitting;
  fit_queue_.push_back(i);
  cv_.notify_all();
}

void FrameAssets::set_rough(uint32_t i, const std::string& why) {
  auto p = std::make_shared<fit::PlacementFile>();
  auto v = [](const std::array<float, 3>& a) { return Eigen::Vector3d(a[0], a[1], a[2]); };
  fit::HeadAxes axes;  // the orbit's: right is the frame's x, as the fit places it
  axes.x = v(orbit_.right), axes.up = v(orbit_.up), axes.front = v(orbit_.front),
  axes.center = v(orbit_.center);
  p->transform = fit::rough_placement(glasses_[i]->metrics.total_width_mm, v(box_min_), v(box_max_), axes);
  p->glasses_path = entries_[i].path;
  p->warnings.push_back("rough stand-in, not a fit: " + why);
  states_[i].placement = p;
  states_[i].status = PlacementStatus::kReady;
  states_[i].source = "rough (" + why + ")";
  states_[i].version++;
}

nlohmann::json FrameAssets::describe(uint32_t i) {
  FrameState s = state(i);
  const auto& m = glasses_.at(i)->metrics;
  nlohmann::json j = {{"index", i},
                      {"name", entries_[i].name},
                      {"status", s.status == PlacementStatus::kReady     ? "ready"
                                 : s.status == PlacementStatus::kFitting ? "fitting"
                                                                         : "none"},
                      {"source", s.source},
                      {"size_mm",
                       {{"total_width", m.total_width_mm},
                        {"lens_width", m.lens_width_mm},
                        {"lens_height", m.lens_height_mm},
                        {"bridge", m.bridge_mm},
                        {"temple", m.temple_length_mm}}}};
  if (s.placement && s.placement->pd_mm > 0) j["pd_mm"] = s.placement->pd_mm;
  if (s.placement) {  // the scale's source and the fit advice (#44), for the panel
    const fit::PlacementFile& p = *s.placement;
    j["pd_uncertainty_mm"] = p.pd_uncertainty_mm;
    j["scale_source"] = p.scale_source;
    j["scale_policy"] = p.scale_policy;
    nlohmann::json advice = nlohmann::json::array();
    for (const fit::AdviceRule& r : p.advice.rules)
      advice.push_back(
          {{"name", r.name}, {"verdict", r.verdict}, {"off_by_mm", r.off_by_mm}, {"text", r.text}});
    j["advice"] = advice;
    j["advice_approximate"] = p.advice.approximate;
  }
  if (!s.message.empty()) j["message"] = s.message;
  return j;
}

nlohmann::json FrameAssets::catalogue_json() const {
  nlohmann::json a = nlohmann::json::array();
  for (size_t i = 0; i < entries_.size(); ++i)
    a.push_back({{"index", i}, {"name", entries_[i].name}, {"thumbnail", fmt::format("/thumb/{}.jpg", i)}});
  return a;
}

std::shared_ptr<const mesh::SurfacePass> FrameAssets::pass(uint32_t i, const Nudge& nudge) {
  std::shared_ptr<const fit::PlacementFile> placement;
  uint64_t version;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    request(i);
    if (states_[i].status != PlacementStatus::kReady) return nullptr;
    placement = states_[i].placement;
    version = states_[i].version;
    std::string key = nudge_key(i, version, nudge);
    for (auto it = passes_.begin(); it != passes_.end(); ++it)
      if (it->key == key) {
        CachedPass hit = *it;
        passes_.erase(it);
        passes_.push_front(hit);
        return hit.pass;
      }
  }
  // Built outside the lock (Embree BVH build); a rare duplicate build is harmless.
  std::shared_ptr<const mesh::SurfacePass> built =
      mesh::place_glasses_mesh(*glasses_[i], placement->transform * nudge_matrix(nudge),
                               placement->has_temples ? placement->temples.bend : mesh::TempleBend{})
          .pass;
  std::lock_guard<std::mutex> lock(mutex_);
  passes_.push_front({nudge_key(i, version, nudge), built});
  if (passes_.size() > kPassCache) passes_.pop_back();
  return built;
}

void FrameAssets::fit_loop() {
  for (;;) {
    uint32_t i;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      cv_.wait(lock, [&] { return stop_ || !fit_queue_.empty(); });
      if (stop_) return;
      i = fit_queue_.front();
      fit_queue_.pop_front();
    }
    run_fit(i);
  }
}

std::string fit_stage_label(const std::string& stage) {
  static const std::map<std::string, std::string> labels = {
      {"load", "loading the head"},
      {"load_detector", "loading the landmark detector"},
      {"front", "finding the face's front"},
      {"render_detect", "rendering views and finding landmarks"},
      {"render_detect_recentred", "rendering re-centred views and finding landmarks"},
      {"triangulate", "triangulating the landmarks"},
      {"triangulate_recentred", "triangulating the re-centred landmarks"},
      {"scale", "measuring the irises for the scale"},
      {"place", "placing the frame"},
      {"contact", "seating the frame on the skin"},
      {"temples", "fitting the temples"},
      {"contact_eq23_ears", "seating the frame again, ears at the eye height"},
      {"temples_eq23_ears", "fitting the temples again"},
      {"advice", "comparing the frame's sizes with the head's"},
      {"checks", "checking the head for holes"}};
  auto it = labels.find(stage);
  return it != labels.end() ? it->second : stage;
}

void FrameAssets::run_fit(uint32_t i) {
  const FrameEntry& e = entries_[i];
  auto t0 = std::chrono::steady_clock::now();
  listener_({{"type", "fit"}, {"state", "started"}, {"frame", i}, {"name", e.name}}, i);
  spdlog::info("view: fitting {} (no placement beside it)", e.name);
  std::mutex stage_mutex;
  std::vector<std::string> started;  // the fit's stages as they start (fit.h FitOptions::on_stage)
  auto work = std::async(std::launch::async, [&] {
    fit::GlassesInput glasses = fit::load_glasses_input(e.path);
    fit::FitOptions opt = fit::fit_options(fit_.settings);
    opt.on_stage = [&](const std::string& s) {
      std::lock_guard<std::mutex> lock(stage_mutex);
      started.push_back(s);
    };
    cl::Runtime rt(fit_.runtime);
    nerf::NerfModel model = nerf::NerfModel::load(rt, fit_.model_path);
    return fit::run_fit_job(model, glasses, opt).placement;
  });
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  // A progress message as each stage starts (even one shorter than the polling), and each second.
  size_t said = 0;
  auto last = std::chrono::steady_clock::now();
  auto progress = [&](bool finished) {
    std::vector<std::string> stages;
    {
      std::lock_guard<std::mutex> lock(stage_mutex);
      stages = started;
    }
    bool heartbeat = !finished && std::chrono::steady_clock::now() - last >= std::chrono::seconds(1);
    if (said == stages.size() && !heartbeat) return;
    for (size_t k = std::min(said + 1, stages.size()); k <= stages.size(); ++k) {
      const std::string stage = k ? stages[k - 1] : "load";
      listener_({{"type", "fit"},
                 {"state", "progress"},
                 {"frame", i},
                 {"elapsed_s", std::round(elapsed())},
                 {"stage", stage},
                 {"stage_label", fit_stage_label(stage)},
                 {"stage_index", k}},
                i);
    }
    said = stages.size();
    last = std::chrono::steady_clock::now();
  };
  while (work.wait_for(std::chrono::milliseconds(100)) != std::future_status::ready) progress(false);
  progress(true);
  const double seconds = elapsed();
  nlohmann::json done = store_fit(i, work);
  done["seconds"] = seconds;
  listener_(done, i);
}

nlohmann::json FrameAssets::store_fit(uint32_t i, std::future<fit::PlacementFile>& work) {
  const FrameEntry& e = entries_[i];
  nlohmann::json done = {{"type", "fit"}, {"frame", i}};
  try {
    auto pf = std::make_shared<fit::PlacementFile>(work.get());
    std::string note;
    if (!fs::exists(e.save_path())) {
      try {
        fit::write_placement(e.save_path(), *pf);
        note = "cached beside the frame";
      } catch (const std::exception& ex) {
        note = std::string("not cached (") + ex.what() + "): kept for this session";
      }
    }
    std::lock_guard<std::mutex> lock(mutex_);
    states_[i].placement = pf;
    states_[i].status = PlacementStatus::kReady;
    states_[i].source = "fit";
    states_[i].version++;
    states_[i].message = note;
    done["state"] = "done";
    done["pd_mm"] = pf->pd_mm;
    done["ok"] = pf->ok;
    done["message"] = note;
  } catch (const std::exception& ex) {
    spdlog::warn("view: fitting {} failed: {}", e.name, ex.what());
    std::lock_guard<std::mutex> lock(mutex_);
    set_rough(i, "the fit failed");
    states_[i].message = ex.what();
    done["state"] = "failed";
    done["message"] =
        std::string(ex.what()) + " (showing a rough stand-in; nudge it and save, or run `lorgnette fit`)";
  }
  return done;
}

}  // namespace lorgnette::viewer
