// Fit accuracy and time on trained NeRFs of synthetic subjects (issue 5): for each case (a .lnerf
// and the dataset it was trained on, made by `lorgnette synth`), the subject's mesh is rebuilt from
// the dataset's ground_truth.json (the mesh file, or the procedural head from its seed) and placed in
// the model frame; ground truth is the same detector on renders of that mesh, each 2D landmark ray
// cast onto it (fit/mesh_ground_truth.h), from a 9 x 5 grid of views over the fit's cap (yaw -20..20,
// pitch -15..15; --gt-yaws / --gt-pitches). The fit then runs on the NeRF under several option
// variants, interleaved per repeat so that machine load hits them alike, and on the mesh itself
// (the method's error without the NeRF). Also a per-view profile of rendering vs detection.
// Usage: bench_fit_nerf OUT_DIR --case NAME MODEL.lnerf DATASET_DIR [--case ...]
//        [--variants baseline,overlap,hog,crop75,crop65,step15,fast,fast_k8,thr50,...]
//        [--gt-shading studio|camera] [--gt-contour side|all] [--gt-yaws a,b,...] [--gt-pitches a,b,...]
//        [--repeats N] [--glasses FILE] [--debug] [--mesh-only] [--no-profile]
//        [--time-case NAME MODEL.lnerf]   (a real capture: the variants timed, no ground truth)
//        bench_fit_nerf OUT_DIR --replot EARLIER/fit_nerf.csv   (the charts again, from a CSV)
// Writes OUT_DIR/fit_nerf.csv (one row per fit), fit_nerf_profile.csv, fit_nerf_time.png,
// fit_nerf_training.png (error against training time, for cases named NAME@N, N seconds or steps) and, with
// --debug, the annotated views of the first fast fit per case in OUT_DIR/<case>-debug/. --mesh-only
// fits the mesh alone (the ground-truth geometry: head pitch, contact slide) and skips the NeRF.
// SPDLOG_LEVEL=debug logs what the fits log at debug level (e.g. each side's lines of creases).
#include <fmt/format.h>
#include <spdlog/cfg/env.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "eval/mesh_ground_truth.h"
#include "fit/camera_math.h"
#include "fit/detect_views.h"
#include "fit/fit.h"
#include "fit/fit_job.h"
#include "fit/glasses_input.h"
#include "fit/landmark_ids.h"
#include "fit/nerf_view_source.h"
#include "fit_variants.h"
#include "host/util/chart.h"
#include "host/util/machine.h"
#include "subject_mesh.h"

using namespace lorgnette;
using namespace lorgnette::fit;
namespace fs = std::filesystem;

namespace {

const std::string kData = LORGNETTE_DATA_DIR;
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

struct Case {
  std::string name, model, dataset;
  bool timed_only = false;  // --time-case: a real capture, no mesh: time and placement, no errors
};

struct Row {
  std::string name, variant;
  int repeat = 0;
  FitErrors e;
  FitErrors own;  // against ground truth from the fit's own cameras (mesh_ground_truth overload)
  double seconds = 0, load_seconds = 0, front_penetration = 0;
  double cpu_seconds =
      0;  // process CPU time (user + sys, all threads) of the whole fit, detector load included
  double pd_mm = 0, slide_mm = 0;
  // Signed offsets along the ground truth's d_fwd (mm, + = in front): the nose point, the temples.
  double nose_fwd_mm = 0, temple_l_fwd_mm = 0, temple_r_fwd_mm = 0;
  // The ears' error split along the ground truth's d_up (+ = above; it pitches the frame) and d_fwd
  // (+ = in front; along the ear root's flat top, where the rest is loosely defined).
  double ear_l_up_mm = NAN, ear_l_fwd_mm = NAN, ear_r_up_mm = NAN, ear_r_fwd_mm = NAN;
  bool timed_only = false;                          // no ground truth: the error columns stay empty
  double contact_shift_mm = 0, head_pitch_deg = 0;  // slide along d_fwd; d_fwd against the scene's horizontal
  double temple_r_mm = 0, temple_l_mm = 0, eye_r_mm = 0, eye_l_mm = 0;  // diagnostics: inputs of Eq. 1-3
  std::string contact;  // stderr only: penetration, temple-tip penetration, temple spreads, ok / warnings
  int views_used = 0, views = 0;
  std::string stages, error;
  // Against the procedural head's anatomical ear rests (synth's ear_rest_l/r, the crease above the
  // ear's root): the ears, and the frame's turn from the placement that the true nose point and those
  // rests give (NaN where the dataset has none). ears_from: density / mirrored / eq23.
  double ear_l_anat_mm = NAN, ear_r_anat_mm = NAN, rotation_anat_deg = NAN;
  double ear_l_anat_fwd_mm = NAN, ear_r_anat_fwd_mm = NAN;  // of which along the head's d_fwd
  std::string ears_from;
};

// Scores the fit that `fit` runs (with `opt`) against the ground truth (none: timed only).
Row run_fit(const std::function<FitResult()>& fit, const GlassesInput& g, const GroundTruth* gt_or_none,
            const FitOptions& opt, const Eigen::Vector3d& scene_up, MeshViewSource* mesh = nullptr,
            const Anatomy& anat = {}) {
  Row row;
  try {
    const double cpu0 = process_cpu_seconds();
    FitResult r = fit();
    row.cpu_seconds = process_cpu_seconds() - cpu0;
    row.pd_mm = r.head.pd_mm, row.slide_mm = r.contact.shift_mm;
    row.timed_only = gt_or_none == nullptr;
    for (const auto& [name, s] : r.seconds) {
      if (name == "load_detector")
        row.load_seconds += s;  // a one-off per process in a real app
      else
        row.seconds += s;
      row.stages += fmt::format("{}{}={:.3f}", row.stages.empty() ? "" : ";", name, s);
    }
    row.views_used = r.views_used;
    row.views = int(r.views.size());
    const EarRoots& roots = r.ear_roots;
    row.ears_from = roots.use == EarRoots::Use::kBoth       ? "density"
                    : roots.use == EarRoots::Use::kMirrored ? "mirrored"
                                                            : "eq23";
    if (!gt_or_none) return row;
    const GroundTruth& gt = *gt_or_none;
    row.e = compare_fit(r, gt);
    if (anat.known) {
      const double mm = gt.head.mm_per_unit;
      row.ear_l_anat_mm = (r.ears.f_l - anat.ear_l).norm() * mm;
      row.ear_r_anat_mm = (r.ears.f_r - anat.ear_r).norm() * mm;
      row.ear_l_anat_fwd_mm = (r.ears.f_l - anat.ear_l).dot(gt.head.d_fwd.normalized()) * mm;
      row.ear_r_anat_fwd_mm = (r.ears.f_r - anat.ear_r).dot(gt.head.d_fwd.normalized()) * mm;
      PlaceInputs truth{gt.f_c, anat.ear_l, anat.ear_r, gt.points[lm::kTempleL], gt.points[lm::kTempleR], mm};
      const Placement p = place_glasses(g.ref, truth, r.scale_policy);
      row.rotation_anat_deg =
          std::abs(Eigen::AngleAxisd(r.placement.rotation * p.rotation.transpose()).angle()) * 180.0 / M_PI;
    }
    if (mesh) {
      std::vector<Camera> cams;
      for (const auto& v : r.views) cams.push_back(v.camera);
      FitOptions gt_opt = opt;  // the same contour rule as the main ground truth
      gt_opt.landmarks.contour.side_tolerance = gt.contour_side_tolerance;
      row.own = compare_fit(r, mesh_ground_truth(*mesh, cams, g.ref, gt_opt));
    }
    row.front_penetration = r.contact.front_penetration_mm;
    row.contact = fmt::format(
        "frame pitch {:.2f} deg (its forward axis against the head's d_up), penetration {:.2f} mm (tips "
        "{:.2f}), "
        "temple spread l/r {:.2f}/{:.2f} deg ({}/{}), ok {}, {} warnings",
        std::asin(std::clamp(r.placement.rotation.col(2).dot(r.head.d_up.normalized()), -1.0, 1.0)) * 180.0 /
            M_PI,
        r.contact.penetration_mm, r.contact.tip_penetration_mm, r.temples.left.spread_deg,
        r.temples.right.spread_deg, r.temples.left.clear ? "clear" : "clipping",
        r.temples.right.clear ? "clear" : "clipping", r.ok, r.warnings.size());
    row.contact_shift_mm = r.contact.shift_mm;
    row.head_pitch_deg =
        std::asin(std::clamp(r.head.d_fwd.dot(scene_up.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
    auto err = [&](int k) { return (r.points[k].position - gt.points[k]).norm() * gt.head.mm_per_unit; };
    row.temple_r_mm = err(lm::kTempleR), row.temple_l_mm = err(lm::kTempleL);
    row.eye_r_mm = err(lm::kEyeOuterR), row.eye_l_mm = err(lm::kEyeOuterL);
    auto fwd = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
      return (a - b).dot(gt.head.d_fwd) * gt.head.mm_per_unit;
    };
    row.nose_fwd_mm = fwd(r.f_c, gt.f_c);
    row.temple_l_fwd_mm = fwd(r.points[lm::kTempleL].position, gt.points[lm::kTempleL]);
    row.temple_r_fwd_mm = fwd(r.points[lm::kTempleR].position, gt.points[lm::kTempleR]);
    auto up = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
      return (a - b).dot(gt.head.d_up.normalized()) * gt.head.mm_per_unit;
    };
    row.ear_l_up_mm = up(r.ears.f_l, gt.ears.f_l), row.ear_l_fwd_mm = fwd(r.ears.f_l, gt.ears.f_l);
    row.ear_r_up_mm = up(r.ears.f_r, gt.ears.f_r), row.ear_r_fwd_mm = fwd(r.ears.f_r, gt.ears.f_r);
  } catch (const std::exception& ex) {
    row.error = ex.what();
  }
  return row;
}

void write_charts(const std::string& out, const std::vector<Row>& rows);

void write_rows(const std::string& out, const std::vector<Row>& rows) {
  std::vector<std::vector<std::string>> csv;
  for (const auto& r : rows) {
    auto e = [&](double v, const char* f) {
      return r.timed_only ? std::string() : fmt::format(fmt::runtime(f), v);
    };
    csv.push_back({r.name,
                   r.variant,
                   std::to_string(r.repeat),
                   e(r.e.nose_mm, "{:.3f}"),
                   e(r.e.ear_l_mm, "{:.3f}"),
                   e(r.e.ear_r_mm, "{:.3f}"),
                   e(r.e.rotation_deg, "{:.3f}"),
                   e(r.own.nose_mm, "{:.3f}"),
                   e(r.own.ear_l_mm, "{:.3f}"),
                   e(r.own.ear_r_mm, "{:.3f}"),
                   e(r.own.rotation_deg, "{:.3f}"),
                   e(r.e.mm_per_unit_rel, "{:.4f}"),
                   fmt::format("{:.3f}", r.front_penetration),
                   fmt::format("{:.2f}", r.contact_shift_mm),
                   e(r.head_pitch_deg, "{:.2f}"),
                   e(r.temple_l_mm, "{:.3f}"),
                   e(r.temple_r_mm, "{:.3f}"),
                   e(r.eye_l_mm, "{:.3f}"),
                   e(r.eye_r_mm, "{:.3f}"),
                   fmt::format("{}/{}", r.views_used, r.views),
                   fmt::format("{:.3f}", r.seconds),
                   fmt::format("{:.3f}", r.load_seconds),
                   fmt::format("{:.3f}", r.cpu_seconds),
                   fmt::format("{:.2f}", r.pd_mm),
                   fmt::format("{:.2f}", r.slide_mm),
                   e(r.nose_fwd_mm, "{:.2f}"),
                   e(r.temple_l_fwd_mm, "{:.2f}"),
                   e(r.temple_r_fwd_mm, "{:.2f}"),
                   r.stages,
                   r.error.empty() ? "ok" : "error: " + r.error.substr(0, 200),
                   std::isnan(r.ear_l_anat_mm) ? "" : fmt::format("{:.3f}", r.ear_l_anat_mm),
                   std::isnan(r.ear_r_anat_mm) ? "" : fmt::format("{:.3f}", r.ear_r_anat_mm),
                   std::isnan(r.rotation_anat_deg) ? "" : fmt::format("{:.3f}", r.rotation_anat_deg),
                   r.ears_from,
                   e(r.ear_l_up_mm, "{:.2f}"),
                   e(r.ear_l_fwd_mm, "{:.2f}"),
                   e(r.ear_r_up_mm, "{:.2f}"),
                   e(r.ear_r_fwd_mm, "{:.2f}"),
                   e(r.ear_l_anat_fwd_mm, "{:.2f}"),
                   e(r.ear_r_anat_fwd_mm, "{:.2f}")});
  }
  write_csv(out + "/fit_nerf.csv",
            {"case",
             "variant",
             "repeat",
             "nose_mm",
             "ear_l_mm",
             "ear_r_mm",
             "rotation_deg",
             "nose_own_views_mm",
             "ear_l_own_views_mm",
             "ear_r_own_views_mm",
             "rotation_own_views_deg",
             "mm_per_unit_rel_err",
             "front_penetration_mm",
             "contact_shift_mm",
             "head_pitch_deg",
             "temple_l_mm",
             "temple_r_mm",
             "eye_l_mm",
             "eye_r_mm",
             "views_used",
             "seconds_excl_model_load",
             "model_load_seconds",
             "cpu_seconds",
             "pd_mm",
             "slide_mm",
             "nose_fwd_mm",
             "temple_l_fwd_mm",
             "temple_r_fwd_mm",
             "stages",
             "status",
             "ear_l_anat_mm",
             "ear_r_anat_mm",
             "rotation_anat_deg",
             "ears_from",
             "ear_l_up_mm",
             "ear_l_fwd_mm",
             "ear_r_up_mm",
             "ear_r_fwd_mm",
             "ear_l_anat_fwd_mm",
             "ear_r_anat_fwd_mm"},
            csv);
  write_charts(out, rows);
}

// The time chart and, for cases named NAME@N, the error-against-training chart.
void write_charts(const std::string& out, const std::vector<Row>& rows) {
  std::vector<ChartSeries> series;
  std::map<std::string, size_t> index;
  for (const auto& r : rows) {
    if (!r.error.empty() || r.variant == "mesh") continue;
    std::string key = r.name + " " + r.variant;
    if (!index.count(key)) index[key] = series.size(), series.push_back({key, {}, {}});
    series[index[key]].x.push_back(r.repeat), series[index[key]].y.push_back(r.seconds);
  }
  if (!series.empty())
    write_chart(out + "/fit_nerf_time.png",
                {"Fit time on a NeRF per variant (excl. dlib model load)", "repeat", "s"}, series);
  // Cases named NAME@N (the same head trained for N seconds or steps): error against training, one
  // line per quantity and variant.
  std::vector<ChartSeries> trained;
  std::map<std::string, size_t> line;
  for (const auto& r : rows) {
    size_t at = r.name.rfind('@');
    if (at == std::string::npos || r.repeat != 0 || r.variant == "mesh" || !r.error.empty()) continue;
    double x = std::atof(r.name.c_str() + at + 1);
    const std::pair<const char*, double> ys[4] = {{"nose mm", r.e.nose_mm},
                                                  {"ear l mm", r.e.ear_l_mm},
                                                  {"ear r mm", r.e.ear_r_mm},
                                                  {"rotation deg", r.e.rotation_deg}};
    for (const auto& [what, y] : ys) {
      std::string key = std::string(what) + " " + r.variant;
      if (!line.count(key)) line[key] = trained.size(), trained.push_back({key, {}, {}});
      trained[line[key]].x.push_back(x), trained[line[key]].y.push_back(y);
    }
  }
  if (!trained.empty())
    write_chart(out + "/fit_nerf_training.png",
                {"Fit error against NeRF training", "training (the N of case NAME@N: seconds or steps)",
                 "error (mm, deg)"},
                trained);
}

// --replot CSV: the rows of an earlier run (its fit_nerf.csv), with the columns the charts need.
std::vector<Row> read_rows(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path + ": give the fit_nerf.csv of an earlier run");
  std::vector<Row> rows;
  std::string text;
  std::getline(in, text);  // header (write_rows' column order)
  while (std::getline(in, text)) {
    std::vector<std::string> f;
    std::stringstream ss(text);
    for (std::string cell; std::getline(ss, cell, ',');) f.push_back(cell);
    if (f.size() < 24)  // 24 before the cpu_seconds ... temple_r_fwd_mm columns, 30 since
      throw std::runtime_error(path + ": a row has " + std::to_string(f.size()) + " columns, not 24 or 30");
    Row r;
    r.name = f[0], r.variant = f[1], r.repeat = std::atoi(f[2].c_str());
    r.e.nose_mm = std::atof(f[3].c_str()), r.e.ear_l_mm = std::atof(f[4].c_str());
    r.e.ear_r_mm = std::atof(f[5].c_str()), r.e.rotation_deg = std::atof(f[6].c_str());
    r.seconds = std::atof(f[20].c_str());
    if (f.back() != "ok") r.error = f.back();
    rows.push_back(r);
  }
  return rows;
}

// Per view of a cap: full and cropped (0.75) rendering, full-resolution and hinted detection, and
// how far the cropped render and the hinted detection are from the full ones.
void profile(const Case& c, ViewSource& src, const std::vector<ViewRecord>& views, const FitOptions& opt,
             std::vector<std::vector<std::string>>& csv) {
  DetectorOptions full_opt = opt.detection.detector;
  full_opt.hog_face_px = 0.0;
  LandmarkDetector full(full_opt);
  DetectorOptions hinted_opt = opt.detection.detector;
  hinted_opt.hog_face_px = 100.0;
  LandmarkDetector hinted(hinted_opt);
  for (size_t i = 0; i < views.size(); ++i) {
    const double face_px = opt.front.face_fraction * views[i].camera.width;  // the cap's size
    auto t0 = Clock::now();
    Image img = src.render(views[i].camera);
    double tr = since(t0);
    t0 = Clock::now();
    Image crop = render_cropped(src, views[i].camera, 0.75);
    double tc = since(t0);
    t0 = Clock::now();
    FaceDetection a = full.detect(img);
    double tf = since(t0);
    t0 = Clock::now();
    FaceDetection b = hinted.detect(img, face_px);
    double th = since(t0);
    FaceDetection d = hinted.detect(crop, face_px);
    auto worst = [](const FaceDetection& x, const FaceDetection& y) {
      double m = 0.0;
      if (x.found && y.found)
        for (int k = 0; k < 68; ++k) m = std::max(m, (x.points[k] - y.points[k]).norm());
      return m;
    };
    csv.push_back({c.name, std::to_string(i), fmt::format("{:.4f}", tr), fmt::format("{:.4f}", tc),
                   fmt::format("{:.4f}", tf), fmt::format("{:.4f}", th), std::to_string(a.found),
                   std::to_string(b.found), std::to_string(d.found), fmt::format("{:.3f}", worst(a, b)),
                   fmt::format("{:.3f}", worst(a, d))});
  }
}

}  // namespace

static int run(int argc, char** argv) {
  if (argc < 2) {
    std::cerr
        << "usage: bench_fit_nerf OUT_DIR --case NAME MODEL DATASET [...] [--variants a,b] [--repeats N] "
           "[--glasses FILE] [--debug] [--fit-alpha A]\n";
    return 2;
  }
  const std::string out = argv[1];
  std::vector<Case> cases;
  std::string variants = "baseline,fast", glasses = kData + "/glasses/glasses-06/scene.gltf";
  int repeats = 2;
  bool debug = false, studio = true, mesh_only = false, gt_all_views = false, no_profile = false;
  // The ground truth's views: every yaw at every pitch, over the fit's whole cap (CapOptions: yaw
  // -20..20, pitch -15..15). The jaw contour (the temples, hence the ears) slides with the view: on the
  // procedural head the level views alone (yaw -20, -10, 0, 10, 20 at pitch 0, the rule before 25 Nov;
  // --gt-yaws -20,-10,0,10,20 --gt-pitches 0) put its ears up to 7.3 mm from this grid's, and the fit
  // on the exact mesh 4.1-6.3 mm off.
  std::vector<double> gt_yaws = {-20, -15, -10, -5, 0, 5, 10, 15, 20};
  std::vector<double> gt_pitches = {-15, -7.5, 0, 7.5, 15};
  std::string replot;
  // Eq. 3's alpha for the fits only (the ground truth keeps the definition, alpha 0.5): the ear columns
  // then show the ears' move and rotation_deg the frame's turn.
  double fit_alpha = FitOptions{}.head.alpha;
  for (int i = 2; i < argc; ++i) {
    if (std::strcmp(argv[i], "--case") == 0 && i + 3 < argc)
      cases.push_back({argv[i + 1], argv[i + 2], argv[i + 3]}), i += 3;
    else if (std::strcmp(argv[i], "--time-case") == 0 && i + 2 < argc)
      cases.push_back({argv[i + 1], argv[i + 2], "", true}), i += 2;
    else if (std::strcmp(argv[i], "--variants") == 0 && i + 1 < argc)
      variants = argv[++i];
    else if (std::strcmp(argv[i], "--repeats") == 0 && i + 1 < argc)
      repeats = std::atoi(argv[++i]);
    else if (std::strcmp(argv[i], "--glasses") == 0 && i + 1 < argc)
      glasses = argv[++i];
    else if (std::strcmp(argv[i], "--replot") == 0 && i + 1 < argc)
      replot = argv[++i];
    else if (std::strcmp(argv[i], "--fit-alpha") == 0 && i + 1 < argc)
      fit_alpha = std::atof(argv[++i]);
    else if (std::strcmp(argv[i], "--mesh-only") == 0)
      mesh_only = true;
    else if (std::strcmp(argv[i], "--debug") == 0)
      debug = true;
    else if (std::strcmp(argv[i], "--no-profile") == 0)  // skip the per-view profile (one more fit)
      no_profile = true;
    else if (std::strcmp(argv[i], "--gt-yaws") == 0 && i + 1 < argc) {
      gt_yaws.clear();
      for (char* tok = std::strtok(argv[++i], ","); tok; tok = std::strtok(nullptr, ","))
        gt_yaws.push_back(std::atof(tok));
    } else if (std::strcmp(argv[i], "--gt-pitches") == 0 && i + 1 < argc) {
      gt_pitches.clear();
      for (char* tok = std::strtok(argv[++i], ","); tok; tok = std::strtok(nullptr, ","))
        gt_pitches.push_back(std::atof(tok));
    } else if (std::strcmp(argv[i], "--gt-contour") == 0 && i + 1 < argc)
      gt_all_views = std::strcmp(argv[++i], "all") == 0;
    else if (std::strcmp(argv[i], "--gt-shading") == 0 && i + 1 < argc)
      studio = std::strcmp(argv[++i], "camera") != 0;
    else
      return std::cerr << "unknown argument " << argv[i] << "\n", 2;
  }
  // Every name in --variants must be a variant: an unknown one would otherwise be skipped silently,
  // and a caller's table would show no fit at all.
  for (size_t at = 0; at <= variants.size();) {
    const size_t end = std::min(variants.find(',', at), variants.size());
    const std::string name = variants.substr(at, end - at);
    const auto& all = all_variants();
    if (std::none_of(all.begin(), all.end(), [&](const Variant& v) { return v.name == name; })) {
      std::string known;
      for (const Variant& v : all) known += (known.empty() ? "" : ",") + v.name;
      return std::cerr << "--variants: unknown variant '" << name << "' (known: " << known << ")\n", 2;
    }
    at = end + 1;
  }
  if (cases.empty() && replot.empty()) return 0;  // nothing to fit: the arguments were checked
  fs::create_directories(out);
  if (!replot.empty()) {  // charts only: the CSV is not rewritten
    try {
      write_charts(out, read_rows(replot));
    } catch (const std::exception& ex) {
      return std::cerr << "--replot: " << ex.what() << "\n", 1;
    }
    return 0;
  }
  cl::Runtime rt;
  GlassesInput g = load_glasses_input(glasses, 2000);
  std::vector<Row> rows;
  std::vector<std::vector<std::string>> prof;
  for (const Case& c : cases) {
    nerf::NerfModel model = nerf::NerfModel::load(rt, c.model);
    if (c.timed_only) {  // a real capture: the variants timed, interleaved, no ground truth
      for (int rep = 0; rep < repeats; ++rep)
        for (const Variant& v : all_variants()) {
          if (("," + variants + ",").find("," + v.name + ",") == std::string::npos) continue;
          FitOptions o;
          plain(o);
          v.set(o);
          NerfViewOptions views;  // the capture's cameras from the model's metadata
          views.render.step_scale = v.step_scale;
          if (v.min_transmittance > 0.0f) views.render.min_transmittance = v.min_transmittance;
          Row row = run_fit([&] { return run_fit_job(model, g, o, views).fit; }, g, nullptr, o,
                            Eigen::Vector3d::UnitY());
          row.name = c.name, row.variant = v.name, row.repeat = rep;
          std::cerr << fmt::format(
              "{} {} #{}: PD {:.2f} mm, slide {:.2f} mm, {:.2f} s, {:.2f} CPU s [{}] {}\n", c.name, v.name,
              rep, row.pd_mm, row.slide_mm, row.seconds, row.cpu_seconds, row.stages,
              row.error.substr(0, 160));
          rows.push_back(row);
          write_rows(out, rows);
        }
      continue;
    }
    ViewPrior prior = prior_from_transforms(c.dataset + "/transforms.json", model);
    auto nerf_views = [&](float step_scale, float min_transmittance = 0.0f) {  // run_fit_job's views
      NerfViewOptions views;
      views.dataset = c.dataset;
      views.render.step_scale = step_scale;
      if (min_transmittance > 0.0f) views.render.min_transmittance = min_transmittance;
      return views;
    };
    auto mesh_src = subject_source(c.dataset, model, prior, studio);
    const Anatomy anat = anatomy_of(c.dataset, model);
    FitOptions base;
    FitResult ref = fit_glasses(*mesh_src, g, base);
    // Ground truth per jaw-contour view rule: each variant is scored against the mesh under its own
    // rule (the landmark's definition); --gt-contour all scores every variant against all views.
    std::map<double, GroundTruth> gts;
    auto gt_for = [&](const FitOptions& o) -> const GroundTruth& {
      FitOptions gt_opt = base;
      gt_opt.landmarks.contour.side_tolerance = gt_all_views ? 1e9 : o.landmarks.contour.side_tolerance;
      auto it = gts.find(gt_opt.landmarks.contour.side_tolerance);
      if (it == gts.end()) {
        std::vector<Camera> cams;
        for (double pitch : gt_pitches)
          for (double yaw : gt_yaws) cams.push_back(orbit_camera(ref.orbit, yaw, pitch));
        it = gts.emplace(gt_opt.landmarks.contour.side_tolerance,
                         mesh_ground_truth(*mesh_src, cams, g.ref, gt_opt))
                 .first;
      }
      return it->second;
    };
    const GroundTruth& gt = gt_for(base);
    std::cerr << fmt::format(
        "{}: ground truth from {} x {} views (yaw x pitch), mm/unit {:.2f}, PD {:.1f} mm\n", c.name,
        gt_yaws.size(), gt_pitches.size(), gt.head.mm_per_unit, gt.head.pd_mm);
    FitOptions mesh_opt = base;
    mesh_opt.head.alpha = fit_alpha;
    Row mesh_row = run_fit([&] { return fit_glasses(*mesh_src, g, mesh_opt); }, g, &gt, mesh_opt, prior.up,
                           nullptr, anat);
    mesh_row.name = c.name, mesh_row.variant = "mesh";
    rows.push_back(mesh_row);
    std::cerr << fmt::format(
        "{} mesh (alpha {:.2f}): nose {:.2f} mm, ears {:.2f}/{:.2f} mm, rot {:.2f} deg (anatomical: ears "
        "{:.2f}/{:.2f} rot {:.2f}, {}), head pitch {:.1f} deg, contact shift {:.2f} mm, {}\n",
        c.name, fit_alpha, mesh_row.e.nose_mm, mesh_row.e.ear_l_mm, mesh_row.e.ear_r_mm,
        mesh_row.e.rotation_deg, mesh_row.ear_l_anat_mm, mesh_row.ear_r_anat_mm, mesh_row.rotation_anat_deg,
        mesh_row.ears_from, mesh_row.head_pitch_deg, mesh_row.contact_shift_mm, mesh_row.contact);
    if (mesh_only) {
      write_rows(out, rows);
      continue;
    }
    for (int rep = 0; rep < repeats; ++rep)
      for (const Variant& v : all_variants()) {
        if (("," + variants + ",").find("," + v.name + ",") == std::string::npos) continue;
        FitOptions o = base;
        plain(o);
        v.set(o);
        o.head.alpha = fit_alpha;
        if (debug && rep == 0 && v.name == "fast") o.debug_dir = out + "/" + c.name + "-debug";
        if (!o.debug_dir.empty()) fs::create_directories(o.debug_dir);
        const NerfViewOptions views = nerf_views(v.step_scale, v.min_transmittance);
        Row row = run_fit([&] { return run_fit_job(model, g, o, views).fit; }, g, &gt_for(o), o, prior.up,
                          mesh_src.get(), anat);
        row.name = c.name, row.variant = v.name, row.repeat = rep;
        std::cerr << fmt::format(
            "{} {} #{}: nose {:.2f} mm ({:+.1f} fwd), ears {:.2f}/{:.2f} mm (temples {:+.1f}/{:+.1f} fwd), "
            "rot "
            "{:.2f} deg (own views: ears {:.2f}/{:.2f}; anatomical: ears {:.2f}/{:.2f} rot {:.2f}, {}), "
            "{:.2f} s, "
            "{:.2f} CPU s [{}] {} {}\n",
            c.name, v.name, rep, row.e.nose_mm, row.nose_fwd_mm, row.e.ear_l_mm, row.e.ear_r_mm,
            row.temple_l_fwd_mm, row.temple_r_fwd_mm, row.e.rotation_deg, row.own.ear_l_mm, row.own.ear_r_mm,
            row.ear_l_anat_mm, row.ear_r_anat_mm, row.rotation_anat_deg, row.ears_from, row.seconds,
            row.cpu_seconds, row.stages, row.contact, row.error.substr(0, 160));
        rows.push_back(row);
        write_rows(out, rows);
      }
    if (no_profile) continue;
    FitOptions po = base;
    try {
      FitResult pr = run_fit_job(model, g, po, nerf_views(1.0f)).fit;
      NerfViewSource src(model, prior);
      profile(c, src, pr.views, po, prof);
    } catch (const std::exception& ex) {  // a model the fit fails on (its rows say why): no profile
      std::cerr << c.name << ": no per-view profile: " << ex.what() << "\n";
    }
    write_csv(
        out + "/fit_nerf_profile.csv",
        {"case", "view", "render_s", "render_crop75_s", "detect_full_s", "detect_hinted_s", "found_full",
         "found_hinted", "found_crop75", "hinted_max_landmark_diff_px", "crop75_max_landmark_diff_px"},
        prof);
  }
  write_rows(out, rows);
  return 0;
}

int main(int argc, char** argv) {
  spdlog::cfg::load_env_levels();
  // A missing model, dataset or glasses file is a message and exit status 1, not an abort.
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "bench_fit_nerf: " << e.what() << "\n";
    return 1;
  }
}
