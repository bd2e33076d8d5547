// Tests of the procedural head: seeded determinism, parameter validation, landmark geometry, and
// the property the demo relies on: dlib's HOG detector + 68-point predictor find the face from yaw
// -30 to +30 degrees and put its landmarks where the head's ground truth says they are.
#include <gtest/gtest.h>

#include <cmath>

#include "fit/landmarks_dlib.h"
#include "mesh/embree_scene.h"
#include "synth/camera_rig.h"
#include "synth/studio_render.h"
#include "synth/synthesize.h"
#include "test_head.h"

namespace lorgnette::synth {
namespace {

TEST(ProceduralHead, SameSeedSameMeshDifferentSeedDifferentHead) {
  HeadMeshOptions small{128, 64, 256};
  ProceduralHead a = make_procedural_head(random_head_params(7), small);
  ProceduralHead b = make_procedural_head(random_head_params(7), small);
  ProceduralHead c = make_procedural_head(random_head_params(8), small);
  ASSERT_EQ(a.mesh.positions.size(), b.mesh.positions.size());
  for (size_t i = 0; i < a.mesh.positions.size(); ++i) ASSERT_EQ(a.mesh.positions[i], b.mesh.positions[i]);
  EXPECT_EQ(a.mesh.textures[0].pixels, b.mesh.textures[0].pixels);
  EXPECT_NE(a.params.eye_distance, c.params.eye_distance);
}

TEST(ProceduralHead, RefusesImplausibleParameters) {
  HeadParams p;
  p.eye_distance = 20.0f;
  try {
    make_procedural_head(p);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("eye_distance"), std::string::npos) << e.what();
  }
}

TEST(ProceduralHead, LandmarksMatchTheParameters) {
  const Subject& s = test::default_head();
  const HeadParams p = random_head_params(0);
  const float mm = float(*s.mm_per_unit);
  auto L = [&](const char* n) { return Eigen::Vector3f(s.landmarks.at(n) * mm); };
  // Pupils are cast along -z at x = +-eye_distance/2: their separation is exact up to float rounding.
  EXPECT_NEAR((L("pupil_l") - L("pupil_r")).x(), p.eye_distance, 1e-3);
  EXPECT_NEAR(L("pupil_l").y(), L("pupil_r").y(), 1e-3);  // the head is symmetric
  // Nose tip protrudes beyond the inner eye corners; the bridge lies between the eyes.
  EXPECT_GT(L("nose_tip").z(), L("eye_r_inner").z() + 15.0f);
  EXPECT_NEAR(L("nose_bridge").x(), 0.0f, 1e-3);
  // Ears: tops above the rest points, both outside the skull's half breadth, mirror images.
  for (const char* side : {"l", "r"}) {
    Eigen::Vector3f top = L((std::string("ear_top_") + side).c_str());
    Eigen::Vector3f rest = L((std::string("ear_rest_") + side).c_str());
    EXPECT_GT(std::abs(top.x()), 0.5f * p.head_width) << side;
    EXPECT_GE(top.y(), rest.y()) << side;
    EXPECT_GT(rest.y(), top.y() - 15.0f) << side;
    EXPECT_LT(rest.z(), L("eye_r_outer").z()) << side;
  }
  EXPECT_NEAR(L("ear_top_l").x(), -L("ear_top_r").x(), 0.5f);
  // The rests are mirror images too, each a crease point of its own profile, not its ear's top (the
  // right rest once stayed at the top: its search ran no ray).
  EXPECT_NEAR(L("ear_rest_l").x(), -L("ear_rest_r").x(), 0.5f);
  EXPECT_NEAR(L("ear_rest_l").y(), L("ear_rest_r").y(), 0.5f);
  EXPECT_NEAR(L("ear_rest_l").z(), L("ear_rest_r").z(), 0.5f);
  for (const char* side : {"l", "r"})
    EXPECT_GT(
        (L((std::string("ear_rest_") + side).c_str()) - L((std::string("ear_top_") + side).c_str())).z(),
        1.0f)
        << side << ": the rest lies in front of the ear top";
  ASSERT_EQ(s.ibug68.size(), 68u);
}

// Renders the head at (yaw, 5 deg pitch) on grey, as the rig of a synthesised dataset would.
Image render_at(const Subject& s, const mesh::EmbreeScene& scene, float yaw, Camera* cam_out) {
  SynthOptions o;
  o.width = o.height = 256;
  Camera cam = rig_camera(rig_for(s, o), yaw, 5.0f);
  if (cam_out) *cam_out = cam;
  RenderSettings rs{2, Eigen::Vector3f(0.45f, 0.45f, 0.45f), 0};
  return render_view(scene, cam, StudioLighting{}, rs).rgba;
}

TEST(ProceduralHead, DlibFindsTheFaceFromYawMinus30To30AndItsLandmarksAgree) {
  const Subject& s = test::default_head();
  mesh::EmbreeScene scene(s.mesh, s.mesh_to_dataset);
  fit::LandmarkDetector detector;
  for (float yaw : {-30.0f, 0.0f, 30.0f}) {
    Camera cam{};
    fit::FaceDetection d = detector.detect(render_at(s, scene, yaw, &cam));
    ASSERT_TRUE(d.found) << "no face at yaw " << yaw;
    ASSERT_EQ(d.points.size(), 68u);
    if (yaw != 0.0f) continue;
    // Frontal view: ground truth vs dlib. The face is ~110 px wide here; dlib's predictor itself is
    // accurate to a few per cent of the inter-ocular distance (~65 px), i.e. ~2-3 px. Tolerances:
    // mean over the 51 feature points (17-67) 3.5 px, each of eyes/nose/mouth (27-67) 6 px, brows
    // (17-26, whose iBUG definition is the fuzzy upper edge) 9 px; contour (0-16, view dependent) mean 6 px.
    double inner = 0, contour = 0;
    for (int i = 0; i < 68; ++i) {
      const Eigen::Vector3f& p = s.ibug68[i];
      float u, v;
      ASSERT_GT(camera_project(&cam, lgn_vec3(p.x(), p.y(), p.z()), &u, &v), 0.0f);
      double e = (d.points[i] - Eigen::Vector2d(u, v)).norm();
      if (i < 17) {
        contour += e;
      } else {
        inner += e;
        EXPECT_LT(e, i < 27 ? 9.0 : 6.0) << "landmark " << i;
      }
    }
    EXPECT_LT(inner / 51, 3.5);
    EXPECT_LT(contour / 17, 6.0);
  }
}

}  // namespace
}  // namespace lorgnette::synth
