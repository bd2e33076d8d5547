// Fit time and stability study on a mesh ViewSource of the Lee Perry-Smith scan: error (nose, ears,
// rotation vs the ray-cast ground truth) and time against the number of views (3..60), the yaw
// range, detector noise and image resolution. Writes fit_stability.csv and one chart per sweep.
// Usage: bench_fit_stability OUT_DIR [--quick] [--sweeps views,yaw_range,noise_px,resolution,ablation]
// The CSV and charts are rewritten after every row, so an interrupted run keeps what it measured.
#include <fmt/format.h>

#include <cstring>
#include <filesystem>
#include <functional>
#include <iostream>

#include "eval/landmark_noise.h"
#include "eval/mesh_ground_truth.h"
#include "fit/fit.h"
#include "fit/glasses_input.h"
#include "host/util/chart.h"

using namespace lorgnette;
using namespace lorgnette::fit;

namespace {

const std::string kData = LORGNETTE_DATA_DIR;

struct Row {
  std::string sweep;
  double value = 0;
  FitErrors e;
  double seconds = 0, penetration = 0, pd = 0, mm_per_unit = 0;
  int views_used = 0;
  std::string error;
};

Row run(MeshViewSource& src, const GlassesInput& g, const GroundTruth& gt, const std::string& sweep,
        double value, FitOptions opt) {
  Row row;
  row.sweep = sweep;
  row.value = value;
  try {
    FitResult r = fit_glasses(src, g, opt);
    row.e = compare_fit(r, gt);
    for (const auto& [name, s] : r.seconds)
      if (name != "load_detector") row.seconds += s;  // the model load is a one-off 2-3 s
    row.penetration = r.contact.penetration_mm;
    row.pd = r.head.pd_mm;
    row.mm_per_unit = r.head.mm_per_unit;
    row.views_used = r.views_used;
  } catch (const std::exception& ex) {
    row.error = ex.what();
  }
  std::cerr << fmt::format("{} = {}: nose {:.2f} mm, ears {:.2f}/{:.2f} mm, rot {:.2f} deg, {:.2f} s {}\n",
                           sweep, value, row.e.nose_mm, row.e.ear_l_mm, row.e.ear_r_mm, row.e.rotation_deg,
                           row.seconds, row.error.empty() ? "" : "FAILED: " + row.error.substr(0, 120));
  return row;
}

void chart(const std::string& out, const std::string& sweep, const std::string& xlabel,
           const std::vector<Row>& rows) {
  ChartSeries nose, ear, rot, t;
  nose.name = "nose mm", ear.name = "max ear mm", rot.name = "rotation deg", t.name = "seconds";
  for (const auto& r : rows) {
    if (r.sweep != sweep || !r.error.empty()) continue;
    nose.x.push_back(r.value), nose.y.push_back(r.e.nose_mm);
    ear.x.push_back(r.value), ear.y.push_back(std::max(r.e.ear_l_mm, r.e.ear_r_mm));
    rot.x.push_back(r.value), rot.y.push_back(r.e.rotation_deg);
    t.x.push_back(r.value), t.y.push_back(r.seconds);
  }
  if (nose.x.empty()) return;
  write_chart(out + "/fit_" + sweep + ".png",
              {"Fit error and time vs " + xlabel + " (Lee Perry-Smith mesh)", xlabel, "mm / deg / s"},
              {nose, ear, rot, t});
}

}  // namespace

void write_outputs(const std::string& out, const std::vector<Row>& rows) {
  std::vector<std::vector<std::string>> csv;
  for (const auto& r : rows)
    csv.push_back({r.sweep, fmt::format("{}", r.value), fmt::format("{:.4f}", r.e.nose_mm),
                   fmt::format("{:.4f}", r.e.ear_l_mm), fmt::format("{:.4f}", r.e.ear_r_mm),
                   fmt::format("{:.4f}", r.e.rotation_deg), fmt::format("{:.4f}", r.e.mm_per_unit_rel),
                   fmt::format("{:.3f}", r.pd), fmt::format("{:.3f}", r.penetration),
                   std::to_string(r.views_used), fmt::format("{:.3f}", r.seconds),
                   r.error.empty() ? "ok" : "error"});
  write_csv(out + "/fit_stability.csv",
            {"sweep", "value", "nose_mm", "ear_l_mm", "ear_r_mm", "rotation_deg", "mm_per_unit_rel_err",
             "pd_mm", "penetration_mm", "views_used", "seconds", "status"},
            csv);
  chart(out, "views", "number of views K", rows);
  chart(out, "yaw_range", "yaw range +- (deg)", rows);
  chart(out, "noise_px", "detector noise (px, 1 sigma)", rows);
  chart(out, "resolution", "view size (px)", rows);
}

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: bench_fit_stability OUT_DIR [--quick] [--sweeps a,b,...]\n";
    return 2;
  }
  const std::string out = argv[1];
  bool quick = false;
  std::string sweeps = "views,yaw_range,noise_px,resolution,ablation";
  for (int i = 2; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) quick = true;
    if (std::strcmp(argv[i], "--sweeps") == 0 && i + 1 < argc) sweeps = argv[++i];
  }
  auto want = [&](const char* name) { return sweeps.find(name) != std::string::npos; };
  std::filesystem::create_directories(out);
  auto src = MeshViewSource::load(kData + "/heads/lee-perry-smith/LeePerrySmith.glb");
  GlassesInput g = load_glasses_input(kData + "/glasses/glasses-06/scene.gltf", 2000);
  FitOptions base;
  FitResult ref = fit_glasses(*src, g, base);
  GroundTruth gt = mesh_ground_truth(*src, ref.orbit, {-20, -10, 0, 10, 20}, g.ref, base);
  std::cerr << "ground truth: mm/unit " << gt.head.mm_per_unit << ", PD " << gt.head.pd_mm << " mm\n";
  std::vector<Row> rows;
  auto add = [&](const std::string& sweep, double value, const std::function<void(FitOptions&)>& set) {
    FitOptions o = base;
    set(o);
    rows.push_back(run(*src, g, gt, sweep, value, o));
    write_outputs(out, rows);
  };
  add("default", 0, [](FitOptions&) {});
  auto pick = [&](std::vector<double> full, std::vector<double> small) { return quick ? small : full; };
  if (want("views"))
    for (double k : pick({3, 4, 6, 8, 12, 20, 30, 45, 60}, {3, 12}))
      add("views", k, [k](FitOptions& o) { o.cap.views = int(k); });
  if (want("yaw_range"))
    for (double y : pick({5, 10, 20, 35, 45, 60}, {35}))
      add("yaw_range", y, [y](FitOptions& o) { o.cap.yaw_range_deg = y; });
  if (want("noise_px"))
    for (double n : pick({0.5, 1, 2, 4, 8, 16}, {2}))
      add("noise_px", n,
          [n](FitOptions& o) { o.detection.detect = noisy_dlib_detector(o.detection.detector, n, 1); });
  if (want("resolution"))
    for (double w : pick({128, 192, 256, 384, 512, 768}, {256}))
      add("resolution", w, [w](FitOptions& o) { o.front.width = o.front.height = o.cap.size = int(w); });
  if (want("ablation")) {
    add("no_snap", 0, [](FitOptions& o) { o.landmarks.snap_to_skin = false; });
    add("no_snap_no_cast", 0,
        [](FitOptions& o) { o.landmarks.snap_to_skin = false, o.landmarks.cast_contour = false; });
  }
  return 0;
}
