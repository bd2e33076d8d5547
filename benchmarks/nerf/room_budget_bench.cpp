// How a real mask-less capture's training budget is best spent (issue 13): several training arms on
// one capture (model sizes, room model on/off, the room model's sample capacity per step) trained
// side by side in one process, in alternating chunks of steps (the arms' order rotated every
// chunk, so machine load hits all alike), each scored every chunk on the held-out views by its face
// PSNR: sRGB PSNR inside the convex hull of dlib's 68 landmarks on each held-out photo, within the
// footprint of the subject box (the region benchmarks/capture/region_psnr --face scores on
// `lorgnette eval` images). Real captures have no true mattes, so only the face is judged.
// Arms with the room model are scored with their subject region applied to a copy of the occupancy,
// as `train` saves them.
//
// Usage: bench_room_budget DATASET OUT_DIR --arm NAME:KEY=VALUE,... [--arm ...] [--every 100]
//        [--seed 1337] [--views N] [--save]
// Keys: bg=on|off (room model; default on), steps=N (default 1200), table=LOG2 (hash table),
//       finest=N (finest grid), levels=N, room_batch=X (room model's samples per step relative to the
//       subject's batch), room_spd=N (room steps per box diagonal), room_spread=0|1 (the room's batch
//       spread evenly over the step's rays), prior=X (weight of the binary-opacity prior on the
//       subject's rays; 0 = off).
// Unset keys keep `train`'s defaults (automatic sizing from the landmark head box, 2^16 samples per step).
// Writes OUT_DIR/room_budget.csv (a row per arm and checkpoint: steps, training seconds, subject and
// room samples, rays, face PSNR) and room_budget_seconds.png / room_budget_steps.png (face PSNR
// against training seconds and against steps). --save: each arm's model after its last step as
// OUT_DIR/<arm>.lnerf, with the room model the subject region applied as `train` saves it (to score
// the arms' mattes with bench_room_matte on a synthetic room capture).
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <sstream>

#include "capture/subject_box.h"
#include "fit/camera_math.h"
#include "fit/landmarks_dlib.h"
#include "host/dataset/dataset.h"
#include "host/nerf/subject_region.h"
#include "host/nerf/train_job.h"
#include "host/render/renderer.h"
#include "host/util/chart.h"

using namespace lorgnette;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

struct ArmSpec {
  std::string name;
  bool background = true;
  uint64_t steps = 1200;
  std::optional<uint32_t> table, finest, levels, room_spd;
  float room_batch = 0.0f;  // 0: BackgroundOptions' default
  std::optional<bool> room_spread;
  std::optional<float> prior;  // the binary-opacity prior's weight
};

ArmSpec parse_arm(const std::string& arg) {
  ArmSpec a;
  const auto colon = arg.find(':');
  a.name = arg.substr(0, colon);
  if (a.name.empty()) throw std::runtime_error("--arm needs a name: NAME:KEY=VALUE,...");
  if (colon == std::string::npos) return a;
  std::stringstream ss(arg.substr(colon + 1));
  std::string kv;
  while (std::getline(ss, kv, ',')) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos) throw std::runtime_error("--arm " + arg + ": '" + kv + "' is not KEY=VALUE");
    const std::string k = kv.substr(0, eq), v = kv.substr(eq + 1);
    if (k == "bg") {
      if (v != "on" && v != "off") throw std::runtime_error("--arm " + arg + ": bg must be on or off");
      a.background = v == "on";
    } else if (k == "steps") {
      a.steps = std::stoull(v);
    } else if (k == "table") {
      a.table = uint32_t(std::stoul(v));
    } else if (k == "finest") {
      a.finest = uint32_t(std::stoul(v));
    } else if (k == "levels") {
      a.levels = uint32_t(std::stoul(v));
    } else if (k == "room_spd") {
      a.room_spd = uint32_t(std::stoul(v));
    } else if (k == "room_spread") {
      a.room_spread = v == "1";
    } else if (k == "room_batch") {
      a.room_batch = std::stof(v);
    } else if (k == "prior") {
      a.prior = std::stof(v);
    } else {
      throw std::runtime_error(
          "--arm " + arg + ": unknown key '" + k +
          "' (bg, steps, table, finest, levels, room_batch, room_spd, room_spread, prior)");
    }
  }
  return a;
}

struct HeldOut {
  const dataset::Frame* frame = nullptr;
  std::vector<uint8_t> face;  // width x height, 1 = judged
  long pixels = 0;
  Camera crop{};  // the holdout camera cropped to the face's bounding rectangle (renders only that)
  int x0 = 0, y0 = 0;
};

bool ray_hits_box(const fit::Ray& r, const nerf::Aabb& box) {
  double t0 = 0.0, t1 = 1e30;
  for (int a = 0; a < 3; ++a) {
    const double inv = 1.0 / r.dir[a];
    const double ta = (box.min[a] - r.origin[a]) * inv, tb = (box.max[a] - r.origin[a]) * inv;
    t0 = std::max(t0, std::min(ta, tb)), t1 = std::min(t1, std::max(ta, tb));
  }
  return t0 <= t1;
}

// The face hull of dlib's landmarks on the photo, within the box's footprint.
HeldOut face_region(const dataset::Frame& f, const nerf::Aabb& box, const fit::LandmarkDetector& det) {
  HeldOut h;
  h.frame = &f;
  const Image& img = f.image;
  fit::FaceDetection d = det.detect(img);
  if (!d.found) return h;
  std::vector<cv::Point> pts, hull;
  for (const auto& p : d.points)
    pts.emplace_back(int(std::lround(p.x() - 0.5)), int(std::lround(p.y() - 0.5)));
  cv::convexHull(pts, hull);
  cv::Mat m(img.height, img.width, CV_8U, cv::Scalar(0));
  cv::fillConvexPoly(m, hull, cv::Scalar(1));
  const cv::Rect r = cv::boundingRect(hull) & cv::Rect(0, 0, img.width, img.height);
  h.x0 = r.x, h.y0 = r.y;
  h.crop = f.camera;  // a pixel-exact crop: the principal point moves, the distortion is unchanged
  h.crop.cx -= float(r.x), h.crop.cy -= float(r.y);
  h.crop.width = unsigned(r.width), h.crop.height = unsigned(r.height);
  h.face.assign(size_t(r.width) * r.height, 0);
  for (int y = 0; y < r.height; ++y)
    for (int x = 0; x < r.width; ++x)
      if (m.at<uint8_t>(y + r.y, x + r.x) &&
          ray_hits_box(fit::camera_ray(f.camera, {x + r.x + 0.5, y + r.y + 0.5}), box)) {
        h.face[size_t(y) * r.width + x] = 1;
        ++h.pixels;
      }
  return h;
}

struct Arm {
  ArmSpec spec;
  std::unique_ptr<nerf::NerfModel> model;
  std::unique_ptr<nerf::Trainer> trainer;
  double seconds = 0.0;
  ChartSeries by_seconds, by_steps;
};

// Mean over views of each view's face PSNR (sRGB), the subject region applied when `region`.
double face_psnr(nerf::NerfModel& model, bool region, const std::vector<HeldOut>& held,
                 render::Renderer& renderer) {
  const nerf::OccupancyGrid saved = model.occupancy();
  if (region) {
    nerf::OccupancyGrid g = saved;
    if (nerf::keep_central_region(g).found) model.set_occupancy(std::move(g));
  }
  double sum = 0.0;
  int views = 0;
  for (const HeldOut& h : held) {
    if (h.pixels == 0) continue;
    const Image pred = renderer.render(model, h.crop, nullptr, render::RenderOptions{}).rgba;
    const Image& truth = h.frame->image;
    double se = 0.0;
    for (int y = 0; y < pred.height; ++y)
      for (int x = 0; x < pred.width; ++x)
        if (h.face[size_t(y) * pred.width + x])
          for (int c = 0; c < 3; ++c) {
            const double e =
                linear_to_srgb(pred.at(x, y, c)) - linear_to_srgb(truth.at(x + h.x0, y + h.y0, c));
            se += e * e;
          }
    sum += -10.0 * std::log10(std::max(se / (3.0 * double(h.pixels)), 1e-12));
    ++views;
  }
  model.set_occupancy(saved);
  return views ? sum / views : 0.0;
}

void write_charts(const std::string& out, const std::vector<Arm>& arms) {
  std::vector<ChartSeries> s1, s2;
  for (const Arm& a : arms) s1.push_back(a.by_seconds), s2.push_back(a.by_steps);
  write_chart(out + "/room_budget_seconds.png",
              {"Face PSNR on held-out views against training time (same load)", "training s", "dB"}, s1);
  write_chart(out + "/room_budget_steps.png", {"Face PSNR on held-out views against steps", "step", "dB"},
              s2);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::cerr
        << "usage: bench_room_budget DATASET OUT_DIR --arm NAME:KEY=VALUE,... [--arm ...] [--every 100] "
           "[--seed 1337] [--views N] [--save]\n";
    return 2;
  }
  try {
    const std::string data = argv[1], out = argv[2];
    uint64_t every = 100;
    uint32_t seed = 1337;
    size_t max_views = 0;
    bool save = false;
    std::vector<ArmSpec> specs;
    for (int i = 3; i < argc; ++i) {
      if (std::strcmp(argv[i], "--arm") == 0 && i + 1 < argc)
        specs.push_back(parse_arm(argv[++i]));
      else if (std::strcmp(argv[i], "--every") == 0 && i + 1 < argc)
        every = std::stoull(argv[++i]);
      else if (std::strcmp(argv[i], "--seed") == 0 && i + 1 < argc)
        seed = uint32_t(std::stoul(argv[++i]));
      else if (std::strcmp(argv[i], "--views") == 0 && i + 1 < argc)
        max_views = std::stoull(argv[++i]);
      else if (std::strcmp(argv[i], "--save") == 0)
        save = true;
      else
        return std::cerr << "unknown argument " << argv[i] << "\n", 2;
    }
    if (specs.empty()) return std::cerr << "give at least one --arm\n", 2;
    for (const ArmSpec& s : specs)
      if (every == 0 || s.steps % every)
        return std::cerr << "arm " << s.name << ": steps must be a multiple of --every (> 0)\n", 2;
    if (fs::exists(out + "/room_budget.csv"))
      return std::cerr << out << "/room_budget.csv exists: choose another OUT_DIR\n", 1;
    fs::create_directories(out);
    cl::Runtime rt;
    dataset::Dataset ds = dataset::load_dataset(data, {});
    nerf::TrainJob job;
    capture::apply_subject_box(ds, capture::BoxSource::Auto, true, job);
    job.sizing.aabb_scale = ds.aabb_scale;
    std::vector<nerf::View> views = nerf::training_views(ds);
    const nerf::ModelSizing base = nerf::choose_model_size(views, job.sizing);

    fit::LandmarkDetector det;
    std::vector<HeldOut> held;
    for (const dataset::Frame* f : ds.require_split(dataset::Split::Holdout)) {
      if (max_views && held.size() >= max_views) break;
      held.push_back(face_region(*f, base.aabb, det));
      std::cerr << fmt::format("held-out {}: {} face pixels\n", f->image_path, held.back().pixels);
    }

    std::vector<Arm> arms(specs.size());
    for (size_t k = 0; k < specs.size(); ++k) {
      Arm& a = arms[k];
      a.spec = specs[k];
      nerf::SizingOverrides ov = job.sizing;
      if (a.spec.table) ov.log2_table_size = *a.spec.table;
      if (a.spec.finest) ov.finest_resolution = *a.spec.finest;
      if (a.spec.levels) ov.levels = *a.spec.levels;
      const nerf::ModelSizing sz = nerf::choose_model_size(views, ov);
      a.model = std::make_unique<nerf::NerfModel>(rt, sz.field, sz.aabb, sz.occupancy_resolution, sz.step,
                                                  1u << 16, seed, false);
      nerf::TrainOptions to;
      to.steps = a.spec.steps;
      to.seed = seed;
      to.progress = false;
      to.background.enabled = a.spec.background;
      if (a.spec.room_batch > 0.0f) to.background.batch_scale = a.spec.room_batch;
      if (a.spec.room_spd) to.background.steps_per_diagonal = *a.spec.room_spd;
      if (a.spec.room_spread) to.background.spread_over_rays = *a.spec.room_spread;
      if (a.spec.prior) to.background.opacity_prior = *a.spec.prior;
      a.trainer = std::make_unique<nerf::Trainer>(*a.model, views, to, sz.occupancy_mask);
      std::cerr << fmt::format("arm {}: {:.1f} M parameters ({} levels up to {}, 2^{} table), {} steps{}\n",
                               a.spec.name, double(sz.field.param_count()) / 1e6, sz.field.levels,
                               sz.field.finest_resolution, sz.field.log2_table_size, a.spec.steps,
                               a.trainer->background() ? ", " + a.trainer->background()->summary() : "");
      a.by_seconds.name = a.by_steps.name = a.spec.name;
    }
    render::Renderer renderer(rt);
    std::vector<std::vector<std::string>> rows;
    const std::vector<std::string> header = {"arm",          "step", "train_seconds", "subject_samples",
                                             "room_samples", "rays", "face_psnr_db"};
    for (uint64_t round = 0;; ++round) {
      bool any = false;
      for (size_t j = 0; j < arms.size(); ++j) {
        Arm& a = arms[(j + round) % arms.size()];  // rotate which arm goes first
        if (a.trainer->steps_done() >= a.spec.steps) continue;
        any = true;
        auto t0 = Clock::now();
        for (uint64_t s = 0; s < every; ++s) {
          a.trainer->set_elapsed(a.seconds);
          a.trainer->step();
        }
        a.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
        const double psnr = face_psnr(*a.model, a.spec.background, held, renderer);
        const uint64_t at = a.trainer->steps_done();
        const uint64_t room = a.trainer->background() ? a.trainer->background()->samples_done() : 0;
        std::cerr << fmt::format(
            "{} step {}: face PSNR {:.2f} dB, {:.1f} s training ({:.3f} s/step), subject {:.1f} M samples, "
            "room {:.1f} M, {:.0f} rays/step\n",
            a.spec.name, at, psnr, a.seconds, a.seconds / double(at), a.trainer->samples_done() / 1e6,
            room / 1e6, double(a.trainer->rays_done()) / double(at));
        rows.push_back({a.spec.name, std::to_string(at), fmt::format("{:.2f}", a.seconds),
                        std::to_string(a.trainer->samples_done()), std::to_string(room),
                        std::to_string(a.trainer->rays_done()), fmt::format("{:.3f}", psnr)});
        a.by_seconds.x.push_back(a.seconds), a.by_seconds.y.push_back(psnr);
        a.by_steps.x.push_back(double(at)), a.by_steps.y.push_back(psnr);
      }
      if (!any) break;
      write_csv(out + "/room_budget.csv", header, rows);
      write_charts(out, arms);  // every round: a run stopped early keeps its charts
    }
    for (Arm& a : arms) {
      if (!save) break;
      if (a.spec.background) {
        nerf::OccupancyGrid g = a.model->occupancy();
        const nerf::SubjectRegionReport rep = nerf::keep_central_region(g);
        std::cerr << fmt::format("{}: {}\n", a.spec.name, rep.summary());
        if (rep.found) a.model->set_occupancy(std::move(g));
      }
      a.model->save(out + "/" + a.spec.name + ".lnerf");
    }
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
