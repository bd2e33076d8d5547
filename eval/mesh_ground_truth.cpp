// Ray-cast ground truth on a mesh head (see mesh_ground_truth.h).
#include "eval/mesh_ground_truth.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "fit/camera_math.h"
#include "fit/ear_root.h"
#include "fit/landmark_ids.h"
#include "fit/mean_face.h"
#include "fit/surface_landmarks.h"

namespace lorgnette::fit {

GroundTruth mesh_ground_truth(MeshViewSource& source, const Orbit& orbit, const std::vector<double>& yaws,
                              const GlassesRefPoints& glasses, const FitOptions& options) {
  std::vector<Camera> cams;
  for (double yaw : yaws) cams.push_back(orbit_camera(orbit, yaw, 0.0));
  return mesh_ground_truth(source, cams, glasses, options);
}

GroundTruth mesh_ground_truth(MeshViewSource& source, const std::vector<Camera>& cameras,
                              const GlassesRefPoints& glasses, const FitOptions& options) {
  LandmarkDetector detector(options.detection.detector);
  std::vector<std::vector<Eigen::Vector3d>> hits(lm::kCount);
  std::vector<std::vector<Eigen::Vector3d>> side_hits(lm::kCount);  // jaw contour: from its own side only
  for (const Camera& cam : cameras) {
    FaceDetection d = detector.detect(source.render(cam));
    if (!d.found) continue;
    for (int k = 0; k < lm::kCount; ++k) {
      Ray r = camera_ray(cam, d.points[k]);
      mesh::Hit h = source.cast(r.origin.cast<float>(), r.dir.cast<float>());
      if (!h.hit) continue;
      hits[k].push_back(h.position.cast<double>());
      if (contour_side_visible(k, d, options.landmarks.contour.side_tolerance))
        side_hits[k].push_back(hits[k].back());
    }
  }
  // The fit's rule for the jaw contour (surface_landmarks.h), unless no view shows a landmark's side.
  for (int k = 0; k < lm::kCount; ++k)
    if (!side_hits[k].empty()) hits[k] = side_hits[k];
  GroundTruth gt;
  gt.contour_side_tolerance = options.landmarks.contour.side_tolerance;
  gt.points.assign(lm::kCount, Eigen::Vector3d::Zero());
  gt.valid.assign(lm::kCount, false);
  for (int k = 0; k < lm::kCount; ++k)
    if (!hits[k].empty()) gt.points[k] = component_median(hits[k]), gt.valid[k] = true;
  if (std::count(gt.valid.begin(), gt.valid.end(), true) < 40)
    throw std::runtime_error("ground truth: the detector found no face on the mesh renders");
  gt.head = estimate_head_frame(gt.points, gt.valid, mean_face_or_builtin(options.head.mean_face_path));
  const auto& P = gt.points;
  gt.f_c = nose_point(P[lm::kNoseBridgeTop], P[lm::kNoseBridge2], options.head.nose_blend);
  EarInputs ei{P[lm::kEyeOuterL], P[lm::kEyeOuterR], P[lm::kTempleL],
               P[lm::kTempleR],   gt.head.d_up,      gt.head.d_fwd};
  gt.ears = ear_points(ei, options.head.alpha);
  if (options.head.ear_root.enabled) {  // the fit's rule (ear_root.h) on the mesh's inside indicator
    DensityFn density = [&source](const std::vector<Eigen::Vector3f>& p) { return source.density(p); };
    gt.ear_roots =
        apply_ear_roots(density, ei, gt.head.d_eye, gt.head.mm_per_unit, options.head.ear_root, gt.ears);
  }
  gt.placement =
      place_glasses(glasses, {gt.f_c, gt.ears.f_l, gt.ears.f_r, ei.t_l, ei.t_r, gt.head.mm_per_unit},
                    // The ground truth's scale is the mean face's: "auto" is stretch with it.
                    resolve_scale_policy(options.place.scale_policy, ScaleSource::kMeanFace));
  return gt;
}

FitErrors compare_fit(const FitResult& fit, const GroundTruth& gt) {
  const double mm = gt.head.mm_per_unit;
  FitErrors e;
  e.nose_mm = (fit.f_c - gt.f_c).norm() * mm;
  e.ear_l_mm = (fit.ears.f_l - gt.ears.f_l).norm() * mm;
  e.ear_r_mm = (fit.ears.f_r - gt.ears.f_r).norm() * mm;
  Eigen::AngleAxisd d(fit.placement.rotation * gt.placement.rotation.transpose());
  e.rotation_deg = std::abs(d.angle()) * 180.0 / M_PI;
  e.mm_per_unit_rel = fit.head.mm_per_unit / mm - 1.0;
  return e;
}

}  // namespace lorgnette::fit
