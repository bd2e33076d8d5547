// How a real mask-less capture's training budget is best spent (issue 13): several training arms on
// one capture (model sizes, room model on/off, the room model's sample capacity per step) trained
// side by side in one process, in alternating chunks of steps (the arms' order rotated every
// chunk, so machine load hits all alike), each scored every chunk on the held-out views by its face
// PSNR (sRGB) over three regions of each held-out photo, all within the footprint of the subject box:
// - face: the convex hull of dlib's 68 landmarks (the region benchmarks/capture/region_psnr --face
//   scores on `lorgnette eval` images). In views away from the front the jaw line's hull takes in room
//   beside the cheek and under the chin, which a model that paints the room on its box (`bg=off`)
//   reproduces and one that keeps only the subject renders clear, so this region favours `off`;
// - inner: the hull of landmarks 17-67 (brows, eyes, nose, mouth), mostly on skin. In views turned
//   away it can still cross the far side's outline (on p_r1_y40 at +-40 deg: up to 133 of a view's
//   3485 pixels, which the room decides), so it favours `off` less than `face` but still does;
// - core: the inner hull shrunk by 8 % of the face's width on every side, for real captures,
//   which have no mattes: away from the outline (on p_r1_y40 and p_r2_y40 the true matte covers all
//   of it; checked by the counts this bench prints);
// - covered (synthetic room captures with true mattes only): the face hull's pixels the subject
//   covers fully (matte >= 0.999), as host/render/matte_eval.h's face_psnr_subject.
// Compare arms with and without the room model on `inner` or `covered`.
// Arms with the room model are scored with their subject region applied to a copy of the occupancy,
// as `train` saves them.
//
// Usage: bench_room_budget DATASET OUT_DIR --arm NAME:KEY=VALUE,... [--arm ...] [--every 100]
//        [--seed 1337] [--views N] [--save] [--save-every]
// Keys: bg=on|off (room model; default on), steps=N|default (default 1200; `default`: the budget
//       `train` gives this arm's size, train_budget.h), table=LOG2 (hash table),
//       finest=N (finest grid), levels=N, room_batch=X (room model's samples per step relative to the
//       subject's batch), room_spd=N (room steps per box diagonal), room_spread=0|1 (the room's batch
//       spread evenly over the step's rays), prior=X (weight of the binary-opacity prior on the
//       subject's rays; 0 = off), prior_start=N and prior_ramp=N (the step it ramps in from, and over
//       how many steps), keep=0|1 (BackgroundOptions::keep_neck).
// Each arm is planned as `train` plans it (nerf::plan_training: automatic sizing from the landmark
// head box, a room capture's table cap, the head volume and its clearing zones, 2^16 samples per
// step); unset keys keep `train`'s defaults.
// Writes OUT_DIR/room_budget.csv (a row per arm and checkpoint: steps, training seconds, subject and
// room samples, rays, face PSNR over each region) and room_budget_seconds.png /
// room_budget_steps.png (face PSNR against training seconds and against steps; `covered` where the
// dataset has true mattes, else `core`). --save: each arm's model after its last step as
// OUT_DIR/<arm>.lnerf, with the room model the subject region applied as `train` saves it (to score
// the arms' mattes with bench_room_matte on a synthetic room capture), and an arm's room model as
// OUT_DIR/<arm>_room.lnerf (`lorgnette eval` renders it alone: what the room holds behind the
// subject, e.g. a bright floater that explains a highlight). --save-every: also after every
// chunk, as OUT_DIR/<arm>_step<N>.lnerf (the subject region applied to a copy, training goes on
// unchanged), to see when in training something forms (head_volume_bench on each).
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
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
#include "synth/matte.h"

using namespace lorgnette;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

struct ArmSpec {
  std::string name;
  bool background = true;
  uint64_t steps = 1200;  // 0: the product's default budget for the arm's size
  std::optional<uint32_t> table, finest, levels, room_spd;
  float room_batch = 0.0f;  // 0: BackgroundOptions' default
  std::optional<bool> room_spread;
  std::optional<float> prior;                       // the binary-opacity prior's weight
  std::optional<uint32_t> prior_start, prior_ramp;  // the step it ramps in from, over this many steps
  std::optional<bool> keep;                         // BackgroundOptions::keep_neck
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
      a.steps = v == "default" ? 0 : std::stoull(v);
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
    } else if (k == "prior_start") {
      a.prior_start = uint32_t(std::stoul(v));
    } else if (k == "prior_ramp") {
      a.prior_ramp = uint32_t(std::stoul(v));
    } else if (k == "keep") {
      a.keep = v != "0";  // keep=0|1
    } else {
      throw std::runtime_error(
          "--arm " + arg + ": unknown key '" + k +
          "' (bg, steps, table, finest, levels, room_batch, room_spd, room_spread, prior, prior_start, "
          "prior_ramp, keep)");
    }
  }
  return a;
}

// The scored regions of a held-out view, in its crop.
enum Region { kFace, kInner, kCovered, kCore, kRegions };
const char* const kRegionNames[kRegions] = {"face", "inner", "covered", "core"};

struct HeldOut {
  const dataset::Frame* frame = nullptr;
  std::vector<uint8_t> mask;  // width x height of the crop, bit r = judged for region r
  long pixels[kRegions] = {0, 0, 0, 0};
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

cv::Mat hull_mask(const std::vector<Eigen::Vector2d>& points, int width, int height,
                  std::vector<cv::Point>& hull) {
  std::vector<cv::Point> pts;
  for (const auto& p : points) pts.emplace_back(int(std::lround(p.x() - 0.5)), int(std::lround(p.y() - 0.5)));
  cv::convexHull(pts, hull);
  cv::Mat m(height, width, CV_8U, cv::Scalar(0));
  cv::fillConvexPoly(m, hull, cv::Scalar(1));
  return m;
}

// The regions of one held-out photo (see the header) from dlib's landmarks on it and, when given, its
// true matte; within the box's footprint.
HeldOut face_region(const dataset::Frame& f, const nerf::Aabb& box, const fit::LandmarkDetector& det,
                    const Image* matte) {
  HeldOut h;
  h.frame = &f;
  const Image& img = f.image;
  fit::FaceDetection d = det.detect(img);
  if (!d.found || d.points.size() != 68) return h;
  if (matte && (matte->width != img.width || matte->height != img.height)) matte = nullptr;  // downscaled
  std::vector<cv::Point> hull, inner_hull;
  const cv::Mat face = hull_mask(d.points, img.width, img.height, hull);
  const cv::Mat inner = hull_mask({d.points.begin() + 17, d.points.end()}, img.width, img.height, inner_hull);
  const cv::Rect r = cv::boundingRect(hull) & cv::Rect(0, 0, img.width, img.height);
  // The inner hull shrunk by 8 % of the face's width on every side (at least 2 px): off the outline.
  const int shrink = std::max(2, int(std::lround(0.08 * r.width)));
  cv::Mat core;
  cv::erode(inner, core,
            cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * shrink + 1, 2 * shrink + 1)));
  h.x0 = r.x, h.y0 = r.y;
  h.crop = f.camera;  // a pixel-exact crop: the principal point moves, the distortion is unchanged
  h.crop.cx -= float(r.x), h.crop.cy -= float(r.y);
  h.crop.width = unsigned(r.width), h.crop.height = unsigned(r.height);
  h.mask.assign(size_t(r.width) * r.height, 0);
  for (int y = 0; y < r.height; ++y)
    for (int x = 0; x < r.width; ++x) {
      const int px = x + r.x, py = y + r.y;
      if (!face.at<uint8_t>(py, px) || !ray_hits_box(fit::camera_ray(f.camera, {px + 0.5, py + 0.5}), box))
        continue;
      uint8_t bits = 1u << kFace;
      if (inner.at<uint8_t>(py, px)) bits |= 1u << kInner;
      if (core.at<uint8_t>(py, px)) bits |= 1u << kCore;
      if (matte && matte->at(px, py, 0) >= 0.999f) bits |= 1u << kCovered;
      h.mask[size_t(y) * r.width + x] = bits;
      for (int k = 0; k < kRegions; ++k) h.pixels[k] += (bits >> k) & 1;
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

struct FacePsnr {
  double db[kRegions] = {0.0, 0.0, 0.0, 0.0};  // mean over the views that have the region
};

// Each region's mean over views of the view's PSNR (sRGB), the subject region applied when `region`.
FacePsnr face_psnr(nerf::NerfModel& model, bool region, const std::vector<HeldOut>& held,
                   render::Renderer& renderer) {
  const nerf::OccupancyGrid saved = model.occupancy();
  if (region) {
    nerf::OccupancyGrid g = saved;
    if (nerf::keep_central_region(g).found) model.set_occupancy(std::move(g));
  }
  double sum[kRegions] = {0.0, 0.0, 0.0, 0.0};
  int views[kRegions] = {0, 0, 0, 0};
  for (const HeldOut& h : held) {
    if (h.pixels[kFace] == 0) continue;
    const Image pred = renderer.render(model, h.crop, nullptr, render::RenderOptions{}).rgba;
    const Image& truth = h.frame->image;
    double se[kRegions] = {0.0, 0.0, 0.0, 0.0};
    for (int y = 0; y < pred.height; ++y)
      for (int x = 0; x < pred.width; ++x)
        if (const uint8_t bits = h.mask[size_t(y) * pred.width + x])
          for (int c = 0; c < 3; ++c) {
            const double e =
                linear_to_srgb(pred.at(x, y, c)) - linear_to_srgb(truth.at(x + h.x0, y + h.y0, c));
            for (int k = 0; k < kRegions; ++k)
              if ((bits >> k) & 1) se[k] += e * e;
          }
    for (int k = 0; k < kRegions; ++k)
      if (h.pixels[k] > 0) {
        sum[k] += -10.0 * std::log10(std::max(se[k] / (3.0 * double(h.pixels[k])), 1e-12));
        ++views[k];
      }
  }
  model.set_occupancy(saved);
  FacePsnr out;
  for (int k = 0; k < kRegions; ++k) out.db[k] = views[k] ? sum[k] / views[k] : 0.0;
  return out;
}

// Saves `model` to `path` as `train` would (the subject's connected region when `region`), leaving the
// model's own occupancy as it was so that training goes on unchanged.
void save_with_region(nerf::NerfModel& model, bool region, const std::string& path) {
  const nerf::OccupancyGrid saved = model.occupancy();
  if (region) {
    nerf::OccupancyGrid g = saved;
    if (nerf::keep_central_region(g).found) model.set_occupancy(std::move(g));
  }
  model.save(path);
  model.set_occupancy(saved);
}

// Charts of the `shown` region's PSNR.
void write_charts(const std::string& out, const std::vector<Arm>& arms, Region shown) {
  std::vector<ChartSeries> s1, s2;
  for (const Arm& a : arms) s1.push_back(a.by_seconds), s2.push_back(a.by_steps);
  const std::string what = fmt::format("Face PSNR ({}) on held-out views", kRegionNames[shown]);
  write_chart(out + "/room_budget_seconds.png",
              {what + " against training time (same load)", "training s", "dB"}, s1);
  write_chart(out + "/room_budget_steps.png", {what + " against steps", "step", "dB"}, s2);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::cerr
        << "usage: bench_room_budget DATASET OUT_DIR --arm NAME:KEY=VALUE,... [--arm ...] [--every 100] "
           "[--seed 1337] [--views N] [--save] [--save-every]\n";
    return 2;
  }
  try {
    const std::string data = argv[1], out = argv[2];
    uint64_t every = 100;
    uint32_t seed = 1337;
    size_t max_views = 0;
    bool save = false, save_every = false;
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
      else if (std::strcmp(argv[i], "--save-every") == 0)
        save_every = true;
      else
        return std::cerr << "unknown argument " << argv[i] << "\n", 2;
    }
    if (specs.empty()) return std::cerr << "give at least one --arm\n", 2;
    if (every == 0) return std::cerr << "--every must be > 0\n", 2;
    if (fs::exists(out + "/room_budget.csv"))
      return std::cerr << out << "/room_budget.csv exists: choose another OUT_DIR\n", 1;
    fs::create_directories(out);
    cl::Runtime rt;
    dataset::Dataset ds = dataset::load_dataset(data, {});
    nerf::TrainJob job;
    capture::apply_subject_box(ds, capture::BoxSource::Auto, true, job);
    job.train.seed = seed;
    job.train.progress = false;
    job.batch_log2 = 16;
    std::vector<nerf::View> views = nerf::training_views(ds);
    std::vector<nerf::TrainPlan> plans;
    for (ArmSpec& a : specs) {
      nerf::TrainJob j = job;
      j.background = a.background ? "on" : "off";
      if (a.table) j.sizing.log2_table_size = *a.table;
      if (a.finest) j.sizing.finest_resolution = *a.finest;
      if (a.levels) j.sizing.levels = *a.levels;
      j.train.steps = a.steps;
      nerf::BackgroundOptions& bo = j.train.background;
      if (a.room_batch > 0.0f) bo.batch_scale = a.room_batch;
      if (a.room_spd) bo.steps_per_diagonal = *a.room_spd;
      if (a.room_spread) bo.spread_over_rays = *a.room_spread;
      if (a.prior) bo.opacity_prior = *a.prior;
      if (a.prior_start) bo.opacity_prior_start = *a.prior_start;
      if (a.prior_ramp) bo.opacity_prior_ramp = *a.prior_ramp;
      if (a.keep) bo.keep_neck = *a.keep;
      plans.push_back(nerf::plan_training(rt, ds, views, j));
      a.steps = plans.back().train.steps;
      if (a.steps % every)
        return std::cerr << "arm " << a.name << ": " << a.steps << " steps are not a multiple of --every\n",
               2;
    }
    const nerf::Aabb box = plans.front().sizing.aabb;

    fit::LandmarkDetector det;
    const std::map<std::string, synth::EvalFiles> mattes = synth::eval_files_by_stem(data);
    std::vector<HeldOut> held;
    for (const dataset::Frame* f : ds.require_split(dataset::Split::Holdout)) {
      if (max_views && held.size() >= max_views) break;
      std::optional<Image> matte;
      if (auto it = mattes.find(fs::path(f->image_path).stem().string()); it != mattes.end())
        matte = synth::read_matte(data + "/" + it->second.matte);
      held.push_back(face_region(*f, box, det, matte ? &*matte : nullptr));
      const HeldOut& h = held.back();
      // A region's pixels that the true matte does not cover fully.
      auto uncovered = [&](Region r) -> long {
        if (!matte) return 0;
        return std::count_if(h.mask.begin(), h.mask.end(),
                             [r](uint8_t b) { return (b >> r & 1) && !(b >> kCovered & 1); });
      };
      const long inner_uncovered = uncovered(kInner), core_uncovered = uncovered(kCore);
      std::cerr << fmt::format(
          "held-out {}: {} face pixels, {} inner ({} of them not fully covered by the subject), {} covered "
          "by "
          "the true matte, {} core ({} not fully covered)\n",
          f->image_path, h.pixels[kFace], h.pixels[kInner], inner_uncovered, h.pixels[kCovered],
          h.pixels[kCore], core_uncovered);
    }

    std::vector<Arm> arms(specs.size());
    for (size_t k = 0; k < specs.size(); ++k) {
      Arm& a = arms[k];
      a.spec = specs[k];
      const nerf::TrainPlan& plan = plans[k];
      const nerf::ModelSizing& sz = plan.sizing;
      a.model = std::make_unique<nerf::NerfModel>(nerf::planned_model(rt, ds, views, plan, job));
      a.trainer = std::make_unique<nerf::Trainer>(*a.model, views, plan.train, sz.occupancy_mask);
      std::cerr << fmt::format("arm {}: {:.1f} M parameters ({} levels up to {}, 2^{} table), {} steps{}\n",
                               a.spec.name, double(sz.field.param_count()) / 1e6, sz.field.levels,
                               sz.field.finest_resolution, sz.field.log2_table_size, a.spec.steps,
                               a.trainer->background() ? ", " + a.trainer->background()->summary() : "");
      a.by_seconds.name = a.by_steps.name = a.spec.name;
    }
    render::Renderer renderer(rt);
    std::vector<std::vector<std::string>> rows;
    const std::vector<std::string> header = {
        "arm",  "step",         "train_seconds",      "subject_samples",      "room_samples",
        "rays", "face_psnr_db", "inner_face_psnr_db", "covered_face_psnr_db", "core_face_psnr_db"};
    const Region shown = mattes.empty() ? kCore : kCovered;
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
        const FacePsnr psnr = face_psnr(*a.model, a.spec.background, held, renderer);
        const uint64_t at = a.trainer->steps_done();
        const uint64_t room = a.trainer->background() ? a.trainer->background()->samples_done() : 0;
        std::cerr << fmt::format(
            "{} step {}: face PSNR {:.2f} dB (inner {:.2f}, covered {:.2f}, core {:.2f}), "
            "{:.1f} s training ({:.3f} s/step), subject {:.1f} M samples, room {:.1f} M, {:.0f} rays/step\n",
            a.spec.name, at, psnr.db[kFace], psnr.db[kInner], psnr.db[kCovered], psnr.db[kCore], a.seconds,
            a.seconds / double(at), a.trainer->samples_done() / 1e6, room / 1e6,
            double(a.trainer->rays_done()) / double(at));
        rows.push_back({a.spec.name, std::to_string(at), fmt::format("{:.2f}", a.seconds),
                        std::to_string(a.trainer->samples_done()), std::to_string(room),
                        std::to_string(a.trainer->rays_done()), fmt::format("{:.3f}", psnr.db[kFace]),
                        fmt::format("{:.3f}", psnr.db[kInner]), fmt::format("{:.3f}", psnr.db[kCovered]),
                        fmt::format("{:.3f}", psnr.db[kCore])});
        if (save_every)
          save_with_region(*a.model, a.spec.background,
                           out + "/" + a.spec.name + "_step" + std::to_string(at) + ".lnerf");
        a.by_seconds.x.push_back(a.seconds), a.by_seconds.y.push_back(psnr.db[shown]);
        a.by_steps.x.push_back(double(at)), a.by_steps.y.push_back(psnr.db[shown]);
      }
      if (!any) break;
      write_csv(out + "/room_budget.csv", header, rows);
      write_charts(out, arms, shown);  // every round: a run stopped early keeps its charts
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
      if (a.trainer->background())
        a.trainer->background()->model().save(out + "/" + a.spec.name + "_room.lnerf");
    }
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
