// bench_truesize: the scale chain against synthetic ground truth (#44). For each trained model and
// the synthetic dataset it was trained on, the fit as `lorgnette fit` runs it (its default settings,
// scale policy auto); the irises' and the mean face's mm per unit against the dataset's exact one
// (ground_truth.json, per model unit through the model's normalisation), PD from each against the
// distance between the head's pupils, the scale's uncertainty, and the seconds of the fit's "scale"
// stage (the iris renders and measure). One CSV row per capture.
//
//   bench_truesize GLASSES OUT.csv MODEL DATASET [MODEL DATASET ...]
#include <fmt/format.h>
#include <spdlog/cfg/env.h>

#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "fit/fit_job.h"
#include "host/dataset/dataset.h"
#include "host/util/image_io.h"

using namespace lorgnette;
using namespace lorgnette::fit;

namespace {

// The distance between the head's pupils (dataset units), NaN when the ground truth has none.
double pupil_distance(const nlohmann::json& gt) {
  const nlohmann::json* l = gt.contains("landmarks") ? &gt["landmarks"] : nullptr;
  if (!l || !l->contains("pupil_l") || !l->contains("pupil_r")) return NAN;
  double s = 0;
  for (int i = 0; i < 3; ++i)
    s += std::pow((*l)["pupil_l"][i].get<double>() - (*l)["pupil_r"][i].get<double>(), 2);
  return std::sqrt(s);
}

double stage_seconds(const FitResult& r, const std::string& name) {
  for (const auto& [n, s] : r.seconds)
    if (n == name) return s;
  return 0.0;
}

std::string row(const std::string& model, const std::string& dataset, const GlassesInput& glasses,
                cl::Runtime& rt) {
  nerf::NerfModel m = nerf::NerfModel::load(rt, model);
  dataset::LoadOptions lo;
  lo.load_images = false;
  const dataset::Dataset ds = dataset::load_dataset(dataset, lo);
  if (!ds.mm_per_unit)
    throw std::runtime_error("'" + dataset + "' has no mm_per_unit in its ground_truth.json");
  const double truth = *ds.mm_per_unit / m.normalisation.scale;  // mm per model unit
  const double pd_true = pupil_distance(ds.ground_truth) * *ds.mm_per_unit;
  NerfViewOptions views;
  views.dataset = dataset;
  const FitResult r = run_fit_job(m, glasses, fit_options(FitSettings{}), views).fit;
  const double chosen = r.scale.mm_per_unit, mean_face = r.scale.mean_face_mm_per_unit;
  const double pd_units = r.head.pd_mm / chosen;
  const double iris = r.iris.ok ? r.iris.mm_per_unit : NAN;
  auto err = [&](double mpu) { return 100.0 * (mpu / truth - 1.0); };
  return fmt::format(
      "{},{:.4f},{},{:.4f},{:.2f},{:.4f},{:.4f},{:.2f},{:.2f},{:.2f},{:.2f},{:.2f},{:.2f},{:.2f},{:.3f},{:."
      "1f},\"{}\"",
      model, truth, scale_source_name(r.scale.source), iris, err(iris), r.iris.mm_per_unit_uncertainty,
      mean_face, err(mean_face), pd_true, pd_units * iris - pd_true, pd_units * mean_face - pd_true,
      r.head.pd_mm - pd_true, r.pd_uncertainty_mm, err(chosen), stage_seconds(r, "scale"), r.total_seconds(),
      r.iris.why);
}

}  // namespace

int main(int argc, char** argv) {
  spdlog::cfg::load_env_levels();
  if (argc < 5 || (argc - 3) % 2 != 0) {
    std::cerr << "usage: bench_truesize GLASSES OUT.csv MODEL DATASET [MODEL DATASET ...]\n";
    return 2;
  }
  try {
    const GlassesInput glasses = load_glasses_input(argv[1]);
    cl::Runtime rt;
    std::string csv =
        "model,true_mm_per_unit,source,iris_mm_per_unit,iris_error_pct,iris_uncertainty,mean_face_mm_per_"
        "unit,"
        "mean_face_error_pct,pd_true_mm,pd_iris_error_mm,pd_mean_face_error_mm,pd_error_mm,pd_uncertainty_mm,"
        "scale_error_pct,scale_stage_s,fit_s,iris_why\n";
    for (int i = 3; i + 1 < argc; i += 2) {
      csv += row(argv[i], argv[i + 1], glasses, rt) + "\n";
      std::cerr << csv.substr(csv.rfind('\n', csv.size() - 2) + 1);
    }
    write_text_file_atomic(argv[2], csv);
  } catch (const std::exception& e) {
    std::cerr << "bench_truesize: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
