// Study (not a benchmark): where the fit puts the ears (paper Eq. 2-3) on a synthetic subject's exact
// mesh, against the ground truth of bench_fit_nerf (fit/mesh_ground_truth.h: the same detector on level
// views of the mesh at yaw -20..20) and, for the procedural head, against what synth knows exactly
// (its ear rests and ear tops, and Eq. 2-3 on its exact iBUG points). Per case it prints, in the ground
// truth's head frame (mm from f_c: x = d_eye towards the wearer's left, y = d_up, z = d_fwd), the
// temples (dlib 0 / 16 cast onto the skin) and ear points of the fit, of the level-view ground truth
// and of the ground truth from the fit's own views; then the temple hit of every view of a yaw x pitch
// grid (near-side views only, as the fit casts them); and draws each ear from the side with the points.
// Usage: ear_study OUT_DIR --case NAME MODEL.lnerf DATASET [--case ...] [--alpha A]
// Writes OUT_DIR/ear_points.csv, ear_gt_sets.csv (the ground truth's rule on other view sets), ear_views.csv,
// ear_same_frame.csv (the ear search on the mesh's and the NeRF's density from one frame: the ground
// truth's, then that of the fit on the NeRF at the true scale, whose landmarks the product's search hangs
// its window from), ear_profiles.csv (its rays' heights at every depth of the window) with
// OUT_DIR/<case>_ear_profile_{l,r}[_nerf_fit].png (at the mesh's rest depth) and
// OUT_DIR/<case>_ear_{l,r}.png.
#include <fmt/format.h>
#include <spdlog/cfg/env.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <tuple>

#include "eval/mesh_ground_truth.h"
#include "fit/camera_math.h"
#include "fit/debug_draw.h"
#include "fit/fit.h"
#include "fit/glasses_input.h"
#include "fit/landmark_ids.h"
#include "fit/nerf_view_source.h"
#include "fit/surface_landmarks.h"
#include "host/util/chart.h"
#include "subject_mesh.h"

using namespace lorgnette;
using namespace lorgnette::fit;
using V3 = Eigen::Vector3d;

namespace {

struct Frame {  // the ground truth's head frame, in mm from its f_c
  V3 o, x, y, z;
  double mm;
  V3 operator()(const V3& p) const {
    V3 q = p - o;
    return V3(q.dot(x), q.dot(y), q.dot(z)) * mm;
  }
};

std::string str(const V3& p) { return fmt::format("({:7.1f} {:7.1f} {:7.1f})", p.x(), p.y(), p.z()); }

struct Mark {
  int landmark = -1;  // a per-view temple hit: drawn on that temple's side only
  std::string label;
  V3 p;  // scene
  cv::Scalar bgr;
  bool ring;
};

}  // namespace

int main(int argc, char** argv) {
  spdlog::cfg::load_env_levels();  // SPDLOG_LEVEL=debug: what the fit logs at debug level
  if (argc < 6)
    return std::cerr << "usage: ear_study OUT_DIR --case NAME MODEL DATASET [...] [--alpha A]\n", 2;
  const std::string out = argv[1];
  struct Case {
    std::string name, model, dataset;
  };
  std::vector<Case> cases;
  double alpha = 0.5;
  for (int i = 2; i < argc; ++i) {
    if (std::strcmp(argv[i], "--case") == 0 && i + 3 < argc)
      cases.push_back({argv[i + 1], argv[i + 2], argv[i + 3]}), i += 3;
    else if (std::strcmp(argv[i], "--alpha") == 0 && i + 1 < argc)
      alpha = std::atof(argv[++i]);
    else
      return std::cerr << "unknown argument " << argv[i] << "\n", 2;
  }
  std::filesystem::create_directories(out);
  cl::Runtime rt;
  GlassesInput glasses =
      load_glasses_input(std::string(LORGNETTE_DATA_DIR) + "/glasses/glasses-06/scene.gltf", 500);
  GlassesInput ref_only;  // the ears do not depend on the frame's points: no contact stage
  ref_only.ref = glasses.ref;
  std::vector<std::vector<std::string>> points_csv, views_csv, sets_csv, same_frame_csv, profile_csv;
  for (const Case& c : cases) {
    nerf::NerfModel model = nerf::NerfModel::load(rt, c.model);
    ViewPrior prior = prior_from_transforms(c.dataset + "/transforms.json", model);
    auto mesh = subject_source(c.dataset, model, prior, true);
    FitOptions base;
    base.head.alpha = alpha;
    FitResult fit = fit_glasses(*mesh, ref_only, base);
    GroundTruth gt = mesh_ground_truth(*mesh, fit.orbit, {-20, -10, 0, 10, 20}, glasses.ref, base);
    std::vector<Camera> own_cams;
    for (const auto& v : fit.views) own_cams.push_back(v.camera);
    GroundTruth own = mesh_ground_truth(*mesh, own_cams, glasses.ref, base);
    const Frame H{gt.f_c, gt.head.d_eye, gt.head.d_up, gt.head.d_fwd, gt.head.mm_per_unit};
    // The same ground-truth rule on other view sets: how much the definition itself moves.
    {
      std::vector<Camera> level9, grid;
      for (double yaw = -20; yaw <= 20; yaw += 5) level9.push_back(orbit_camera(fit.orbit, yaw, 0.0));
      for (double pitch = -15; pitch <= 15; pitch += 7.5)
        for (double yaw = -20; yaw <= 20; yaw += 5) grid.push_back(orbit_camera(fit.orbit, yaw, pitch));
      const double fit_pitch =
          std::asin(std::clamp(fit.head.d_fwd.dot(gt.head.d_up), -1.0, 1.0)) * 180.0 / M_PI;
      std::cout << fmt::format(
          "   {}: the fit's d_fwd is {:+.2f} deg up from the level-view ground truth's\n", c.name, fit_pitch);
      for (auto [name, cams] :
           {std::pair<const char*, const std::vector<Camera>*>{"level 9 (yaw -20..20 step 5)", &level9},
            {"cap grid 9x5 (pitch -15..15)", &grid},
            {"the fit's 12 views", &own_cams}}) {
        GroundTruth g = mesh_ground_truth(*mesh, *cams, glasses.ref, base);
        FitErrors e = compare_fit(fit, g);
        const double dl = (g.ears.f_l - gt.ears.f_l).norm() * gt.head.mm_per_unit,
                     dr = (g.ears.f_r - gt.ears.f_r).norm() * gt.head.mm_per_unit;
        std::cout << fmt::format(
            "   gt on {:30s}: its ears {:.2f} / {:.2f} mm from the level-5 gt's; the fit's ears {:.2f} / "
            "{:.2f} mm, rotation {:.2f} deg from it\n",
            name, dl, dr, e.ear_l_mm, e.ear_r_mm, e.rotation_deg);
        sets_csv.push_back({c.name, name, fmt::format("{:.2f}", dl), fmt::format("{:.2f}", dr),
                            fmt::format("{:.2f}", e.ear_l_mm), fmt::format("{:.2f}", e.ear_r_mm),
                            fmt::format("{:.2f}", e.rotation_deg)});
      }
      FitErrors e = compare_fit(fit, gt);
      sets_csv.push_back({c.name, "level 5 (yaw -20..20 step 10; the benchmark's until 25 Nov)", "0", "0",
                          fmt::format("{:.2f}", e.ear_l_mm), fmt::format("{:.2f}", e.ear_r_mm),
                          fmt::format("{:.2f}", e.rotation_deg)});
      std::cout << fmt::format(
          "   gt on level 5 (the benchmark's until 25 Nov): the fit's ears {:.2f} / {:.2f} mm, rotation "
          "{:.2f} "
          "deg\n",
          e.ear_l_mm, e.ear_r_mm, e.rotation_deg);
    }
    // What synth knows (procedural head): dataset frame -> model frame.
    std::ifstream in(c.dataset + "/ground_truth.json");
    nlohmann::json truth = nlohmann::json::parse(in);
    auto to_model = [&](const nlohmann::json& j) {
      V3 q(j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>());
      q *= model.normalisation.scale;
      for (int i = 0; i < 3; ++i) q[i] += model.normalisation.offset[i];
      return q;
    };
    std::cout << fmt::format(
        "== {}: head frame of the level-view ground truth (mm from its f_c; x = d_eye, y = d_up, z = "
        "d_fwd)\n",
        c.name);
    std::cout << fmt::format("   fit views {} (yaw/pitch:", fit.views.size());
    for (const auto& v : fit.views) std::cout << fmt::format(" {:.0f}/{:.0f}", v.yaw_deg, v.pitch_deg);
    std::cout << ")\n";
    auto row = [&](const std::string& side, const std::string& what, const V3& p) {
      V3 h = H(p);
      std::cout << fmt::format("   {} {:28s} {}\n", side, what, str(h));
      points_csv.push_back({c.name, side, what, fmt::format("{:.2f}", h.x()), fmt::format("{:.2f}", h.y()),
                            fmt::format("{:.2f}", h.z())});
    };
    std::map<std::string, V3> anat;
    for (const char* name : {"ear_rest_l", "ear_rest_r", "ear_top_l", "ear_top_r"})
      if (truth.contains("landmarks") && truth["landmarks"].contains(name))
        anat[name] = to_model(truth["landmarks"][name]);
    std::optional<EarPoints> exact_ears;
    std::vector<V3> ibug;
    if (truth.contains("ibug68") && truth["ibug68"].size() == 68) {
      for (const auto& p : truth["ibug68"]) ibug.push_back(to_model(p));
      EarInputs ei{ibug[lm::kEyeOuterL], ibug[lm::kEyeOuterR], ibug[lm::kTempleL],
                   ibug[lm::kTempleR],   gt.head.d_up,         gt.head.d_fwd};
      exact_ears = ear_points(ei, alpha);
    }
    for (int side : {+1, -1}) {
      const char* s = side > 0 ? "l" : "r";
      const int k = side > 0 ? lm::kTempleL : lm::kTempleR, e = side > 0 ? lm::kEyeOuterL : lm::kEyeOuterR;
      auto pick = [&](const EarPoints& ep) { return side > 0 ? ep.f_l : ep.f_r; };
      row(s, "eye corner: fit", fit.points[e].position);
      row(s, "eye corner: gt", gt.points[e]);
      row(s, "temple: fit", fit.points[k].position);
      row(s, "temple: gt (level views)", gt.points[k]);
      row(s, "temple: gt (fit's views)", own.points[k]);
      row(s, "ear: fit", pick(fit.ears));
      row(s, "ear: gt (level views)", pick(gt.ears));
      row(s, "ear: gt (fit's views)", pick(own.ears));
      V3 d = H(pick(fit.ears)) - H(pick(gt.ears));
      std::cout << fmt::format("   {} fit - gt: dx {:+.1f} dy {:+.1f} dz {:+.1f} mm, |d| {:.2f} mm\n", s,
                               d.x(), d.y(), d.z(), d.norm());
      if (!ibug.empty()) {
        row(s, "temple: exact iBUG (frontal)", ibug[k]);
        row(s, "ear: Eq.2-3 on exact iBUG", pick(*exact_ears));
      }
      for (const char* what : {"ear_rest_", "ear_top_"})
        if (anat.count(std::string(what) + s))
          row(s, std::string(what) + s + " (synth)", anat[std::string(what) + s]);
    }
    // The ear search from one frame: the ground truth's temples, eye corners and axes, on the mesh's
    // density and on the NeRF's. What differs between the two is the density alone (a fit's own
    // landmarks and frame move its rests too).
    {
      NerfViewSource nerf(model, prior);
      const DensityFn on_mesh = [&](const std::vector<Eigen::Vector3f>& p) { return mesh->density(p); };
      const DensityFn on_nerf = [&](const std::vector<Eigen::Vector3f>& p) { return nerf.density(p); };
      // And from the frame of the fit on the NeRF (at the true scale, as a card's): what the product's
      // search reads on the NeRF, and what it would read on the mesh from the same landmarks.
      FitOptions on_true_scale = base;
      if (truth.contains("mm_per_unit"))
        on_true_scale.scale.card =
            CaptureScale{"card", truth["mm_per_unit"].get<double>() / model.normalisation.scale, 0.0};
      const FitResult nerf_fit = fit_glasses(nerf, ref_only, on_true_scale);
      std::vector<V3> nerf_points;
      for (const auto& p : nerf_fit.points) nerf_points.push_back(p.position);
      auto deg = [](const V3& a, const V3& b) {
        return std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180 / M_PI;
      };
      std::cout << fmt::format(
          "   the NeRF fit: temples l {} r {}, outer eye corners l {} r {}; its d_up {:.2f} deg and d_fwd "
          "{:.2f} "
          "deg from the ground truth's, {:.2f} mm per unit (ground truth {:.2f})\n",
          str(H(nerf_points[lm::kTempleL])), str(H(nerf_points[lm::kTempleR])),
          str(H(nerf_points[lm::kEyeOuterL])), str(H(nerf_points[lm::kEyeOuterR])),
          deg(nerf_fit.head.d_up, gt.head.d_up), deg(nerf_fit.head.d_fwd, gt.head.d_fwd),
          nerf_fit.head.mm_per_unit, gt.head.mm_per_unit);
      struct SearchFrame {
        std::string name, suffix;
        const std::vector<V3>* points;
        const HeadFrame* head;
      };
      for (const SearchFrame& sf :
           {SearchFrame{"the ground truth's", "", &gt.points, &gt.head},
            SearchFrame{"the NeRF fit's", " from the nerf fit", &nerf_points, &nerf_fit.head}})
        for (int side : {+1, -1}) {
          const int k = side > 0 ? lm::kTempleL : lm::kTempleR,
                    e = side > 0 ? lm::kEyeOuterL : lm::kEyeOuterR;
          if (side > 0)
            std::cout << fmt::format(
                "   the ear search from {} frame (mm in the ground truth's head frame):\n", sf.name);
          const EarRootInputs in{(*sf.points)[k],     (*sf.points)[e], sf.head->d_eye,
                                 sf.head->d_up,       sf.head->d_fwd,  side,
                                 sf.head->mm_per_unit};
          // The NeRF at the rays' default opacity and at 0.5 (where a render shows the surface): a NeRF's
          // soft ear top is met deeper at the higher level (ear_root.h). Then the rays' heights across the
          // side near the mesh's rest depth (the mesh goes first): what the search reads there.
          const double level = base.head.ear_root.rays.opacity;
          // The chart shows the grid's depth nearest the mesh's rest, which lies 9 mm behind a line's
          // front end and so between the grid's depths (ear_root.h).
          std::optional<double> mesh_rest_depth, chart_depth;
          std::vector<ChartSeries> series;
          for (auto [what, fn, opacity] :
               {std::tuple<std::string, const DensityFn*, double>{"mesh" + sf.suffix, &on_mesh, level},
                {fmt::format("nerf at opacity {:.2f}{}", level, sf.suffix), &on_nerf, level},
                {"nerf at opacity 0.50" + sf.suffix, &on_nerf, 0.5}}) {  // (no commas: the CSVs' fields)
            EarRootOptions o = base.head.ear_root;
            o.rays.opacity = opacity;
            const std::vector<EarRootSide> lines = find_ear_root_lines(*fn, in, o);
            if (fn == &on_mesh && lines.front().found) mesh_rest_depth = lines.front().depth_mm;
            for (const EarRootSide& line : lines) {
              if (!line.found) {
                std::cout << fmt::format("   {} {}: {}\n", side > 0 ? "l" : "r", what, line.why);
                continue;
              }
              std::cout << fmt::format(
                  "   {} {}: rest {} height {:+.1f} depth {:+.1f} ({:+.0f}..{:+.0f}, {} depths, {} on the "
                  "top) "
                  "lateral {:+.1f}, {:.0f} deg\n",
                  side > 0 ? "l" : "r", what, str(H(line.point)), line.height_mm, line.depth_mm, line.back_mm,
                  line.front_mm, line.slices, line.plateau, line.lateral_mm, line.bend_deg);
              same_frame_csv.push_back(
                  {c.name, side > 0 ? "l" : "r", what, fmt::format("{:.2f}", line.height_mm),
                   fmt::format("{:.2f}", line.depth_mm), fmt::format("{:.2f}", line.lateral_mm),
                   fmt::format("{:.0f}", line.back_mm), fmt::format("{:.0f}", line.front_mm),
                   std::to_string(line.slices), fmt::format("{:.1f}", line.bend_deg)});
            }
            // Every depth of the window into the CSV (what the search reads at each), the one nearest
            // the mesh's rest into the chart.
            const std::vector<double> depths =
                ear_grid(-o.rays.back_mm, o.rays.front_mm, o.rays.depth_step_mm);
            if (mesh_rest_depth && !chart_depth)
              chart_depth = *std::min_element(depths.begin(), depths.end(), [&](double a, double b) {
                return std::abs(a - *mesh_rest_depth) < std::abs(b - *mesh_rest_depth);
              });
            ChartSeries cs{what, {}, {}};
            for (const EarRootProfile& p : ear_root_profiles(*fn, in, o, depths))
              for (size_t j = 0; j < p.lateral_mm.size(); ++j) {
                if (std::isnan(p.height_mm[j])) continue;
                if (chart_depth && std::abs(p.depth_mm - *chart_depth) < 1e-6)
                  cs.x.push_back(p.lateral_mm[j]), cs.y.push_back(p.height_mm[j]);
                profile_csv.push_back({c.name, side > 0 ? "l" : "r", what, fmt::format("{:.0f}", p.depth_mm),
                                       fmt::format("{:.1f}", p.lateral_mm[j]),
                                       fmt::format("{:.2f}", p.height_mm[j])});
              }
            if (!chart_depth) continue;
            series.push_back(std::move(cs));
          }
          if (chart_depth)
            write_chart(fmt::format("{}/{}_ear_profile_{}{}.png", out, c.name, side > 0 ? "l" : "r",
                                    sf.suffix.empty() ? "" : "_nerf_fit"),
                        {fmt::format("{} {}, rays {:+.0f} mm from the temple (the mesh's rest {:+.0f} mm)",
                                     c.name, side > 0 ? "left" : "right", *chart_depth, *mesh_rest_depth),
                         "mm outwards from the temple", "mm above the eye corner"},
                        series);
        }
    }
    // The temple hit per view of a yaw x pitch grid, exact cast, near-side views as the fit uses.
    LandmarkDetector det(base.detection.detector);
    std::vector<Mark> view_marks;
    std::cout
        << "   per view: yaw pitch | right temple (0) hit | left temple (16) hit  (* = not near side)\n";
    for (double pitch : {-15.0, 0.0, 15.0})
      for (double yaw = -30; yaw <= 30; yaw += 10) {
        Camera cam = orbit_camera(fit.orbit, yaw, pitch);
        cam.width = cam.height = 384;
        FaceDetection d = det.detect(mesh->render(cam));
        if (!d.found) {
          std::cout << fmt::format("   {:4.0f} {:4.0f} | no face\n", yaw, pitch);
          continue;
        }
        std::string line = fmt::format("   {:4.0f} {:4.0f}", yaw, pitch);
        for (int k : {lm::kTempleR, lm::kTempleL}) {
          Ray r = camera_ray(cam, d.points[k]);
          mesh::Hit h = mesh->cast(r.origin.cast<float>(), r.dir.cast<float>());
          const bool near = contour_side_visible(k, d, base.landmarks.contour.side_tolerance);
          if (!h.hit) {
            line += " | miss";
            continue;
          }
          V3 p = h.position.cast<double>(), q = H(p);
          line += fmt::format(" | {}{}", str(q), near ? ' ' : '*');
          views_csv.push_back({c.name, fmt::format("{:.0f}", yaw), fmt::format("{:.0f}", pitch),
                               std::to_string(k), near ? "1" : "0", fmt::format("{:.2f}", q.x()),
                               fmt::format("{:.2f}", q.y()), fmt::format("{:.2f}", q.z())});
          if (near) view_marks.push_back({k, "", p, cv::Scalar(0, 200, 255), false});
        }
        std::cout << line << "\n";
      }
    // Each ear from the side: the camera on the head's x axis, 0.35 m out (in mm via the GT scale).
    for (int side : {+1, -1}) {
      const char* s = side > 0 ? "l" : "r";
      const int k = side > 0 ? lm::kTempleL : lm::kTempleR;
      auto pick = [&](const EarPoints& ep) { return side > 0 ? ep.f_l : ep.f_r; };
      const V3 centre = 0.5 * (pick(gt.ears) + gt.points[k]);
      const V3 eye = centre + side * gt.head.d_eye * (350.0 / gt.head.mm_per_unit);
      Camera cam = look_at_camera(eye, centre, gt.head.d_up, 22.0, 512, 512);
      cv::Mat m = to_bgr8(mesh->render(cam));
      std::vector<Mark> marks = view_marks;
      marks.push_back({-1, "gt t", gt.points[k], cv::Scalar(0, 160, 0), true});
      marks.push_back({-1, "gt f", pick(gt.ears), cv::Scalar(0, 160, 0), false});
      marks.push_back({-1, "fit t", fit.points[k].position, cv::Scalar(0, 0, 230), true});
      marks.push_back({-1, "fit f", pick(fit.ears), cv::Scalar(0, 0, 230), false});
      if (exact_ears) marks.push_back({-1, "iBUG f", pick(*exact_ears), cv::Scalar(200, 0, 200), false});
      if (anat.count(std::string("ear_rest_") + s))
        marks.push_back({-1, "rest", anat[std::string("ear_rest_") + s], cv::Scalar(230, 80, 0), false});
      for (const Mark& mk : marks) {
        if (mk.landmark >= 0 && mk.landmark != k) continue;
        Eigen::Vector2d uv;
        if (!camera_project(cam, mk.p, &uv)) continue;
        cv::Point2d pt(uv.x() - 0.5, uv.y() - 0.5);
        if (mk.label.empty())
          cv::circle(m, pt, 2, mk.bgr, -1);
        else if (mk.ring)
          cv::circle(m, pt, 7, mk.bgr, 2);
        else
          cv::drawMarker(m, pt, mk.bgr, cv::MARKER_CROSS, 14, 2);
        if (!mk.label.empty())
          cv::putText(m, mk.label, pt + cv::Point2d(9, -6), cv::FONT_HERSHEY_SIMPLEX, 0.45, mk.bgr, 1);
      }
      cv::putText(
          m, fmt::format("{} {} ear (yellow: per-view temple hits)", c.name, side > 0 ? "left" : "right"),
          cv::Point(8, 20), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1);
      cv::imwrite(fmt::format("{}/{}_ear_{}.png", out, c.name, s), m);
    }
  }
  write_csv(out + "/ear_points.csv", {"case", "side", "point", "x_mm", "y_mm", "z_mm"}, points_csv);
  write_csv(out + "/ear_gt_sets.csv",
            {"case", "gt_views", "gt_ear_l_moved_mm", "gt_ear_r_moved_mm", "fit_ear_l_mm", "fit_ear_r_mm",
             "fit_rotation_deg"},
            sets_csv);
  write_csv(out + "/ear_same_frame.csv",
            {"case", "side", "density", "height_mm", "depth_mm", "lateral_mm", "back_mm", "front_mm",
             "depths", "bend_deg"},
            same_frame_csv);
  write_csv(out + "/ear_profiles.csv", {"case", "side", "density", "depth_mm", "lateral_mm", "height_mm"},
            profile_csv);
  write_csv(out + "/ear_views.csv", {"case", "yaw", "pitch", "landmark", "near_side", "x_mm", "y_mm", "z_mm"},
            views_csv);
  return 0;
}
