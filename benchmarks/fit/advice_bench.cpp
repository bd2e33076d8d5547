// bench_advice: the fit advice's verdicts against synthetic ground truth (#44). For one trained model
// of a `lorgnette synth --procedural` dataset and a set of frames, each frame is fitted as `lorgnette
// fit` fits it (its default settings), at true size with the head's exact scale (`truth`: given to
// the fit as a card's, so every millimetre error is the advice's own), or with the
// product's scale chain (`chain`: the model's card, else the irises, else the mean face) or the mean
// face's alone (`mean-face`: the demo's case, drawn stretched).
// Each rule's verdict is then compared with the verdict the same rule gives on the head's true numbers:
//   - frame_width: ground_truth.json's face_width_temples_mm (the head's width at the temples);
//   - temple_length: from each hinge of the frame the advice measures (true size, resting) to
//     the head's ear rest (ground_truth.json's landmarks ear_rest_l/r), averaged over the sides;
//   - bridge: the nose's width where the pads rest, measured by the advice's own probe
//     (advice_geometry.h) on the exact head mesh instead of the NeRF's density;
//   - lens_height: the head's pupils (landmarks pupil_l/r) above the placed lenses' centre line.
//     A row `lens_height_landmarks` judges the same fit with the pupils taken as the eyes' landmark
//     means (each eye's six dlib points), the product's stand-in when no limbus is found, against the
//     same truth: the two rows compare the two sources on identical placements.
// One CSV row per frame and rule, with the true difference's distance to the band's nearest edge (the
// issue's criterion: every frame >= 4 mm from a boundary must agree). SOURCE `nerf` fits the trained
// model as the product does; `mesh` fits the head's exact mesh (lit as in the dataset) in the model's
// frame: the advice's own error without the NeRF's.
//
//   bench_advice OUT.csv truth|chain|mean-face nerf|mesh MODEL DATASET FRAME.glb [FRAME.glb ...]
//   bench_advice --chart ADVICE.csv OUT.png   (frame width: the measured difference against the true)
#include <fmt/format.h>
#include <spdlog/cfg/env.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fit/advice_geometry.h"
#include "fit/fit_job.h"
#include "fit/nerf_view_source.h"
#include "host/dataset/dataset.h"
#include "host/util/chart.h"
#include "host/util/image_io.h"
#include "subject_mesh.h"

using namespace lorgnette;
using namespace lorgnette::fit;

namespace {

struct Truth {
  double mm_per_unit = 0;  // per model unit
  double face_width_mm = 0;
  Eigen::Vector3d ear_l, ear_r, pupil_l, pupil_r;  // model frame
  Eigen::Vector3d corner_l, corner_r, temple_l, temple_r,
      nose_bridge;  // the outer eye corners, the temple points
};

Truth read_truth(const std::string& dataset, const nerf::NerfModel& m) {
  std::ifstream in(dataset + "/ground_truth.json");
  if (!in) throw std::runtime_error(dataset + " has no ground_truth.json: it must be a synth dataset");
  const nlohmann::json gt = nlohmann::json::parse(in);
  if (!gt.contains("face_width_temples_mm") || !gt.contains("landmarks"))
    throw std::runtime_error(dataset + "'s ground truth has no face_width_temples_mm: synth it again");
  Truth t;
  t.mm_per_unit = gt.at("mm_per_unit").get<double>() / m.normalisation.scale;
  t.face_width_mm = gt.at("face_width_temples_mm").get<double>();
  auto point = [&](const char* name) {
    const nlohmann::json& p = gt.at("landmarks").contains(name) ? gt.at("landmarks").at(name) : gt.at(name);
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i)
      v[i] = p.at(i).get<double>() * m.normalisation.scale + m.normalisation.offset[i];
    return v;
  };
  t.ear_l = point("ear_rest_l"), t.ear_r = point("ear_rest_r");
  t.pupil_l = point("pupil_l"), t.pupil_r = point("pupil_r");
  t.corner_l = point("eye_l_outer"), t.corner_r = point("eye_r_outer");
  t.nose_bridge = point("nose_bridge");
  t.temple_l = point("temple_l"), t.temple_r = point("temple_r");
  return t;
}

// The true rule for `rule` of the fitted frame (same band and words as the product's), or not judged.
AdviceRule true_rule(const AdviceRule& product, const GlassesInput& g, const FitResult& r, const Truth& t,
                     MeshViewSource& mesh) {
  const Placement& p = r.advice_placement;  // the frame at true size as the advice measures it
  const FrameSizes& f = g.sizes;
  auto canon = [&](const Eigen::Vector3d& q) {
    return canonical_at_true_size(p, g.ref.g_c, t.mm_per_unit, q);
  };
  if (product.name == "frame_width") return frame_width_rule(f.total_width_mm, t.face_width_mm);
  if (product.name == "temple_length" && g.ref.has_hinges)
    return temple_length_rule(f.temple_length_mm, 0.5 * ((g.ref.hinge_l - canon(t.ear_l)).norm() +
                                                         (g.ref.hinge_r - canon(t.ear_r)).norm()));
  if (product.name == "lens_height" || product.name == "lens_height_landmarks")
    return lens_height_rule(0.5 * (canon(t.pupil_l).y() + canon(t.pupil_r).y()) - f.lens_centre_y_mm,
                            f.lens_height_mm);
  if (product.name == "bridge" && f.bridge_mm > 0) {
    std::string why;
    DensityFn density = [&mesh](const std::vector<Eigen::Vector3f>& q) { return mesh.density(q); };
    const double nose = nose_width_mm(density, 1.0f, p, g.ref.g_c, t.mm_per_unit, f.lens_centre_y_mm,
                                      NoseProbeOptions{}, &why);
    if (nose > 0) return bridge_rule(f.bridge_mm, nose);
    return not_judged("bridge", why);
  }
  return not_judged(product.name, "no ground truth");
}

// The mean of one eye's six triangulated landmarks from `first` (36: right eye, 42: left).
Eigen::Vector3d landmark_mean(const std::vector<TriangulatedPoint>& P, int first) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  int n = 0;
  for (int k = first; k < first + 6; ++k)
    if (P[k].ok) c += P[k].position, ++n;
  return n ? Eigen::Vector3d(c / n) : P[first].position;
}

// How far the true difference lies from the band's nearest edge (mm).
double margin_mm(const AdviceRule& truth) {
  return std::min(std::abs(truth.difference_mm - truth.low_mm),
                  std::abs(truth.difference_mm - truth.high_mm));
}

std::vector<std::string> rows_for(const std::string& frame, const std::string& model_path,
                                  const std::string& dataset, const std::string& scale, bool on_mesh,
                                  nerf::NerfModel& m, const Truth& t, MeshViewSource& mesh) {
  const GlassesInput g = load_glasses_input(frame);
  FitOptions o = fit_options(FitSettings{});
  if (scale == "truth") o.scale.card = CaptureScale{"card", t.mm_per_unit, 0.0};
  if (scale == "mean-face") o.scale.irises = false;  // and no card: the mean face's scale, stretch
  NerfViewOptions views;
  views.dataset = dataset;
  const FitResult r = on_mesh ? fit_glasses(mesh, g, o) : run_fit_job(m, g, o, views).fit;
  auto canon = [&](const Eigen::Vector3d& q) {
    return canonical_at_true_size(r.advice_placement, g.ref.g_c, t.mm_per_unit, q);
  };
  const auto& P = r.points;
  std::cerr << fmt::format(
      "contact shift {:.1f} mm; true nose bridge (27) in frame axes: ({:.1f}, {:.1f}, {:.1f}); true pupil l "
      "({:.1f}, {:.1f}, {:.1f})\n",
      r.contact.shift_mm, canon(t.nose_bridge).x(), canon(t.nose_bridge).y(), canon(t.nose_bridge).z(),
      canon(t.pupil_l).x(), canon(t.pupil_l).y(), canon(t.pupil_l).z());
  for (int s = 0; s < 2; ++s) {  // where the fit's eye corners lie from the true ones (frame axes, mm)
    const Eigen::Vector3d d = canon(P[s ? 45 : 36].position) - canon(s ? t.corner_l : t.corner_r);
    const Eigen::Vector3d a =
        canon(s ? r.corner_skin_l : r.corner_skin_r) - canon(s ? t.corner_l : t.corner_r);
    const Eigen::Vector3d tp = canon(s ? t.temple_l : t.temple_r);
    std::cerr << fmt::format(
        "{} eye corner: fit - true = ({:+.1f}, {:+.1f}, {:+.1f}), the advice's (nearest skin) ({:+.1f}, "
        "{:+.1f}, {:+.1f}); true temple point ({:.1f}, {:.1f}, {:.1f})\n",
        s ? "left" : "right", d.x(), d.y(), d.z(), a.x(), a.y(), a.z(), tp.x(), tp.y(), tp.z());
  }
  for (int s = 0; s < 2; ++s) {  // where the fit's ear rests lie from the true ones (frame axes, mm)
    const Eigen::Vector3d d = canon(s ? r.ears.f_l : r.ears.f_r) - canon(s ? t.ear_l : t.ear_r);
    std::cerr << fmt::format(
        "{} ear: fit - true = ({:+.1f}, {:+.1f}, {:+.1f}) mm (x out-of-plane, y up, z fwd); "
        "hinge-to-true-ear {:.1f}\n",
        s ? "left" : "right", d.x(), d.y(), d.z(),
        (canon(s ? t.ear_l : t.ear_r) - (s ? g.ref.hinge_l : g.ref.hinge_r)).norm());
  }
  {  // The width at the temples with the true eye corners and ear rests put in, one at a time, and on
     // the exact mesh: which input the width's error comes from (the fit's placement is kept).
    NerfViewSource nerf(m, prior_from_transforms(dataset + "/transforms.json", m));
    ViewSource& src = on_mesh ? static_cast<ViewSource&>(mesh) : nerf;
    const DensityFn fit_density = [&src](const std::vector<Eigen::Vector3f>& q) { return src.density(q); };
    const DensityFn mesh_density = [&mesh](const std::vector<Eigen::Vector3f>& q) { return mesh.density(q); };
    AdviceHead h;
    h.mm_per_unit = t.mm_per_unit;
    auto width = [&](const DensityFn& d, float thr, const Eigen::Vector3d& cl, const Eigen::Vector3d& cr,
                     const Eigen::Vector3d& el, const Eigen::Vector3d& er) {
      h.corner_l = cl, h.corner_r = cr, h.ear_l = el, h.ear_r = er;
      std::string why;
      return temple_width_mm(d, thr, r.advice_placement, g.ref.g_c, h, {}, &why);
    };
    const float thr = src.surface_density();
    std::cerr << fmt::format(
        "width at the temples (true {:.2f}): true corners and rests {:.2f} on the fit's density, {:.2f} on "
        "the "
        "mesh; the fit's corners with the true rests {:.2f}\n",
        t.face_width_mm, width(fit_density, thr, t.corner_l, t.corner_r, t.ear_l, t.ear_r),
        width(mesh_density, 1.0f, t.corner_l, t.corner_r, t.ear_l, t.ear_r),
        width(fit_density, thr, r.corner_skin_l, r.corner_skin_r, t.ear_l, t.ear_r));
  }
  std::vector<AdviceRule> rules = r.advice.rules;
  for (const AdviceRule& a : r.advice.rules)
    if (a.name == "lens_height" && a.judged()) {
      AdviceRule m =
          lens_height_rule(0.5 * (canon(landmark_mean(P, 42)).y() + canon(landmark_mean(P, 36)).y()) -
                               g.sizes.lens_centre_y_mm,
                           g.sizes.lens_height_mm);
      m.name = "lens_height_landmarks";
      rules.push_back(m);
    }
  std::vector<std::string> rows;
  for (const AdviceRule& a : rules) {
    const AdviceRule tr = true_rule(a, g, r, t, mesh);
    const bool both = a.judged() && tr.judged();
    rows.push_back(fmt::format(
        "{},{},{},{},{:.3f},{:.4f},{},{:.2f},{:.2f},{:.2f},{:.2f},{},{},{:.2f},{},{:.1f}", model_path, frame,
        scale, on_mesh ? "mesh" : "nerf", t.face_width_mm, r.scale.mm_per_unit / t.mm_per_unit - 1.0, a.name,
        a.frame_mm, a.head_mm, tr.head_mm, both ? a.difference_mm - tr.difference_mm : NAN, a.verdict,
        tr.verdict, tr.judged() ? margin_mm(tr) : NAN, both ? (a.verdict == tr.verdict ? "1" : "0") : "",
        r.total_seconds()));
    std::cerr << rows.back() << "\n";
  }
  return rows;
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out(1);
  for (char c : line)
    if (c == ',')
      out.emplace_back();
    else
      out.back().push_back(c);
  return out;
}

// The frame_width rows: frame - face (true) on x, frame - face (measured) on y, one series per head;
// the diagonal and the band's edges (+-5 mm) as lines.
void chart(const std::string& csv_path, const std::string& png) {
  std::ifstream in(csv_path);
  if (!in) throw std::runtime_error("cannot read " + csv_path);
  std::string line;
  std::getline(in, line);
  std::vector<ChartSeries> series;
  while (std::getline(in, line)) {
    const std::vector<std::string> c = split(line);
    if (c.size() < 16 || c[6] != "frame_width" || c[8] == "0.00") continue;
    const double frame = std::stod(c[7]), measured = std::stod(c[8]), truth = std::stod(c[9]);
    const std::string head = "face " + c[4].substr(0, c[4].find('.')) + " mm, " + c[3];
    if (series.empty() || series.back().name != head) series.push_back({head, {}, {}, true});
    series.back().x.push_back(frame - truth), series.back().y.push_back(frame - measured);
  }
  series.push_back({"measured = true", {-16, 16}, {-16, 16}});
  for (double edge : {-5.0, 5.0})
    series.push_back({fmt::format("band edge {:+.0f}", edge), {-16, 16}, {edge, edge}});
  write_chart(png,
              {"Frame width against the face's width at the temples: fit vs ground truth",
               "frame - face, true (mm)", "frame - face, fit (mm)"},
              series);
}

}  // namespace

int main(int argc, char** argv) {
  spdlog::cfg::load_env_levels();
  if (argc == 4 && std::string(argv[1]) == "--chart") {
    try {
      chart(argv[2], argv[3]);
    } catch (const std::exception& e) {
      std::cerr << "bench_advice: " << e.what() << "\n";
      return 1;
    }
    return 0;
  }
  const std::string scale = argc > 2 ? argv[2] : "", source = argc > 3 ? argv[3] : "";
  if (argc < 7 || (scale != "truth" && scale != "chain" && scale != "mean-face") ||
      (source != "nerf" && source != "mesh")) {
    std::cerr << "usage: bench_advice OUT.csv truth|chain|mean-face nerf|mesh MODEL DATASET FRAME.glb "
                 "[FRAME.glb ...]\n";
    return 2;
  }
  try {
    cl::Runtime rt;
    std::string csv =
        "model,frame,scale,source,face_width_true_mm,scale_error,rule,frame_mm,head_mm,head_true_mm,"
        "difference_error_mm,verdict,true_verdict,true_margin_mm,agree,fit_s\n";
    const std::string model = argv[4], dataset = argv[5];
    nerf::NerfModel m = nerf::NerfModel::load(rt, model);
    const Truth t = read_truth(dataset, m);
    std::unique_ptr<MeshViewSource> mesh =
        subject_source(dataset, m, prior_from_transforms(dataset + "/transforms.json", m), true);
    for (int i = 6; i < argc; ++i)
      for (const std::string& row : rows_for(argv[i], model, dataset, scale, source == "mesh", m, t, *mesh))
        csv += row + "\n";
    write_text_file_atomic(argv[1], csv);
  } catch (const std::exception& e) {
    std::cerr << "bench_advice: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
