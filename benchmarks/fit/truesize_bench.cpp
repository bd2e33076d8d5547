// bench_truesize: the scale chain against synthetic ground truth (#44). For each trained model and
// the synthetic dataset it was trained on, the fit as `lorgnette fit` runs it (its default settings,
// scale policy auto) with metadata.metric_scale removed (a capture without a card: the irises, else
// the mean face, whose own figure the fit keeps); the card's figures (the scale `train` wrote into
// the header from the capture's scale.json) follow from the same fit. Against ground_truth.json:
// each source's mm per unit (per model unit through the model's normalisation) and PD (pd_mm), the
// stated uncertainties, and the iris measure's own error against the painted iris (iris_diameter_mm:
// the method's error apart from the population's). Also the card step's
// seconds in `capture` (DATASET/card.json, `capture --card-only --json`), the fit's "scale" stage (the iris
// renders and measure) and the training's seconds (DATASET/train_seconds.json, when the script wrote it).
// Writes OUT.csv (one row per capture) and beside it OUT.png (the scale errors per capture).
//
//   bench_truesize GLASSES OUT.csv MODEL DATASET [MODEL DATASET ...]
#include <fmt/format.h>
#include <spdlog/cfg/env.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "fit/fit_job.h"
#include "host/dataset/dataset.h"
#include "host/util/chart.h"
#include "host/util/image_io.h"

using namespace lorgnette;
using namespace lorgnette::fit;

namespace {

struct Row {
  std::string name, source, iris_why;
  double truth = NAN, painted = NAN, pd_true = NAN, face_width = NAN;
  double card = NAN, card_unc = NAN, card_pd = NAN, card_pd_unc = NAN, card_s = NAN;
  double iris = NAN, iris_unc = NAN, iris_pd = NAN, iris_measured_mm = NAN;
  double mean_face = NAN, mean_face_pd = NAN;
  double pd_unc = NAN, iris_s = NAN, fit_s = NAN, train_s = NAN;
  int iris_views = 0;
};

double stage_seconds(const FitResult& r, const std::string& name) {
  for (const auto& [n, s] : r.seconds)
    if (n == name) return s;
  return NAN;
}

nlohmann::json read_json_or_empty(const std::string& path) {
  std::ifstream in(path);
  if (!in) return nlohmann::json::object();
  return nlohmann::json::parse(in, nullptr, false);
}

double number_or_nan(const nlohmann::json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_number() ? j[key].get<double>() : NAN;
}

// The irises' mean diameter over the views where an edge was found (model units; NaN when none),
// whether or not iris_scale() accepted them: the measure's own error is wanted either way.
double mean_iris_diameter(const std::vector<IrisMeasurement>& ms, int* n) {
  double s = 0;
  *n = 0;
  for (const IrisMeasurement& m : ms) {
    std::cerr << fmt::format("  eye {:+d}: {} {:.2f} px {:.4f} units, {} rows, step {:.2f} {}\n", m.eye,
                             m.edges.found ? "found" : "none", m.edges.diameter_px, m.diameter_units,
                             m.edges.rows, m.edges.relative_step, m.edges.why);
    if (m.edges.found && m.diameter_units > 0) s += m.diameter_units, ++*n;
  }
  return *n ? s / *n : NAN;
}

Row measure(const std::string& model_path, const std::string& dataset, const GlassesInput& glasses,
            cl::Runtime& rt) {
  nerf::NerfModel m = nerf::NerfModel::load(rt, model_path);
  dataset::LoadOptions lo;
  lo.load_images = false;
  const dataset::Dataset ds = dataset::load_dataset(dataset, lo);
  if (!ds.mm_per_unit)
    throw std::runtime_error("'" + dataset + "' has no mm_per_unit in its ground_truth.json");
  Row w;
  w.name = std::filesystem::path(model_path).stem().string();
  w.truth = *ds.mm_per_unit / m.normalisation.scale;  // mm per model unit
  w.pd_true = number_or_nan(ds.ground_truth, "pd_mm");
  w.painted = number_or_nan(ds.ground_truth, "iris_diameter_mm");
  w.face_width = number_or_nan(ds.ground_truth, "face_width_temples_mm");
  w.card_s = number_or_nan(read_json_or_empty(dataset + "/card.json"), "seconds");
  w.train_s = number_or_nan(read_json_or_empty(dataset + "/train_seconds.json"), "seconds");
  NerfViewOptions views;
  views.dataset = dataset;
  // One fit, without the card (a capture without one: the irises, else the mean face). With a card the
  // fit takes the model's metric_scale as its mm per unit and PD in units times it (scale_chain.h), so
  // the card's figures follow from the same fit: PD's sigma has the scale's share replaced.
  const std::optional<nerf::MetricScale> card = m.metadata.metric_scale;
  m.metadata.metric_scale.reset();
  const FitResult r = run_fit_job(m, glasses, fit_options(FitSettings{}), views).fit;
  const double pd_units = r.head.pd_mm / r.scale.mm_per_unit;  // PD in units does not depend on the scale
  if (card) {
    w.card = card->mm_per_unit, w.card_unc = card->uncertainty, w.card_pd = pd_units * w.card;
    const double eyes2 =
        std::pow(r.pd_uncertainty_mm, 2) - std::pow(r.head.pd_mm * r.scale.relative_uncertainty(), 2);
    w.card_pd_unc = std::sqrt(std::pow(w.card_pd * w.card_unc / w.card, 2) +
                              std::max(0.0, eyes2) * std::pow(w.card / r.scale.mm_per_unit, 2));
  }
  w.source = scale_source_name(r.scale.source);
  w.iris_why = r.iris.why;
  if (r.iris.ok) w.iris = r.iris.mm_per_unit, w.iris_unc = r.iris.mm_per_unit_uncertainty;
  w.iris_pd = pd_units * w.iris;
  w.iris_measured_mm = mean_iris_diameter(r.iris_measurements, &w.iris_views) * w.truth;
  w.mean_face = r.scale.mean_face_mm_per_unit, w.mean_face_pd = pd_units * w.mean_face;
  w.pd_unc = r.pd_uncertainty_mm;
  w.iris_s = stage_seconds(r, "scale"), w.fit_s = r.total_seconds();
  return w;
}

std::vector<std::string> header() {
  return {"case",
          "true_mm_per_unit",
          "iris_painted_mm",
          "pd_true_mm",
          "face_width_temples_mm",
          "card_error_pct",
          "card_uncertainty_pct",
          "card_pd_error_mm",
          "card_pd_uncertainty_mm",
          "card_seconds",
          "iris_error_pct",
          "iris_uncertainty_pct",
          "iris_pd_error_mm",
          "iris_measured_mm",
          "iris_method_error_pct",
          "iris_views",
          "mean_face_error_pct",
          "mean_face_pd_error_mm",
          "no_card_source",
          "no_card_pd_uncertainty_mm",
          "iris_seconds",
          "fit_seconds",
          "train_seconds",
          "iris_why"};
}

std::vector<std::string> cells(const Row& w) {
  auto f = [](double v, int digits) { return std::isfinite(v) ? fmt::format("{:.{}f}", v, digits) : ""; };
  auto pct = [&](double v) { return 100.0 * (v / w.truth - 1.0); };
  std::string why = w.iris_why;
  for (char& ch : why)
    if (ch == ',' || ch == '"') ch = ';';
  return {w.name,
          f(w.truth, 4),
          f(w.painted, 3),
          f(w.pd_true, 2),
          f(w.face_width, 2),
          f(pct(w.card), 3),
          f(100 * w.card_unc / w.card, 3),
          f(w.card_pd - w.pd_true, 2),
          f(w.card_pd_unc, 2),
          f(w.card_s, 2),
          f(pct(w.iris), 3),
          f(100 * w.iris_unc / w.iris, 3),
          f(w.iris_pd - w.pd_true, 2),
          f(w.iris_measured_mm, 3),
          f(100 * (w.iris_measured_mm / w.painted - 1), 2),
          std::to_string(w.iris_views),
          f(pct(w.mean_face), 3),
          f(w.mean_face_pd - w.pd_true, 2),
          w.source,
          f(w.pd_unc, 2),
          f(w.iris_s, 2),
          f(w.fit_s, 2),
          f(w.train_s, 1),
          why};
}

// Scale error per capture for each source, and the iris measure's own error (against the paint).
void chart(const std::string& path, const std::vector<Row>& rows) {
  std::vector<ChartSeries> s = {{"card", {}, {}, true},
                                {"irises", {}, {}, true},
                                {"iris diameter vs paint", {}, {}, true},
                                {"mean face", {}, {}, true}};
  for (size_t i = 0; i < rows.size(); ++i) {
    const Row& w = rows[i];
    const double ys[4] = {100 * (w.card / w.truth - 1), 100 * (w.iris / w.truth - 1),
                          100 * (w.iris_measured_mm / w.painted - 1), 100 * (w.mean_face / w.truth - 1)};
    for (int k = 0; k < 4; ++k)
      if (std::isfinite(ys[k])) s[k].x.push_back(double(i + 1)), s[k].y.push_back(ys[k]);
  }
  write_chart(path, {"Scale error per capture (true size, #44)", "capture (CSV row)", "error, %"}, s);
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
    std::vector<Row> rows;
    std::vector<std::vector<std::string>> table;
    for (int i = 3; i + 1 < argc; i += 2) {
      rows.push_back(measure(argv[i], argv[i + 1], glasses, rt));
      table.push_back(cells(rows.back()));
      std::string line;
      for (const auto& c : table.back()) line += c + ",";
      std::cerr << line << "\n";
    }
    const std::string csv = argv[2];
    write_csv(csv, header(), table);
    const std::string png = std::filesystem::path(csv).replace_extension(".png").string();
    chart(png, rows);
    std::cerr << "wrote " << csv << " and " << png << "\n";
  } catch (const std::exception& e) {
    std::cerr << "bench_truesize: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
