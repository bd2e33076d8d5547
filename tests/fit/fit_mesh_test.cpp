// The dlib adapter and the whole fit on a mesh ViewSource of the Lee Perry-Smith head scan (textured,
// Embree ray cast). Ground truth: the same detector on mesh renders, each landmark ray cast onto the
// mesh (fit/mesh_ground_truth.h). Skips with a message when the scan or the dlib model is missing.
#include <gtest/gtest.h>

#include <filesystem>

#include "eval/mesh_ground_truth.h"
#include "fit/camera_math.h"
#include "fit/fit.h"
#include "fit/fit_placement.h"
#include "fit/glasses_input.h"
#include "fit/landmark_ids.h"
#include "fit/placement_json.h"
#include "host/util/image_io.h"
#include "mesh/placed_glasses.h"

namespace lorgnette::fit {
namespace {

const std::string kHead = std::string(LORGNETTE_DATA_DIR) + "/heads/lee-perry-smith/LeePerrySmith.glb";
const std::string kGlasses = std::string(LORGNETTE_DATA_DIR) + "/glasses/glasses-06/scene.gltf";

class LeePerrySmith : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!std::filesystem::exists(kHead) || !std::filesystem::exists(DetectorOptions{}.model_path)) return;
    source_ = MeshViewSource::load(kHead).release();  // no prior: find the front
  }
  static void TearDownTestSuite() {
    delete source_;
    source_ = nullptr;
  }
  void SetUp() override {
    if (!source_) GTEST_SKIP() << "needs " << kHead << " and the dlib model (Debian package libdlib-data)";
  }
  static MeshViewSource* source_;
};
MeshViewSource* LeePerrySmith::source_ = nullptr;

TEST_F(LeePerrySmith, DlibFindsTheFaceFromTheFrontNotFromBehind) {
  LandmarkDetector det;
  Orbit o;
  o.target =
      source_->bounds().center().cast<double>() + Eigen::Vector3d(0, 2.0, 0);  // the face, not the bust
  o.distance = 14.0;
  o.fov_y_deg = 25.0;
  FaceDetection front = det.detect(source_->render(orbit_camera(o, 0, 0)));  // the scan faces +z
  ASSERT_TRUE(front.found);
  ASSERT_EQ(front.points.size(), 68u);
  // Frontal: the nose tip in the middle between the temples, eyes above the nose.
  EXPECT_LT(std::abs(front.points[lm::kNoseTip].x() - 0.5 * (front.points[0].x() + front.points[16].x())),
            8.0);
  EXPECT_LT(front.points[lm::kEyeOuterL].y(), front.points[lm::kNoseTip].y());
  EXPECT_FALSE(det.detect(source_->render(orbit_camera(o, 180, 0))).found);
}

// The head render with the glasses composited by depth (S_c + (1 - S_a) head where the frame is
// nearer), for the pictures in docs/bench/fit-temples.md.
Image with_glasses(MeshViewSource& head, const mesh::PlacedGlasses& g, const Camera& cam) {
  Image img = head.render(cam);
  mesh::SurfaceParams sp;
  lorgnette::SurfaceBuffers s = g.pass->render(cam, sp);
  LgnVec3 o = camera_origin(&cam);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      size_t i = size_t(y) * img.width + x;
      LgnVec3 d = camera_ray_dir(&cam, x + 0.5f, y + 0.5f);
      mesh::Hit h = head.cast({o.x, o.y, o.z}, Eigen::Vector3f(d.x, d.y, d.z).normalized());
      if (!(s.depth[i] < (h.hit ? h.t : 1e30f))) continue;
      for (int c = 0; c < 3; ++c)
        img.at(x, y, c) = s.color_alpha[4 * i + c] + (1.0f - s.color_alpha[4 * i + 3]) * img.at(x, y, c);
    }
  return img;
}

// Rigid (top row) and spread (bottom row) temples from above and from the side.
void write_temple_pictures(MeshViewSource& head, const FitResult& r, const std::string& glasses,
                           const std::string& path) {
  mesh::GlassesOptions go;
  const Eigen::Matrix4d& t = r.placement.transform;
  mesh::PlacedGlasses rigid = mesh::load_placed_glasses(glasses, t, {}, go);
  mesh::PlacedGlasses spread = mesh::place_glasses_mesh(mesh::load_glasses(glasses, go), t, r.temples.bend);
  Orbit o = r.orbit;
  o.width = o.height = 240;
  const std::vector<std::pair<double, double>> views = {{0, 80}, {75, 5}, {-40, 30}};
  Image out(240 * int(views.size()), 480, 3);
  for (size_t v = 0; v < views.size(); ++v) {
    Camera cam = orbit_camera(o, views[v].first, views[v].second);
    for (int row = 0; row < 2; ++row) {
      Image img = with_glasses(head, row ? spread : rigid, cam);
      for (int y = 0; y < 240; ++y)
        for (int x = 0; x < 240; ++x)
          for (int c = 0; c < 3; ++c) out.at(int(v) * 240 + x, row * 240 + y, c) = img.at(x, y, c);
    }
  }
  write_image(path, out);
}

TEST_F(LeePerrySmith, FitMatchesGroundTruth) {
  FitOptions opt;
  GlassesInput g = load_glasses_input(kGlasses, 2000);
  opt.debug_dir = std::string(LORGNETTE_TEST_TMP) + "/fit-debug";
  std::vector<std::string> started;  // the progress hook: each stage announced as it starts
  opt.on_stage = [&](const std::string& stage) { started.push_back(stage); };
  FitResult r = fit_glasses(*source_, g, opt);
  ASSERT_EQ(started.size(), r.seconds.size());
  for (size_t i = 0; i < started.size(); ++i) EXPECT_EQ(started[i], r.seconds[i].first);
  GroundTruth gt = mesh_ground_truth(*source_, r.orbit, {-20, -10, 0, 10, 20}, g.ref, opt);
  FitErrors e = compare_fit(r, gt);
  // A mesh's surface is exact: the temples keep the depths their casts found (temple_depth.h
  // corrects only a volume's soft sides).
  EXPECT_TRUE(source_->hard_surface());
  EXPECT_EQ(r.temple_depth.moved, 0);
  // The scan shows both ears' roots: the ears come from the density (fit/ear_root.h), in the fit and
  // in the ground truth alike, and sit behind the temples (the rests lie 8-16 mm behind them).
  EXPECT_TRUE(r.ear_roots.left.found && r.ear_roots.right.found) << r.ear_roots.summary();
  EXPECT_TRUE(gt.ear_roots.left.found && gt.ear_roots.right.found) << gt.ear_roots.summary();
  for (const auto& [ear, temple] : {std::pair{r.ears.f_l, r.points[lm::kTempleL].position},
                                    std::pair{r.ears.f_r, r.points[lm::kTempleR].position}}) {
    const double behind_mm = (temple - ear).dot(r.head.d_fwd) * r.head.mm_per_unit;
    EXPECT_GT(behind_mm, 2.0);
    EXPECT_LT(behind_mm, 35.0);
  }
  // The targets: nose <= 2 mm, ears <= 4 mm, rotation <= 2 deg, penetration <= 0.5 mm.
  EXPECT_LT(e.nose_mm, 2.0);
  EXPECT_LT(e.ear_l_mm, 4.0);
  EXPECT_LT(e.ear_r_mm, 4.0);
  EXPECT_LT(e.rotation_deg, 2.0);
  // The refinement seats the front (rims, bridge, pads) on the skin without clipping. The rigid
  // temples pass into the head behind the ears (the head is wider there than the frame); the temple
  // fit spreads each at its hinge until it clears (fit/temple_fit.h; numbers in docs/bench/fit-temples.md).
  EXPECT_LE(r.contact.front_penetration_mm, 0.5);
  ASSERT_TRUE(r.temples.fitted);
  for (const TempleSideFit* t : {&r.temples.left, &r.temples.right}) {
    EXPECT_GT(t->penetration_before_mm, 0.5);  // the rigid frame clips: the spread is needed
    EXPECT_GT(t->spread_deg, 0.0);
    EXPECT_LT(t->spread_deg, 15.0);  // a flex, not a break
    EXPECT_LE(t->penetration_mm, 0.5);
    EXPECT_TRUE(t->clear);
  }
  EXPECT_LE(r.contact.penetration_mm, 0.5);  // re-measured with the spread temples
  EXPECT_LE(r.contact.tip_penetration_mm, 0.5);
  EXPECT_TRUE(r.ok);
  for (const auto& w : r.warnings) EXPECT_EQ(w.find("temple"), std::string::npos) << w;
  // The scan is "roughly 5.5-6 cm per unit" (data README); the mean face gives the estimate.
  EXPECT_GT(r.head.mm_per_unit, 45.0);
  EXPECT_LT(r.head.mm_per_unit, 70.0);
  EXPECT_GT(r.head.pd_mm, 50.0);
  EXPECT_LT(r.head.pd_mm, 75.0);
  // The face looks along +z in the scan.
  EXPECT_GT(r.head.d_fwd.z(), 0.97);
  EXPECT_GE(r.views_used, opt.detection.min_views);
  EXPECT_TRUE(std::filesystem::exists(opt.debug_dir + "/view_00.png"));
  PlacementFile pf = make_placement_file(r, kGlasses, "stretch");
  EXPECT_EQ(pf.landmarks.size(), 7u);
  EXPECT_FALSE(pf.glasses_hash.empty());
  EXPECT_TRUE(pf.has_temples);
  write_temple_pictures(*source_, r, kGlasses, opt.debug_dir + "/temples_rigid_vs_spread.png");
  EXPECT_EQ(pf.temples.bend.left.spread_deg, r.temples.left.spread_deg);
  std::cerr << "fit errors: nose " << e.nose_mm << " mm, ears " << e.ear_l_mm << " / " << e.ear_r_mm
            << " mm, rotation " << e.rotation_deg << " deg, mm/unit " << r.head.mm_per_unit << " (gt "
            << gt.head.mm_per_unit << "), pd " << r.head.pd_mm << " mm, penetration "
            << r.contact.penetration_mm << " mm (shift " << r.contact.shift_mm << "), temples spread "
            << r.temples.left.spread_deg << " / " << r.temples.right.spread_deg << " deg (penetration "
            << r.temples.left.penetration_before_mm << " -> " << r.temples.left.penetration_mm << " / "
            << r.temples.right.penetration_before_mm << " -> " << r.temples.right.penetration_mm << " mm), "
            << r.total_seconds() << " s\n";
  std::cerr << "  hinge_l " << r.temples.bend.left.hinge.transpose() << " mm, tip penetration "
            << r.contact.tip_penetration_mm << " mm\n";
  for (const auto& [stage, sec] : r.seconds) std::cerr << "  " << stage << " " << sec << " s\n";
}

TEST_F(LeePerrySmith, TooFewViewsIsAClearError) {
  FitOptions opt;
  opt.cap.views = 2;
  opt.detection.min_views = 3;
  try {
    fit_glasses(*source_, GlassesInput{}, opt);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("views"), std::string::npos) << e.what();
  }
}

TEST(FitErrors, NoFaceAnywhereSaysWhatWasTried) {
  // An empty scene (a small sphere): the front sweep sees no face and must say which yaws it tried.
  class Ball : public ViewSource {
   public:
    Image render(const Camera& c) override { return Image(int(c.width), int(c.height), 3, 0.5f); }
    std::vector<float> density(const std::vector<Eigen::Vector3f>& p) override {
      return std::vector<float>(p.size(), 0.0f);
    }
    Bounds bounds() const override { return {}; }
  } ball;
  if (!std::filesystem::exists(DetectorOptions{}.model_path))
    GTEST_SKIP() << "dlib model missing (libdlib-data)";
  FitOptions opt;
  opt.front.width = opt.front.height = 128;
  try {
    fit_glasses(ball, GlassesInput{}, opt);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no face found in any of the 8"), std::string::npos) << e.what();
  }
  DetectorOptions missing;
  missing.model_path = "/nonexistent/shape_predictor.dat";
  try {
    LandmarkDetector d(missing);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("libdlib-data"), std::string::npos);
  }
}

}  // namespace
}  // namespace lorgnette::fit
