// The iris measure against analytic pictures: a dark disc of known diameter on a white sclera inside
// skin (anti-aliased by 8x8 supersampling, with fixed-seed noise), the px -> scene units step of a
// pinhole camera, the scale and its refusals on synthetic measurements, and the whole chain on a
// ViewSource that paints irises of known size on a plane (views straight on and from the side), with
// PD from their centres.
#include "fit/iris.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fit/camera_math.h"
#include "fit/iris_views.h"
#include "fit/pupil_distance.h"

namespace lorgnette::fit {
namespace {

struct EyePicture {
  Eigen::Vector2d iris_centre{100.3, 61.7};
  double iris_radius = 23.7, pupil_radius = 8.0;
  double skin = 0.35, sclera = 0.75, iris = 0.08, pupil = 0.02;
  double lid_y = 40.0;  // skin above this row (the upper lid cutting the iris' top)
  double noise = 0.01;
};

double shade(const EyePicture& e, double x, double y) {
  if (y < e.lid_y) return e.skin;
  const double ex = (x - 100.0) / 75.0, ey = (y - 62.0) / 30.0;
  if (ex * ex + ey * ey > 1.0) return e.skin;
  const double r = (Eigen::Vector2d(x, y) - e.iris_centre).norm();
  return r < e.pupil_radius ? e.pupil : r < e.iris_radius ? e.iris : e.sclera;
}

Image eye_picture(const EyePicture& e, int w = 200, int h = 120, unsigned seed = 3) {
  Image im(w, h, 3);
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, e.noise);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double s = 0;
      for (int k = 0; k < 64; ++k) s += shade(e, x + (k % 8 + 0.5) / 8.0, y + (k / 8 + 0.5) / 8.0);
      const double v = s / 64.0 + n(rng);
      for (int c = 0; c < 3; ++c) im.at(x, y, c) = float(v);
    }
  return im;
}

// Discs of several sizes and sub-pixel centres: the diameter within 0.5 px (the edge is located by a
// parabola through the gradient; 8x8 supersampling leaves < 0.1 px of area error), the centre within
// 0.5 px, from guesses 30 % off in size and a third of a radius off in place.
TEST(IrisEdges, DiscOfKnownDiameter) {
  for (double radius : {12.0, 23.7, 31.4}) {
    EyePicture e;
    e.iris_radius = radius;
    e.pupil_radius = 0.35 * radius;
    e.iris_centre = {97.6 + 0.1 * radius, 63.2};
    const Image im = eye_picture(e);
    for (double guess : {0.7, 1.0, 1.3}) {
      IrisEdges r = find_iris_edges(im, e.iris_centre + Eigen::Vector2d(0.33 * radius, -2.0), guess * radius);
      ASSERT_TRUE(r.found) << "radius " << radius << " guess " << guess << ": " << r.why;
      EXPECT_NEAR(r.diameter_px, 2 * radius, 0.5) << "radius " << radius << " guess " << guess;
      EXPECT_NEAR(r.centre_px.x(), e.iris_centre.x(), 0.5);
      EXPECT_GT(r.relative_step, 0.8);  // (0.75 - 0.08) / 0.75 = 0.89 less the pupil's share
    }
  }
}

TEST(IrisEdges, BlueIrisWithDarkPupil) {
  EyePicture e;
  e.iris = 0.3;  // a light iris: the pupil's edge is a step too, the limbus the stronger one
  const IrisEdges r = find_iris_edges(eye_picture(e), e.iris_centre, e.iris_radius);
  ASSERT_TRUE(r.found) << r.why;
  EXPECT_NEAR(r.diameter_px, 2 * e.iris_radius, 0.5);
}

TEST(IrisEdges, RefusesClosedEyeAndWeakEdges) {
  EyePicture closed;
  closed.lid_y = 1000;  // skin everywhere
  IrisEdges r = find_iris_edges(eye_picture(closed), closed.iris_centre, closed.iris_radius);
  EXPECT_FALSE(r.found);
  EXPECT_NE(r.why.find("weak edges"), std::string::npos) << r.why;
  EyePicture faint;
  faint.iris = 0.65;  // 13 % darker than the sclera: not a limbus one can trust
  faint.pupil = 0.6;
  r = find_iris_edges(eye_picture(faint), faint.iris_centre, faint.iris_radius);
  EXPECT_FALSE(r.found);
  EXPECT_FALSE(r.why.empty());
  r = find_iris_edges(Image(), {0, 0}, 10);
  EXPECT_FALSE(r.found);
  r = find_iris_edges(eye_picture(EyePicture{}), {100, 60}, 1.0);
  EXPECT_FALSE(r.found);
  EXPECT_NE(r.why.find("too small"), std::string::npos) << r.why;
}

TEST(IrisScale, PixelsToUnitsIsThePinholeRule) {
  const Camera cam = look_at_camera({0, 0, 3}, {0, 0, 0}, {0, 1, 0}, 20.0, 256, 128);
  // A point 2.5 units deep (off the axis: the depth is along the viewing axis, not the distance).
  EXPECT_NEAR(pixels_to_units(cam, {0.2, 0.1, 0.5}, 40.0), 40.0 * 2.5 / cam.fx, 1e-9);
  EXPECT_THROW(pixels_to_units(cam, {0, 0, 4}, 40.0), std::runtime_error);
}

std::vector<IrisMeasurement> measurements(double units_left, double units_right, int views, double spread) {
  std::vector<IrisMeasurement> ms;
  for (int v = 0; v < views; ++v)
    for (int eye : {+1, -1}) {
      IrisMeasurement m;
      m.eye = eye;
      m.edges.found = true;
      m.diameter_units = (eye > 0 ? units_left : units_right) * (1.0 + spread * (v - 0.5 * (views - 1)));
      ms.push_back(m);
    }
  return ms;
}

// 200 mm per unit: the irises are 11.7 / 200 units across; the uncertainty is at least the population's
// 0.5 / 11.7 = 4.3 % and grows with the measurements' spread.
TEST(IrisScale, ScaleAndUncertainty) {
  const double d = kIrisDiameterMm / 200.0;
  IrisScale s = iris_scale(measurements(d, d, 3, 0.0), 214.0);
  ASSERT_TRUE(s.ok) << s.why;
  EXPECT_NEAR(s.mm_per_unit, 200.0, 1e-9);
  EXPECT_NEAR(s.mm_per_unit_uncertainty, 200.0 * 0.5 / 11.7, 1e-6);
  EXPECT_EQ(s.measurements, 6);
  IrisScale wide = iris_scale(measurements(d, d, 3, 0.05), 214.0);
  ASSERT_TRUE(wide.ok) << wide.why;
  EXPECT_GT(wide.mm_per_unit_uncertainty, s.mm_per_unit_uncertainty);
}

TEST(IrisScale, Refusals) {
  const double d = kIrisDiameterMm / 200.0;
  IrisScale s = iris_scale(measurements(d, 1.2 * d, 2, 0.0), 200.0);
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.why.find("disagree"), std::string::npos) << s.why;
  std::vector<IrisMeasurement> closed = measurements(d, d, 2, 0.0);
  for (auto& m : closed) m.closed = m.eye < 0;
  s = iris_scale(closed, 200.0);
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.why.find("2 closed"), std::string::npos) << s.why;
  std::vector<IrisMeasurement> weak = measurements(d, d, 2, 0.0);
  for (auto& m : weak) m.edges.found = false, m.edges.why = "weak edges: a clear limbus in 1 rows (need 4)";
  s = iris_scale(weak, 200.0);
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.why.find("weak edges"), std::string::npos) << s.why;
  s = iris_scale(measurements(d, d, 2, 0.0), 140.0);  // 43 % from the mean face: not an iris
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.why.find("mean face"), std::string::npos) << s.why;
  EXPECT_FALSE(iris_scale({}, 200.0).ok);
}

// A face-like plane z = 0 (facing +z) with two painted eyes: sclera ellipses 30 mm wide and iris
// discs of 11.7 mm, drawn at 200 mm per unit; rays are intersected with the plane exactly.
class PaintedEyes : public ViewSource {
 public:
  static constexpr double kMmPerUnit = 200.0;
  Eigen::Vector3d eye_centre(int side) const { return {side * 32.0 / kMmPerUnit, 0.0, 0.0}; }
  EyeContour contour(int side) const {
    const Eigen::Vector3d c = eye_centre(side);
    const double w = 15.0 / kMmPerUnit, h = 5.0 / kMmPerUnit;
    return {c + Eigen::Vector3d(w, 0, 0),         c + Eigen::Vector3d(0.4 * w, h, 0),
            c + Eigen::Vector3d(-0.4 * w, h, 0),  c - Eigen::Vector3d(w, 0, 0),
            c + Eigen::Vector3d(-0.4 * w, -h, 0), c + Eigen::Vector3d(0.4 * w, -h, 0)};
  }
  Image render(const Camera& cam) override {
    Image im(int(cam.width), int(cam.height), 3);
    for (int y = 0; y < im.height; ++y)
      for (int x = 0; x < im.width; ++x) {
        double s = 0;
        for (int k = 0; k < 16; ++k)
          s += shade(camera_ray(cam, {x + (k % 4 + 0.5) / 4, y + (k / 4 + 0.5) / 4}));
        for (int c = 0; c < 3; ++c) im.at(x, y, c) = float(s / 16);
      }
    return im;
  }
  std::vector<float> density(const std::vector<Eigen::Vector3f>& p) override {
    return std::vector<float>(p.size());
  }
  Bounds bounds() const override { return {}; }

 private:
  double shade(const Ray& r) const {
    const Eigen::Vector3d p = r.origin - r.dir * (r.origin.z() / r.dir.z());
    for (int side : {+1, -1}) {
      const Eigen::Vector3d mm = (p - eye_centre(side)) * kMmPerUnit;
      if (mm.head<2>().norm() < 0.5 * kIrisDiameterMm) return 0.1;
      if (std::pow(mm.x() / 15.0, 2) + std::pow(mm.y() / 7.0, 2) < 1.0) return 0.8;
    }
    return 0.4;
  }
};

// From 2 units (400 mm, a phone at arm's length) in front of each eye, straight on and 12 degrees to
// either side: each diameter within 1 % (the edge's 0.5 px over ~50 px) and the scale within 1 %.
TEST(IrisViews, PaintedIrisesGiveTheirScale) {
  PaintedEyes src;
  IrisViewOptions o;
  o.yaw_deg = {-12.0, 0.0, 12.0};
  const auto ms = measure_irises(src, src.contour(+1), src.contour(-1), {0, 1, 0}, {0, 0, 1}, 2.0, o);
  ASSERT_EQ(ms.size(), 6u);
  for (const auto& m : ms) {
    ASSERT_TRUE(m.edges.found) << m.edges.why;
    EXPECT_NEAR(m.diameter_units * PaintedEyes::kMmPerUnit, kIrisDiameterMm, 0.12);
  }
  const IrisScale s = iris_scale(ms, 214.0);
  ASSERT_TRUE(s.ok) << s.why;
  EXPECT_NEAR(s.mm_per_unit, PaintedEyes::kMmPerUnit, 0.01 * PaintedEyes::kMmPerUnit);
  // The discs' centres are 64 mm apart: PD from the limbus centres within 0.1 mm.
  const PupilDistance pd = pupil_distance(ms);
  ASSERT_TRUE(pd.ok) << pd.why;
  EXPECT_NEAR(pd.units * PaintedEyes::kMmPerUnit, 64.0, 0.1);
}

TEST(IrisViews, ClosedEyesAreNotMeasured) {
  PaintedEyes src;
  EyeContour shut = src.contour(+1);
  for (int k : {1, 2, 4, 5}) shut[k].y() = 0.1 * shut[k].y();
  EXPECT_LT(eye_opening_ratio(shut), 0.18);
  EXPECT_GT(eye_opening_ratio(src.contour(+1)), 0.3);
  IrisViewOptions o;
  o.yaw_deg = {0.0};
  const auto ms = measure_irises(src, shut, src.contour(-1), {0, 1, 0}, {0, 0, 1}, 2.0, o);
  ASSERT_EQ(ms.size(), 2u);
  EXPECT_TRUE(ms[0].closed);
  EXPECT_FALSE(ms[1].closed);
  EXPECT_FALSE(iris_scale(ms, 200.0).ok);
}

}  // namespace
}  // namespace lorgnette::fit
