// Where to look from: K cameras on a yaw/pitch cap around the face (dlib finds faces within about
// +-45 deg of frontal, so the default cap stays inside that), and a coarse yaw sweep that finds the
// front of an unknown head.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "common/camera_types.h"

namespace lorgnette::fit {

// A view frame around the head: cameras orbit `target` at `distance`, yaw about `up`, 0 = `front`.
struct Orbit {
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  Eigen::Vector3d up{0, 1, 0};
  Eigen::Vector3d front{0, 0, 1};  // unit, orthogonal to up: from the head towards the yaw-0 camera
  double distance = 3.0;           // scene units
  double fov_y_deg = 30.0;
  int width = 512, height = 512;
};

struct CapOptions {
  int views = 12;  // K
  double yaw_range_deg =
      20.0;  // cameras span [-range, +range] in yaw (stability study: 20 best, fails from 45)
  double pitch_range_deg = 15.0;  // ... and [-range, +range] in pitch
  // Pixels (square) of the cap's views; 0: the front search's size. The cap is framed on the face
  // (FrontSearchOptions::face_fraction), the front search on the whole head, so the cap needs fewer:
  // at 256 the face is 128 px wide, well above dlib's 80 px window, and the scan's fit errors stay
  // within their targets (docs/bench/fit.md, resolution sweep). Rendering the views is most of a
  // fit on a NeRF: 256 renders 2.25x fewer rays than 384 (docs/fit.md, "The cap of views").
  int size = 256;
};

// The camera at (yaw, pitch) degrees on the orbit, looking at its target.
Camera orbit_camera(const Orbit& orbit, double yaw_deg, double pitch_deg);

// K views spread over the cap: a golden-angle (Fibonacci) spiral on the yaw/pitch rectangle, so
// every K covers the range evenly and the centre view (yaw 0, pitch 0) is always included.
std::vector<Eigen::Vector2d> cap_angles(const CapOptions& opt);
std::vector<Camera> cap_cameras(const Orbit& orbit, const CapOptions& opt);

// Yaw angles of the coarse front search: `count` steps over 360 deg, starting at 0.
std::vector<double> sweep_yaws(int count);

}  // namespace lorgnette::fit
