// The synthetic subject's mesh, rebuilt from a `lorgnette synth` dataset's ground_truth.json (the mesh
// file, or the procedural head from its seed) and placed in a trained model's frame, as a
// MeshViewSource: the ground-truth geometry that the fit benchmarks compare a NeRF fit against.
#pragma once
#include <Eigen/Core>
#include <memory>
#include <string>

#include "eval/mesh_view_source.h"
#include "host/nerf/model.h"

namespace lorgnette::fit {

// `studio`: the views are lit as in the dataset (synth's studio lighting, fixed in the world frame)
// over white, so dlib sees what it sees on the NeRF; otherwise MeshViewSource's camera light.
// Throws when the dataset has no ground_truth.json or its procedural head differs from the seed's.
std::unique_ptr<MeshViewSource> subject_source(const std::string& dataset, const nerf::NerfModel& model,
                                               ViewPrior prior, bool studio);

// synth's anatomical ear rests (`ear_rest_l/r`, procedural heads only) in the model's frame.
struct Anatomy {
  bool known = false;  // false: the dataset's ground truth has none (a mesh subject)
  Eigen::Vector3d ear_l = Eigen::Vector3d::Zero(), ear_r = Eigen::Vector3d::Zero();
};
Anatomy anatomy_of(const std::string& dataset, const nerf::NerfModel& model);

}  // namespace lorgnette::fit
