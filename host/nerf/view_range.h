// The directions a capture looked at its subject from ("view range"): the yaw and pitch of the
// cameras' positions about the subject's centre, in an orbit frame whose up is the cameras' mean up
// and whose front is their mean backward axis made horizontal. A NeRF shows guesses where no camera
// looked, so `train` stores the range in the .lnerf snapshot and every view the product plans
// (render --orbit, the demo, bench, the viewer) stays inside it plus kViewMarginDeg
// (host/render/view_plan.h); `capture` and `train` report it and warn when the arc is too narrow to
// see the temples and ears. Plain math, no OpenCL: the snapshot parser (and its fuzzer) use it.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "kernels/common/camera_types.h"

namespace lorgnette::nerf {

// Views may go this far beyond the outermost cameras (degrees): a NeRF still renders well a little
// outside its training directions, and the orbit then reaches the capture's last view.
constexpr double kViewMarginDeg = 10.0;
// Each side of the face must have been filmed from at least this far round (degrees of yaw from the
// capture's mean direction) for the temples and ears, where the glasses rest, to be reconstructed.
constexpr double kEarToEarYawDeg = 35.0;

struct ViewRange {
  std::array<float, 3> center{0, 0, 0};  // the subject's centre (model frame)
  std::array<float, 3> front{0, 0, 1};   // yaw 0, pitch 0: unit, orthogonal to up
  std::array<float, 3> up{0, 1, 0};      // unit; yaw turns about it, pitch rises towards it
  // Camera positions' extremes, degrees, without margin. Yaw grows towards right = up x front.
  double yaw_min = 0, yaw_max = 0, pitch_min = 0, pitch_max = 0;
  uint32_t cameras = 0;  // how many cameras it was measured from

  bool valid() const;  // finite, unit orthogonal axes, -180 <= min <= max <= 180 (pitch within +-90)
  // The extremes widened by `margin` degrees on each side (yaw clipped to +-180, pitch to +-89).
  ViewRange widened(double margin = kViewMarginDeg) const;
  // "yaw -42..+38 deg, pitch -12..+20 deg (24 cameras)" for logs and reports.
  std::string summary() const;
};

// The range of `cameras` about `center` (cameras in the same frame as center). Throws
// std::invalid_argument when there are no cameras.
ViewRange view_range_from_cameras(const std::vector<Camera>& cameras, const std::array<float, 3>& center);

// Yaw and pitch (degrees) of the direction from the range's centre to `position`.
std::array<double, 2> yaw_pitch_of(const ViewRange& range, const std::array<float, 3>& position);

// The direction (unit) at yaw/pitch degrees in the range's frame.
std::array<float, 3> direction_at(const ViewRange& range, double yaw_deg, double pitch_deg);

// What to film differently when the capture did not go round far enough on both sides to see the
// temples and ears (kEarToEarYawDeg); "" when it did.
std::string coverage_advice(const ViewRange& range);

}  // namespace lorgnette::nerf
