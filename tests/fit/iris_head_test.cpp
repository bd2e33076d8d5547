// The iris measure end to end on the procedural head (synth/procedural_head.h), ray cast with
// Embree: its irises are painted with a known radius (FaceLayout::iris_radius, mm) and its eye
// landmarks are exact, so the diameter the views measure, in scene units at a known scale, must give
// back the painted size. This checks the narrow views, the limbus finder on a textured, shaded, curved
// eye and the pixel-to-unit step together, free of the NeRF's blur and the detector's noise.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "eval/mesh_view_source.h"
#include "fit/iris_views.h"
#include "fit/pupil_distance.h"
#include "synth/procedural_head.h"

namespace lorgnette::fit {
namespace {

constexpr double kMmPerUnit = 200.0;  // the demo head's scale

EyeContour contour(const synth::ProceduralHead& h, int first) {
  EyeContour e;
  for (int k = 0; k < 6; ++k) e[k] = h.ibug[first + k].cast<double>() / kMmPerUnit;
  return e;
}

// Two seeds (two head sizes and iris colours), each eye seen from 320 mm in front of it, straight on
// and 6 degrees to either side (measure_irises' default): each measurement within 3 % of the painted
// diameter (the middle of the paint's edge blend; the blend is 0.6 mm wide, 5 % of the iris, and the
// strongest step lies somewhere inside it), and the scale from all six within 2 % of 11.7 / the painted
// diameter times the true scale.
TEST(IrisHead, PaintedIrisesOfTheProceduralHead) {
  for (uint64_t seed : {3u, 11u}) {
    const synth::ProceduralHead head = synth::make_procedural_head(synth::random_head_params(seed));
    Eigen::Matrix4f to_scene = Eigen::Matrix4f::Identity();
    to_scene.topLeftCorner<3, 3>() *= float(1.0 / kMmPerUnit);
    MeshViewSource source(head.mesh, to_scene);
    const auto ms = measure_irises(source, contour(head, 42), contour(head, 36), {0, 1, 0}, {0, 0, 1},
                                   320.0 / kMmPerUnit);
    // The paint's limbal ring fades into the sclera between R - 0.4 and R + 0.2 mm (synth/head_paint.cpp):
    // the edge's middle is 0.1 mm inside the iris radius R.
    const double painted_mm = 2.0 * (head.layout.iris_radius - 0.1);
    for (const IrisMeasurement& m : ms) {
      ASSERT_TRUE(m.edges.found) << "seed " << seed << ": " << m.edges.why;
      EXPECT_NEAR(m.diameter_units * kMmPerUnit, painted_mm, 0.03 * painted_mm)
          << "seed " << seed << " eye " << m.eye << ": " << m.edges.diameter_px << " px over " << m.edges.rows
          << " rows, centre " << m.edges.centre_px.transpose();
    }
    const IrisScale s = iris_scale(ms, kMmPerUnit);
    ASSERT_TRUE(s.ok) << s.why;
    const double expected = kMmPerUnit * kIrisDiameterMm / painted_mm;
    EXPECT_NEAR(s.mm_per_unit, expected, 0.02 * expected) << "seed " << seed;
    // The irises are painted centred in the eyes, eye_distance apart (synth/face_layout.cpp): PD from
    // the limbus centres on the mesh's surface within 0.2 mm (0.06 mm on these two seeds; a fifth of a pixel
    // of the ~50 px iris views).
    const PupilDistance pd = pupil_distance(ms);
    ASSERT_TRUE(pd.ok) << pd.why;
    EXPECT_NEAR(pd.units * kMmPerUnit, head.params.eye_distance, 0.2) << "seed " << seed;
    // The limbus centres are the lens-height rule's pupils (fit_advice.h): their height (the head's up
    // is +y) within the same 0.2 mm of the painted pupils' (the head's landmarks pupil_l/r); the eyes'
    // landmark means, the rule's fallback, are printed beside them.
    for (int side : {+1, -1}) {
      const Eigen::Vector3d limbus = (side > 0 ? pd.left : pd.right) * kMmPerUnit;
      const Eigen::Vector3f pupil = head.landmarks.at(side > 0 ? "pupil_l" : "pupil_r");
      const EyeContour eye = contour(head, side > 0 ? 42 : 36);
      double lids = 0.0;
      for (const Eigen::Vector3d& p : eye) lids += p.y() * kMmPerUnit / 6.0;
      EXPECT_NEAR(limbus.y(), pupil.y(), 0.2) << "seed " << seed << " eye " << side << ": landmark mean "
                                              << lids - pupil.y() << " mm off the pupil's height";
    }
  }
}

}  // namespace
}  // namespace lorgnette::fit
