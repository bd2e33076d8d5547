// The placement transform (the frame's canonical millimetres -> the scene) as one type,
// Eigen::Matrix4d, for every front end: the check every reader and writer applies, the forms a user
// types (`render --transform`, `--translate/--rotate/--scale`, Python's adjusted()) and the rough
// stand-in shown when there is no fit.
#pragma once
#include <Eigen/Core>
#include <array>
#include <string>

namespace lorgnette::fit {

using Transform = Eigen::Matrix4d;

// Sane scene units per millimetre: a 140 mm frame spans 1.4e-4 to 1.4e6 scene units. Wider than any
// scene a capture gives (about 0.01) so only broken numbers are refused.
constexpr double kMinTransformScale = 1e-6, kMaxTransformScale = 1e4;
constexpr double kMaxTranslation = 1e6;  // scene units

// Throws std::invalid_argument naming `what` unless `m` is affine (last row 0 0 0 1), finite, its
// three axes each scaled within [kMinTransformScale, kMaxTransformScale] (an all-zero matrix is
// refused) and not flat (the axes span a volume: |det| >= 1e-6 of the product of their lengths),
// with a translation within kMaxTranslation.
void check_transform(const Transform& m, const std::string& what);

// p' = translate + R(rotate_deg) * scale * p, with R = Rz * Ry * Rx (degrees about the scene axes).
Transform trs_transform(const std::array<float, 3>& translate, const std::array<float, 3>& rotate_deg,
                        float scale);

// 16 numbers (row-major) from a string (spaces or commas, brackets allowed); checked as above.
Transform parse_transform(const std::string& text, const std::string& what = "--transform");

// The head's axes in the scene for the rough placement: the frame's canonical x, y and z (unit,
// orthogonal) and a point on the head's centre line.
struct HeadAxes {
  Eigen::Vector3d x = Eigen::Vector3d::UnitX(), up = Eigen::Vector3d::UnitY(),
                  front = Eigen::Vector3d::UnitZ(), center = Eigen::Vector3d::Zero();
};

// A rough placement without a fit (timing runs, and the viewer's stand-in when a fit failed or is
// off): the frame's bridge (canonical origin) centred across the head box, at 60 % of its height,
// 12 % inside its front face, the frame 80 % as wide as the box (widths under 1 mm count as 1 mm);
// axes aligned with `axes`, the box measured along them. Not a try-on fit.
Transform rough_placement(double frame_width_mm, const Eigen::Vector3d& box_min,
                          const Eigen::Vector3d& box_max, const HeadAxes& axes = {});

}  // namespace lorgnette::fit
