// Ground truth for the fit on a mesh head: the same detector on renders of the mesh, each 2D landmark
// ray cast onto the mesh surface, the hits combined per landmark (component-wise median over the
// views; for the jaw contour, over the views that show its side, as the fit does: FitOptions::
// landmarks.contour.side_tolerance, a huge value restores all views); from those, the reference placement's
// f_c, f_l, f_r and head axes, to which a fit is compared (3D errors in mm, rotation error in degrees).
#pragma once
#include <vector>

#include "eval/mesh_view_source.h"
#include "fit/fit.h"

namespace lorgnette::fit {

struct GroundTruth {
  std::vector<Eigen::Vector3d> points;  // 68, scene units
  std::vector<bool> valid;
  HeadFrame head;
  EarPoints ears;
  EarRoots ear_roots;  // what the density search (ear_root.h) found, when the options enable it
  Eigen::Vector3d f_c = Eigen::Vector3d::Zero();
  Placement placement;
  double contour_side_tolerance = 0.0;  // the jaw-contour view rule it was made with
};

// Views at the given yaws (pitch 0) on `orbit`; throws when no view shows a face.
GroundTruth mesh_ground_truth(MeshViewSource& source, const Orbit& orbit, const std::vector<double>& yaws,
                              const GlassesRefPoints& glasses, const FitOptions& options);

// The same from given cameras, e.g. a fit's own views: the jaw contour (temples, hence ears) is view
// dependent, so ground truth from the fit's cameras separates the reconstruction's error from the
// landmark definition's dependence on the views.
GroundTruth mesh_ground_truth(MeshViewSource& source, const std::vector<Camera>& cameras,
                              const GlassesRefPoints& glasses, const FitOptions& options);

struct FitErrors {
  double nose_mm = 0, ear_l_mm = 0, ear_r_mm = 0, rotation_deg = 0, mm_per_unit_rel = 0;
};

// Errors of a fit against ground truth, in mm via the ground truth's mm_per_unit.
FitErrors compare_fit(const FitResult& fit, const GroundTruth& gt);

}  // namespace lorgnette::fit
