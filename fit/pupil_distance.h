// Pupillary distance from the irises: the distance between the two limbus centres (iris.h,
// IrisMeasurement::centre), each the mean over its eye's views. The limbus is a sharp circle tens of
// pixels across in the iris views, so its centre is found to a fraction of a pixel; the eye's six
// dlib landmarks (lids and corners) are not where the pupil is: their mean sits 1-2 mm off it on
// rendered heads, which is what PD needs to be better than. The pupil is centred in the limbus to
// about 0.2 mm in adults, well under this figure's uncertainty.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "fit/iris.h"

namespace lorgnette::fit {

struct PupilDistanceOptions {
  // The floor of each eye centre's 1-sigma, as a share of its iris diameter: the views are renders
  // of one model a few degrees apart, so their spread misses what they share (the model's own blur of
  // an iris the capture saw 10-25 px across). A twentieth of the iris (about 0.6 mm) is a
  // capture pixel or two at 768 px.
  double sigma_floor_per_iris = 0.05;
};

struct PupilDistance {
  bool ok = false;
  std::string why;  // when not ok: which eye had no limbus
  double units = 0.0;
  double sigma_left = 0.0, sigma_right = 0.0;  // each eye centre's 1-sigma along the eyes' line, units
  Eigen::Vector3d left = Eigen::Vector3d::Zero(), right = Eigen::Vector3d::Zero();
};

// Needs at least one limbus found for each eye (IrisMeasurement::eye +1 left, -1 right).
PupilDistance pupil_distance(const std::vector<IrisMeasurement>& measurements,
                             const PupilDistanceOptions& options = {});

}  // namespace lorgnette::fit
