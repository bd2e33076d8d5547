// Training on a mask-less synthetic room capture (synth --room) separates the subject from the
// room: after a short training with the room model (host/nerf/background_field.h) and the subject
// region (subject_region.h), the held-out opacity matches the true mattes (host/render/matte_eval.h)
// above a stated IoU floor, with little opacity outside them. The subject box is the head box the
// landmark triangulation gives on real captures, taken here from the procedural head's own mesh
// (crown to 50 mm under the chin, +-10 %): dlib finds no faces on images this small.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "capture/face_hull.h"
#include "fit/landmark_ids.h"
#include "host/dataset/dataset.h"
#include "host/nerf/subject_holes.h"
#include "host/nerf/train_job.h"
#include "host/render/matte_eval.h"
#include "host/render/renderer.h"
#include "synth/matte.h"
#include "synth/synthesize.h"

namespace lorgnette {
namespace {

namespace fs = std::filesystem;

nerf::Aabb head_box(const synth::Subject& s, const synth::HeadParams& p) {
  Eigen::AlignedBox3f box;
  const float cut = -p.face_length - 50.0f;  // mm, head frame
  for (const auto& v : s.mesh.positions)
    if (v.y() > cut) box.extend(synth::transform_point(s.mesh_to_dataset, v));
  nerf::Aabb out;
  Eigen::Vector3f grow = 0.1f * box.sizes();
  for (int a = 0; a < 3; ++a) out.min[a] = box.min()[a] - grow[a], out.max[a] = box.max()[a] + grow[a];
  return out;
}

// The face and neck regions of the subject's true head box (capture/face_hull.h), as the landmark
// head box gives them on a real capture: the true frame, scale and landmarks (head_volume_test's
// anchor: the eye corners' centroid at the inner corners' depth).
std::vector<nerf::SolidHull> true_solid_hulls(const synth::Subject& s) {
  std::vector<Eigen::Vector3d> lm;
  for (const auto& p : s.ibug68) lm.push_back(p.cast<double>());
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int k : {fit::lm::kEyeOuterR, fit::lm::kEyeInnerR, fit::lm::kEyeInnerL, fit::lm::kEyeOuterL})
    centroid += 0.25 * lm[size_t(k)];
  const Eigen::Vector3d inner = 0.5 * (lm[fit::lm::kEyeInnerR] + lm[fit::lm::kEyeInnerL]);
  fit::HeadFrame head;
  head.d_eye = Eigen::Vector3d::UnitX(), head.d_up = Eigen::Vector3d::UnitY(),
  head.d_fwd = Eigen::Vector3d::UnitZ();
  head.mm_per_unit = *s.mm_per_unit;
  fit::HeadBox box = fit::head_box_from_frame(head, centroid + head.d_fwd * head.d_fwd.dot(inner - centroid),
                                              fit::HeadExtents{});
  box.landmarks = lm;
  box.landmark_ok.assign(lm.size(), true);
  return capture::head_solid_hulls(box);
}

// IoU floor 0.88 and leak ceiling 10 % after 500 steps of 2^15 samples on 24 views of 120x160
// (50-85 s on 2 shared CPU cores). Measured: IoU 0.846, leak 8.7 %; with the binary-opacity prior
// (background_field.h) IoU 0.870 and 0.870, leak 7.8 and 8.5 % in two runs (training is not bitwise
// deterministic here, hence the margins); with the room's samples spread over the rays (25 Nov)
// IoU 0.916-0.918, leak 10.5-10.8 %, the subject's batch 97 % full; with the room-explained
// clearing (26 Nov, BackgroundOptions::room_clear 1) IoU 0.941, leak 6.5 % (one run), so the
// ceiling fails the code before it; with the zones and the prior at 0.03 (27 Nov) IoU 0.938, leak
// 5.1 % (one run); without the room model the same capture's box fills with the
// room (IoU 0.30 at full size). The full-size figures are in docs/room-training.md.
TEST(RoomTraining, SubjectSeparatesFromTheRoom) {
  synth::HeadParams params = synth::random_head_params(0);
  synth::Subject subject = synth::procedural_subject(params, synth::HeadMeshOptions{256, 128, 512}, true);
  fs::path dir = fs::path(LORGNETTE_TEST_TMP) / "synth" / "room_training";
  fs::remove_all(dir);
  fs::create_directories(dir.parent_path());
  synth::SynthOptions o;
  o.room = 1;
  o.views = 24;
  o.width = 120, o.height = 160;
  o.samples_per_axis = 2;
  o.seed = 1;
  o.yaw_min_deg = -40.0f, o.yaw_max_deg = 40.0f;
  o.pitch_min_deg = -10.0f, o.pitch_max_deg = 10.0f;
  synth::synthesize_dataset(subject, dir.string(), o);

  dataset::Dataset ds = dataset::load_dataset(dir.string(), {});
  ASSERT_FALSE(ds.has_alpha);
  cl::Runtime rt{cl::RuntimeOptions{"", "", false}};
  nerf::TrainJob job;
  job.sizing.aabb = head_box(subject, params);
  job.batch_log2 = 15;
  job.background = "on";
  job.train.steps = 500;
  job.train.progress = false;
  // Only the regions the self-check judges (no volume: training is as before); no second training.
  job.subject = nerf::SubjectZones{};
  job.subject->whole = true_solid_hulls(subject);
  job.retrain_on_holes = false;
  nerf::TrainJobResult tr = nerf::train_on_dataset(rt, ds, job);
  ASSERT_TRUE(tr.background);
  ASSERT_FALSE(tr.region.empty());
  // The room model's samples ride on top of the subject's batch (BackgroundOptions::spread_over_rays):
  // the subject's steps stay nearly full. Before, the room's batch cut the step's rays where the rays
  // held more room than subject samples (in2n-face: 41 % of the subject's batch).
  const double fill = double(tr.result.samples) / (double(job.train.steps) * double(1u << job.batch_log2));
  EXPECT_GE(fill, 0.85) << "the subject got " << 100.0 * fill << " % of its samples";

  nlohmann::json tj = nlohmann::json::parse(std::ifstream(dir / "transforms.json"));
  std::vector<Eigen::Vector3f> face;
  nlohmann::json gt = nlohmann::json::parse(std::ifstream(dir / "ground_truth.json"));
  for (const auto& p : gt["ibug68"])
    face.emplace_back(p[0].get<float>(), p[1].get<float>(), p[2].get<float>());
  render::Renderer renderer(rt);
  std::vector<render::MatteScore> scores;
  for (const dataset::Frame* f : ds.split(dataset::Split::Holdout)) {
    std::string stem = fs::path(f->image_path).stem().string();
    Image matte = synth::read_matte((dir / "mattes" / (stem + ".png")).string());
    Image depth = read_image((dir / "depth" / (stem + ".exr")).string());
    Image pred = renderer.render(tr.model, f->camera, nullptr, render::RenderOptions{}).rgba;
    scores.push_back(
        render::score_matte({f->camera, &pred, &f->image, &matte, &depth, face}, tr.model.aabb()));
  }
  ASSERT_GE(scores.size(), 3u);
  render::MatteScore m = render::mean_score(scores);
  // The self-check passes a whole head (subject_holes.h): the training views see its face and neck.
  EXPECT_GE(tr.model.metadata.holes, 0.0);
  EXPECT_LT(tr.model.metadata.holes, nerf::kSubjectHoleShare);
  EXPECT_TRUE(tr.model.metadata.subject_problem.empty()) << tr.model.metadata.subject_problem;
  EXPECT_GE(m.iou, 0.88);
  EXPECT_LE(m.leak, 0.10);
  std::cout << "room capture, 500 steps: IoU " << m.iou << ", leak " << 100.0 * m.leak << " %, face PSNR "
            << m.face_psnr << " dB, head interior holes " << 100.0 * m.holes << " %, self-check holes "
            << 100.0 * tr.model.metadata.holes << " %, subject batch filled " << 100.0 * fill << " %\n";
}

}  // namespace
}  // namespace lorgnette
