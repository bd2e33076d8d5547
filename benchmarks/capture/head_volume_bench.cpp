// head_volume_bench: where a mask-less capture's subject model holds density, and what of it the
// held-out views see, in its head's frame. For each case (a trained .lnerf and its dataset) the
// landmark head box is estimated again as training does (fit::estimate_head_box on the training
// photos) and space is sorted into three regions: the head volume (capture/head_volume.h: "head"),
// the rest of the oriented head box ("box_not_head"), and the rest of the model's axis-aligned box
// ("corners"). Per region: occupancy cells, occupied cells, "solid" cells (one cell's length of the
// grid density gives opacity > 0.5), and the opacity the held-out views see there (rays of every
// 4th pixel of 4 views marched at the model's step through the field's density in occupied cells;
// each sample's compositing weight T * alpha goes to its region; mean per ray). Writes
// head_volume.csv, head_volume_depth.csv (solid cells per 10 mm of head depth, z forward from the
// eyes), head_volume_seen_depth.csv (seen opacity per 10 mm of head depth), <case>_seen_<k>.png
// (each held-out view: grey head, red box_not_head, blue corners, mixed by their weights; white
// where nothing is seen) and <case>_side.png / _top.png (the densest cell along the head's x / y,
// coloured alike, with the oriented box in black and the head volume's middle section in green).
// Also runs the check `train` ends with (host/nerf/subject_cut.h) on the training views: the share of
// the seen opacity in the head volume's rim above the brows and behind the eyes, at its top and back
// and at its sides (rim_share, rim_sides_share in head_volume.csv); --hair
// sizes the head box as `train --hair` did.
// Where the dataset has true mattes (`lorgnette synth --room`), the leak (the seen opacity x (1 -
// matte) on the held-out rays, as a share of the subject's matte area, as bench_room_matte's leak) is
// split by the room clearing's zone its samples lie in (capture/head_volume.h: keep = the neck below
// the chin, core = the bare head, lean = the rest of the head volume, outside = beyond it) and located
// in 20 mm bins of head-frame height and depth: head_volume_leak.csv and head_volume_leak_yz.csv.
// The holes (host/render/hole_eval.h: the head's interior under 0.5 opacity) are logged by the zone
// of the true surface point each interior ray hits (from the true depth), with the room-explained
// gate its pixel reads against the plain wall's colour in its row, per 20 mm of head-frame height,
// and for rays that cross the head's certain interior grown by 0-30 mm (training's crossing test,
// BackgroundOptions::solid_reach_mm) with the leak those rays carry.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>

#include "capture/face_hull.h"
#include "capture/head_volume.h"
#include "capture/subject_box.h"
#include "fit/camera_math.h"
#include "host/field/density_at.h"
#include "host/nerf/background_field.h"
#include "host/nerf/model.h"
#include "host/nerf/snapshot.h"
#include "host/nerf/subject_cut.h"
#include "host/render/hole_eval.h"
#include "host/render/matte_eval.h"
#include "host/util/chart.h"
#include "host/util/image_io.h"
#include "synth/matte.h"
#include "train/render.h"

namespace fs = std::filesystem;
using namespace lorgnette;

namespace {

enum Region { kHead = 0, kBoxNotHead = 1, kCorners = 2 };
const char* kRegionNames[3] = {"head", "box_not_head", "corners"};

// The room clearing's zones (capture/head_volume.h) and where the leak lies in the head frame.
enum Zone { kKeep = 0, kCore = 1, kLean = 2, kOutside = 3 };
const char* kZoneNames[4] = {"keep", "core", "lean", "outside"};
struct LeakSplit {
  std::function<int(const Eigen::Vector3d&)> zone_of;                   // dataset-frame point -> Zone
  std::function<Eigen::Vector2d(const Eigen::Vector3d&)> height_depth;  // -> head-frame (y, z) mm
  // True matte and subject depth by held-out image stem. As bench_room_matte judges: subject pixels
  // (matte >= 0.5) count only where their subject point lies in the model's box (head to neck).
  std::map<std::string, std::pair<Image, Image>> mattes;
  double subject = 0.0;  // the judged subject pixels among the marched rays
  std::array<double, 4> zone{0, 0, 0, 0};
  std::map<std::pair<int, int>, std::array<double, 4>> yz;  // 20 mm bins of (y, z): leak by zone
  // Holes (host/render/hole_eval.h: the head's interior, opacity < 0.5) by the zone of the true
  // surface point each interior ray hits (from the true depth), with the room-explained gate the
  // ray's pixel reads (train/render.h) against the plain wall's colour in its row (the mean of the
  // row's room pixels: a room model that learned the wall exactly). Per zone: interior rays, holes,
  // the gate summed over each; and interior rays and holes per 20 mm of head-frame height.
  std::array<double, 4> interior{0, 0, 0, 0}, holes{0, 0, 0, 0}, gate{0, 0, 0, 0}, hole_gate{0, 0, 0, 0};
  std::map<int, std::array<double, 2>> holes_y;
  // The head's certain interior grown by kGrowthMm (training's crossing test: a ray that crosses it
  // gets no clearing): per growth, the interior rays, holes and the leak (seen opacity on room rays)
  // whose rays cross it.
  std::vector<nerf::SubjectVolume> grown_solid;
  std::array<double, 6> cross_interior{}, cross_holes{}, cross_leak{};
};
constexpr double kGrowthMm[6] = {0, 5, 10, 15, 20, 30};

struct Case {
  std::string name, model, data;
};

struct Grid {
  nerf::Snapshot snap;
  float cell = 0.0f;  // mean cell side (scene units)
  float alpha(uint64_t c) const {
    if (!((snap.occ.bits[c >> 5] >> (c & 31u)) & 1u)) return 0.0f;
    float d = snap.occ.density.empty() ? 0.0f : snap.occ.density[c];
    return 1.0f - std::exp(-std::max(d, 0.0f) * cell);
  }
  // The cell holding scene point p, or -1 outside the box.
  int64_t cell_of(const nerf::Vec3f& p) const {
    const uint32_t res = snap.occ.res;
    int64_t idx[3];
    for (int a = 0; a < 3; ++a) {
      float f = (p[a] - snap.aabb.min[a]) / snap.aabb.extent(a);
      if (!(f >= 0.0f && f < 1.0f)) return -1;
      idx[a] = int64_t(f * float(res));
    }
    return idx[0] + int64_t(res) * (idx[1] + int64_t(res) * idx[2]);
  }
};

Eigen::Vector3d to_scene(const fit::HeadBox& b, const Eigen::Vector3d& mm) {
  return b.anchor + b.axes * (mm / b.head.mm_per_unit);
}

nerf::Vec3f vec(const Eigen::Vector3d& p) { return {float(p.x()), float(p.y()), float(p.z())}; }

Region region_of(const nerf::Vec3f& p, const nerf::SubjectVolume& box, const nerf::SubjectVolume& head) {
  if (head.contains(p)) return kHead;
  return box.contains(p) ? kBoxNotHead : kCorners;
}

// One projection of the grid along head-frame axis `along` onto the other two (u horizontal, v up),
// 2 mm per pixel over the model's box in the head frame.
void write_view(const std::string& path, const Grid& g, const fit::HeadBox& b, const nerf::SubjectVolume& box,
                const nerf::SubjectVolume& head, int u_axis, int v_axis, int along) {
  const double px = 2.0, range = 260.0;  // mm per pixel; half the picture's side in mm
  const int n = int(2.0 * range / px);
  const double mid[3] = {0.0, -5.0, -87.0};  // about the oriented box's middle (mm)
  Image img(n, n, 3);
  const double step = std::max(1.0, 0.5 * g.cell * b.head.mm_per_unit);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      float best[3] = {0, 0, 0};
      Eigen::Vector3d mm = Eigen::Vector3d::Zero();
      mm[u_axis] = mid[u_axis] - range + (i + 0.5) * px;
      mm[v_axis] = mid[v_axis] + range - (j + 0.5) * px;
      for (double w = -range; w <= range; w += step) {
        mm[along] = w;
        nerf::Vec3f p = vec(to_scene(b, mm));
        int64_t c = g.cell_of(p);
        if (c < 0) continue;
        float a = g.alpha(uint64_t(c));
        if (a <= 0.0f) continue;
        int r = region_of(p, box, head);
        best[r] = std::max(best[r], a);
      }
      mm[along] = 0.0;  // outlines: the section through the eyes' middle (side) or eye level (top)
      auto inside = [&](const nerf::SubjectVolume& v, double du, double dv) {
        Eigen::Vector3d q = mm;
        q[u_axis] += du, q[v_axis] += dv;
        return v.contains(vec(to_scene(b, q)));
      };
      bool in_head = inside(head, 0, 0), in_box = inside(box, 0, 0);
      bool head_edge = in_head != inside(head, px, 0) || in_head != inside(head, 0, px);
      bool box_edge = in_box != inside(box, px, 0) || in_box != inside(box, 0, px);
      float rgb[3] = {1.0f, 1.0f, 1.0f};
      int r = int(std::max_element(best, best + 3) - best);
      float a = best[r];
      const float tint[3][3] = {{0.25f, 0.25f, 0.25f}, {0.9f, 0.1f, 0.1f}, {0.1f, 0.3f, 0.95f}};
      for (int k = 0; k < 3; ++k) rgb[k] = (1.0f - a) + a * tint[r][k];
      if (box_edge) rgb[0] = rgb[1] = rgb[2] = 0.0f;
      if (head_edge) rgb[0] = 0.0f, rgb[1] = 0.7f, rgb[2] = 0.0f;
      for (int k = 0; k < 3; ++k) img.at(i, j, k) = rgb[k] * rgb[k];  // image_io writes sRGB from linear
    }
  write_image(path, img);
}

// The interior rays of one held-out view for LeakSplit's holes (see there): for each marched pixel in
// the head's interior, the zone and 20 mm height bin of its true surface point and its gate.
void interior_rays(const dataset::Frame& fr, const Image& matte, const Image& depth, const LeakSplit& leak,
                   int stride, std::vector<int>* zone, std::vector<int>* y_bin, std::vector<float>* gate) {
  const int w = int(fr.camera.width) / stride, h = int(fr.camera.height) / stride;
  const std::vector<uint8_t> interior = render::head_interior_mask(matte);
  std::vector<std::array<float, 3>> wall(size_t(matte.height), {0, 0, 0});
  for (int py = 0; py < matte.height; ++py) {
    double sum[3] = {0, 0, 0}, n = 0;
    for (int px = 0; px < matte.width; ++px)
      if (matte.at(px, py, 0) < 0.01f) {
        for (int c = 0; c < 3; ++c) sum[c] += fr.image.at(px, py, c);
        n += 1;
      }
    for (int c = 0; c < 3; ++c) wall[py][c] = n > 0 ? float(sum[c] / n) : (py > 0 ? wall[py - 1][c] : 0.0f);
  }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int px = x * stride + stride / 2, py = y * stride + stride / 2;
      if (!interior[size_t(py) * matte.width + px] || !std::isfinite(depth.at(px, py, 0))) continue;
      const fit::Ray r = fit::camera_ray(fr.camera, {px + 0.5, py + 0.5});
      const Eigen::Vector3d p = r.origin + double(depth.at(px, py, 0)) * r.dir;
      const size_t i = size_t(y) * w + x;
      (*zone)[i] = leak.zone_of(p);
      (*y_bin)[i] = int(std::floor(leak.height_depth(p)[0] / 20.0));
      const float target[3] = {fr.image.at(px, py, 0), fr.image.at(px, py, 1), fr.image.at(px, py, 2)};
      (*gate)[i] =
          render_ray_room_gate(target, wall[py].data(), nerf::BackgroundOptions{}.room_clear_tolerance);
    }
}

// What the held-out views see: each view's rays (every `stride`-th pixel) marched through the model's
// box at its step, the field's density queried at the samples in occupied cells, and each sample's
// compositing weight (T * alpha) added to its region. Returns the mean weight per ray in each region
// and writes one picture per view: white where nothing is seen, else the regions' colours
// (grey: head, red: box but not head, blue: corners) mixed by their weights.
std::array<double, 3> seen_opacity(cl::Runtime& rt, nerf::NerfModel& model, const dataset::Dataset& ds,
                                   const nerf::SubjectVolume& box, const nerf::SubjectVolume& head,
                                   const std::function<double(const Eigen::Vector3d&)>& head_z_mm,
                                   const std::string& picture_prefix, int stride, size_t max_views,
                                   std::map<int, std::array<double, 3>>* seen_depth, LeakSplit* leak) {
  const nerf::Aabb& bb = model.aabb();
  const nerf::OccupancyGrid& occ = model.occupancy();
  const float step = model.step();
  std::array<double, 3> total{0, 0, 0};
  size_t rays_total = 0, views = 0;
  for (const dataset::Frame* fr : ds.require_split(dataset::Split::Holdout)) {
    if (views >= max_views) break;
    const int w = int(fr->camera.width) / stride, h = int(fr->camera.height) / stride;
    struct Sample {
      uint32_t ray;
      uint8_t region, zone;
      int16_t depth_bin;     // head-frame z, 10 mm bins
      int16_t y_bin, z_bin;  // head-frame y and z, 20 mm bins (the leak's place)
      nerf::Vec3f q;         // normalised position
    };
    // The true matte at each ray's pixel (the leak's split), or none.
    const Image *matte = nullptr, *depth = nullptr;
    if (leak) {
      auto it = leak->mattes.find(fs::path(fr->image_path).stem().string());
      if (it != leak->mattes.end()) matte = &it->second.first, depth = &it->second.second;
    }
    std::vector<float> room(size_t(w) * h, 0.0f);  // 1 - matte per judged ray
    // Interior rays: the zone and height of their true surface point and their pixel's gate; -1 else.
    std::vector<int> hole_zone(size_t(w) * h, -1), hole_y(size_t(w) * h, 0);
    std::vector<float> hole_gate(size_t(w) * h, 0.0f);
    if (matte) interior_rays(*fr, *matte, *depth, *leak, stride, &hole_zone, &hole_y, &hole_gate);
    if (matte)
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const int px = x * stride + stride / 2, py = y * stride + stride / 2;
          if (!render::judged_pixel(fr->camera, *matte, depth, px, py, bb)) continue;
          const float m = matte->at(px, py, 0);
          room[size_t(y) * w + x] = 1.0f - m, leak->subject += m >= 0.5f;
        }
    std::vector<Sample> samples;
    std::vector<int> crossing(size_t(w) * h, 99);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        fit::Ray r = fit::camera_ray(fr->camera, {(x + 0.5) * stride, (y + 0.5) * stride});
        Eigen::Vector3d o = r.origin * model.normalisation.scale +
                            Eigen::Vector3d(model.normalisation.offset[0], model.normalisation.offset[1],
                                            model.normalisation.offset[2]);
        double t0 = 0.0, t1 = 1e30;
        for (int a = 0; a < 3; ++a) {
          double inv = 1.0 / r.dir[a], ta = (bb.min[a] - o[a]) * inv, tb = (bb.max[a] - o[a]) * inv;
          t0 = std::max(t0, std::min(ta, tb)), t1 = std::min(t1, std::max(ta, tb));
        }
        int growth = 99;  // the smallest growth of the certain interior this ray crosses
        for (double t = t0 + 0.5 * step; t < t1; t += step) {
          Eigen::Vector3d p = o + t * r.dir;
          if (matte && !leak->grown_solid.empty()) {
            const Eigen::Vector3d pg =
                (p - Eigen::Vector3d(model.normalisation.offset[0], model.normalisation.offset[1],
                                     model.normalisation.offset[2])) /
                model.normalisation.scale;
            for (int g = 0; g < std::min(growth, 6); ++g)
              if (leak->grown_solid[g].contains(vec(pg))) {
                growth = g;
                break;
              }
          }
          nerf::Vec3f q;
          for (int a = 0; a < 3; ++a)
            q[a] = std::clamp(float((p[a] - bb.min[a]) / bb.extent(a)), 0.0f, 0.999999f);
          uint32_t cx = uint32_t(q[0] * occ.res), cy = uint32_t(q[1] * occ.res),
                   cz = uint32_t(q[2] * occ.res);
          uint64_t c = cx + uint64_t(occ.res) * (cy + uint64_t(occ.res) * cz);
          if (!((occ.bits[c >> 5] >> (c & 31u)) & 1u)) continue;
          // Region from the dataset-frame point (the volumes are in the dataset's scene).
          Eigen::Vector3d pd =
              (p - Eigen::Vector3d(model.normalisation.offset[0], model.normalisation.offset[1],
                                   model.normalisation.offset[2])) /
              model.normalisation.scale;
          const double z_mm = head_z_mm(pd);
          Sample s{uint32_t(y * w + x),
                   uint8_t(region_of(vec(pd), box, head)),
                   0,
                   int16_t(std::floor(z_mm / 10.0)),
                   0,
                   0,
                   q};
          if (matte && room[s.ray] > 0.0f) {
            const Eigen::Vector2d yz = leak->height_depth(pd);
            s.zone = uint8_t(leak->zone_of(pd));
            s.y_bin = int16_t(std::floor(yz[0] / 20.0)), s.z_bin = int16_t(std::floor(yz[1] / 20.0));
          }
          samples.push_back(s);
        }
        if (matte) crossing[size_t(y) * w + x] = growth;
      }
    std::vector<nerf::Vec3f> points(samples.size());
    for (size_t i = 0; i < samples.size(); ++i) points[i] = samples[i].q;
    const std::vector<float> sig = field::density_at(model.field(), rt, points);
    std::vector<std::array<float, 3>> per_ray(size_t(w) * h, {0, 0, 0});
    std::vector<float> T(size_t(w) * h, 1.0f);
    for (size_t i = 0; i < samples.size(); ++i) {  // samples are in ray order, near to far
      const Sample& s = samples[i];
      const float a = 1.0f - std::exp(-sig[i] * step), wgt = T[s.ray] * a;
      per_ray[s.ray][s.region] += wgt;
      (*seen_depth)[s.depth_bin][s.region] += wgt;
      if (matte && room[s.ray] > 0.0f) {
        leak->zone[s.zone] += wgt * room[s.ray];
        leak->yz[{s.y_bin, s.z_bin}][s.zone] += wgt * room[s.ray];
      }
      T[s.ray] *= 1.0f - a;
    }
    for (int i = 0; i < w * h; ++i) {
      if (hole_zone[i] < 0) continue;
      const bool hole = T[i] > 0.5f;
      leak->interior[hole_zone[i]] += 1, leak->holes[hole_zone[i]] += hole;
      leak->gate[hole_zone[i]] += hole_gate[i], leak->hole_gate[hole_zone[i]] += hole ? hole_gate[i] : 0.0f;
      leak->holes_y[hole_y[i]][0] += 1, leak->holes_y[hole_y[i]][1] += hole;
      for (int g = crossing[i]; g < 6; ++g) leak->cross_interior[g] += 1, leak->cross_holes[g] += hole;
    }
    if (matte)
      for (int i = 0; i < w * h; ++i)
        for (int g = crossing[i]; g < 6 && room[i] > 0.0f; ++g)
          leak->cross_leak[g] += (per_ray[i][0] + per_ray[i][1] + per_ray[i][2]) * room[i];
    Image img(w, h, 3);
    const float tint[3][3] = {{0.25f, 0.25f, 0.25f}, {0.9f, 0.1f, 0.1f}, {0.1f, 0.3f, 0.95f}};
    for (int i = 0; i < w * h; ++i) {
      float rgb[3] = {T[i], T[i], T[i]};
      for (int r = 0; r < 3; ++r) {
        total[r] += per_ray[i][r];
        for (int k = 0; k < 3; ++k) rgb[k] += per_ray[i][r] * tint[r][k];
      }
      for (int k = 0; k < 3; ++k) img.pixels[size_t(i) * 3 + k] = rgb[k] * rgb[k];
    }
    rays_total += size_t(w) * h;
    write_image(fmt::format("{}_seen_{}.png", picture_prefix, views), img);
    ++views;
  }
  for (double& t : total) t /= double(std::max<size_t>(rays_total, 1));
  for (auto& [bin, v] : *seen_depth)
    for (double& t : v) t /= double(std::max<size_t>(rays_total, 1));
  return total;
}

}  // namespace

static int run(int argc, char** argv) {
  CLI::App app{"where a subject model's density lies in its head frame"};
  std::string out = "head_volume_bench";
  std::vector<std::string> case_args;
  app.add_option("out", out, "output directory")->required();
  app.add_option("--case", case_args, "NAME MODEL DATASET (repeatable)")->expected(3)->take_all();
  int stride = 4;
  size_t max_views = 4;
  app.add_option("--stride", stride, "held-out pixels: every N-th in x and y (default 4)");
  app.add_option("--views", max_views, "held-out views marched (default 4)");
  fit::HeadBoxOptions head_options;
  app.add_option("--hair", head_options.extents.hair_mm,
                 "the head box's hair allowance (mm), as train --hair (default 30)");
  CLI11_PARSE(app, argc, argv);
  cl::Runtime rt;
  if (case_args.empty() || case_args.size() % 3) {
    spdlog::error("give at least one --case NAME MODEL DATASET");
    return 2;
  }
  fs::create_directories(out);
  std::vector<std::vector<std::string>> rows, depth_rows, seen_rows, leak_rows, leak_yz_rows;
  for (size_t k = 0; k + 2 < case_args.size(); k += 3) {
    Case cs{case_args[k], case_args[k + 1], case_args[k + 2]};
    dataset::Dataset ds = dataset::load_dataset(cs.data, {});
    fit::HeadBox b = fit::estimate_head_box(capture::posed_photos(ds), head_options);
    Grid g;
    g.snap = nerf::read_snapshot(cs.model);
    const uint32_t res = g.snap.occ.res;
    g.cell = (g.snap.aabb.extent(0) + g.snap.aabb.extent(1) + g.snap.aabb.extent(2)) / (3.0f * float(res));
    spdlog::info("{}: {}; model box [{:.3f} {:.3f} {:.3f}] .. [{:.3f} {:.3f} {:.3f}], cell {:.1f} mm",
                 cs.name, b.summary(), g.snap.aabb.min[0], g.snap.aabb.min[1], g.snap.aabb.min[2],
                 g.snap.aabb.max[0], g.snap.aabb.max[1], g.snap.aabb.max[2], g.cell * b.head.mm_per_unit);
    nerf::SubjectVolume box = capture::head_volume(b, capture::HeadVolumeShape::OrientedBox);
    nerf::SubjectVolume head = capture::head_volume(b, capture::HeadVolumeShape::Head);
    uint64_t occupied[3] = {0, 0, 0}, solid[3] = {0, 0, 0}, cells[3] = {0, 0, 0};
    double alpha_sum[3] = {0, 0, 0};
    std::map<int, std::array<uint64_t, 3>> depth;  // 10 mm bins of head-frame z
    for (uint32_t z = 0; z < res; ++z)
      for (uint32_t y = 0; y < res; ++y)
        for (uint32_t x = 0; x < res; ++x) {
          const uint64_t c = x + uint64_t(res) * (y + uint64_t(res) * z);
          nerf::Vec3f p;
          const uint32_t q[3] = {x, y, z};
          for (int a = 0; a < 3; ++a)
            p[a] = g.snap.aabb.min[a] + (float(q[a]) + 0.5f) / float(res) * g.snap.aabb.extent(a);
          const int r = region_of(p, box, head);
          ++cells[r];
          const float al = g.alpha(c);
          if (!((g.snap.occ.bits[c >> 5] >> (c & 31u)) & 1u)) continue;
          ++occupied[r], alpha_sum[r] += al;
          if (al > 0.5f) {
            ++solid[r];
            Eigen::Vector3d mm =
                b.axes.transpose() * (Eigen::Vector3d(p[0], p[1], p[2]) - b.anchor) * b.head.mm_per_unit;
            depth[int(std::floor(mm.z() / 10.0))][r]++;
          }
        }
    for (int r = 0; r < 3; ++r) {
      spdlog::info("{}: {:>13}: {:6} cells, {:6} occupied, {:6} solid (opacity > 0.5), opacity sum {:.0f}",
                   cs.name, kRegionNames[r], cells[r], occupied[r], solid[r], alpha_sum[r]);
      rows.push_back({cs.name, kRegionNames[r], std::to_string(cells[r]), std::to_string(occupied[r]),
                      std::to_string(solid[r]), fmt::format("{:.1f}", alpha_sum[r])});
    }
    for (const auto& [bin, n] : depth)
      depth_rows.push_back({cs.name, std::to_string(bin * 10), std::to_string(n[0]), std::to_string(n[1]),
                            std::to_string(n[2])});
    nerf::NerfModel model = nerf::NerfModel::load(rt, cs.model);
    std::map<int, std::array<double, 3>> seen_depth;
    auto head_z = [&](const Eigen::Vector3d& p) {
      return b.head.d_fwd.dot(p - b.anchor) * b.head.mm_per_unit;
    };
    // The leak's split, where the dataset has true mattes.
    LeakSplit leak;
    for (const auto& [stem, files] : synth::eval_files_by_stem(cs.data))
      leak.mattes.emplace(stem, std::make_pair(synth::read_matte(cs.data + "/" + files.matte),
                                               read_image(cs.data + "/" + files.depth)));
    const nerf::SubjectVolume keep = capture::head_clear_keep(b), core = capture::head_clear_core(b);
    for (double g : kGrowthMm) {
      nerf::SubjectVolume v = capture::head_solid_core(b);
      for (nerf::OrientedShape& part : v.parts) part = part.grown(float(g / b.head.mm_per_unit));
      leak.grown_solid.push_back(v);
    }
    leak.zone_of = [&](const Eigen::Vector3d& p) {
      const nerf::Vec3f v = vec(p);
      return keep.contains(v) ? kKeep : core.contains(v) ? kCore : head.contains(v) ? kLean : kOutside;
    };
    leak.height_depth = [&](const Eigen::Vector3d& p) -> Eigen::Vector2d {
      const double s = b.head.mm_per_unit;
      return {s * b.head.d_up.dot(p - b.anchor), s * b.head.d_fwd.dot(p - b.anchor)};
    };
    std::array<double, 3> seen =
        seen_opacity(rt, model, ds, box, head, head_z, (fs::path(out) / cs.name).string(), stride, max_views,
                     &seen_depth, leak.mattes.empty() ? nullptr : &leak);
    if (leak.subject > 0.0) {
      const double k = 100.0 / leak.subject;
      spdlog::info(
          "{}: leak {:.2f} % of the subject's area: keep {:.2f}, core {:.2f}, lean {:.2f}, outside {:.2f}",
          cs.name, k * (leak.zone[0] + leak.zone[1] + leak.zone[2] + leak.zone[3]), k * leak.zone[0],
          k * leak.zone[1], k * leak.zone[2], k * leak.zone[3]);
      for (int z = 0; z < 4; ++z)
        spdlog::info(
            "{}: interior rays on {:>7}: {:5.0f}, holes {:5.0f} ({:5.1f} %), gate mean {:.2f} (holes {:.2f})",
            cs.name, kZoneNames[z], leak.interior[z], leak.holes[z],
            100.0 * leak.holes[z] / std::max(leak.interior[z], 1.0),
            leak.gate[z] / std::max(leak.interior[z], 1.0), leak.hole_gate[z] / std::max(leak.holes[z], 1.0));
      for (int g = 0; g < 6; ++g)
        spdlog::info(
            "{}: rays crossing the certain interior grown by {:2.0f} mm: {:5.0f} interior rays, {:4.0f} "
            "holes of {:4.0f}; {:.2f} % leak of {:.2f}",
            cs.name, kGrowthMm[g], leak.cross_interior[g], leak.cross_holes[g],
            leak.holes[0] + leak.holes[1] + leak.holes[2] + leak.holes[3], k * leak.cross_leak[g],
            k * (leak.zone[0] + leak.zone[1] + leak.zone[2] + leak.zone[3]));
      for (const auto& [bin, v] : leak.holes_y)
        spdlog::info("{}: head-frame height {:4} mm: {:4.0f} interior rays, {:4.0f} holes", cs.name, bin * 20,
                     v[0], v[1]);
      for (int z = 0; z < 4; ++z)
        leak_rows.push_back({cs.name, kZoneNames[z], fmt::format("{:.4f}", k * leak.zone[z])});
      for (const auto& [bin, v] : leak.yz)
        leak_yz_rows.push_back({cs.name, std::to_string(bin.first * 20), std::to_string(bin.second * 20),
                                fmt::format("{:.4f}", k * v[0]), fmt::format("{:.4f}", k * v[1]),
                                fmt::format("{:.4f}", k * v[2]), fmt::format("{:.4f}", k * v[3])});
    }
    for (auto& [bin, v] : seen_depth) {
      seen_rows.push_back({cs.name, std::to_string(bin * 10), fmt::format("{:.5f}", v[0]),
                           fmt::format("{:.5f}", v[1]), fmt::format("{:.5f}", v[2])});
    }
    spdlog::info(
        "{}: held-out views see opacity {:.4f} in the head, {:.4f} in the box outside it, {:.4f} in "
        "the corners (mean per ray)",
        cs.name, seen[0], seen[1], seen[2]);
    std::vector<Camera> train_cameras;
    for (const dataset::Frame* fr : ds.require_split(dataset::Split::Train))
      train_cameras.push_back(fr->camera);
    const auto t0 = std::chrono::steady_clock::now();
    const nerf::SubjectCutReport cut =
        nerf::check_subject_cut(model, train_cameras, capture::head_cut_rim(b));
    spdlog::info("{}: {} ({:.2f} s)", cs.name, cut.summary(),
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    for (int r = 0; r < 3; ++r) {
      rows[rows.size() - 3 + r].push_back(fmt::format("{:.4f}", seen[r]));
      rows[rows.size() - 3 + r].push_back(fmt::format("{:.5f}", cut.rim_share));
      rows[rows.size() - 3 + r].push_back(fmt::format("{:.5f}", cut.sides_share));
    }
    write_view((fs::path(out) / (cs.name + "_side.png")).string(), g, b, box, head, 2, 1, 0);
    write_view((fs::path(out) / (cs.name + "_top.png")).string(), g, b, box, head, 0, 2, 1);
  }
  write_csv((fs::path(out) / "head_volume.csv").string(),
            {"case", "region", "cells", "occupied", "solid", "opacity_sum", "seen_opacity_per_ray",
             "rim_share", "rim_sides_share"},
            rows);
  write_csv((fs::path(out) / "head_volume_seen_depth.csv").string(),
            {"case", "depth_mm", "seen_head", "seen_box_not_head", "seen_corners"}, seen_rows);
  if (!leak_rows.empty()) {
    write_csv((fs::path(out) / "head_volume_leak.csv").string(), {"case", "zone", "leak_pct"}, leak_rows);
    write_csv((fs::path(out) / "head_volume_leak_yz.csv").string(),
              {"case", "y_mm", "z_mm", "keep_pct", "core_pct", "lean_pct", "outside_pct"}, leak_yz_rows);
  }
  write_csv((fs::path(out) / "head_volume_depth.csv").string(),
            {"case", "depth_mm", "solid_head", "solid_box_not_head", "solid_corners"}, depth_rows);
  return 0;
}

int main(int argc, char** argv) {
  // A missing model, dataset or true matte is a message and exit status 1, not an abort.
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    spdlog::error("head_volume_bench: {}", e.what());
    return 1;
  }
}
