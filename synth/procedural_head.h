// The procedural human head: a seeded, parameterised, textured triangle mesh in millimetres (head
// frame: origin at the head centre, x towards the wearer's left, y up, z forward out of the face,
// eye level at y = 0) with its anatomical landmarks known exactly: every landmark is a point of the
// mesh surface (found by ray casting the final mesh), placed on the painted feature it names.
// This is Lorgnette's demo subject and the ground truth for the fit's accuracy tests.
#pragma once
#include <Eigen/Core>
#include <array>
#include <map>
#include <string>

#include "mesh/trimesh.h"
#include "synth/face_layout.h"
#include "synth/head_params.h"

namespace lorgnette::synth {

struct HeadMeshOptions {
  int longitudes = 640;      // grid columns around the vertical axis
  int latitudes = 320;       // grid rows from the crown to the neck
  int texture_width = 2048;  // latitude-longitude texture, width x width/2
};

struct ProceduralHead {
  HeadParams params;
  FaceLayout layout;
  mesh::TriMesh mesh;  // millimetres, head frame, one material with the painted texture
  // The 68 iBUG landmarks on the surface. 17-67 lie on the painted features (frontal projection of
  // the layout); 0-16 are the face contour of a frontal view (the cheek/jaw silhouette), which is
  // view dependent by nature: use them with a looser tolerance.
  std::array<Eigen::Vector3f, 68> ibug;
  // Named anatomical points: nose_bridge, nose_tip, chin, eye_r_outer, eye_r_inner, eye_l_inner,
  // eye_l_outer, pupil_r, pupil_l, ear_top_r, ear_top_l (highest point of each ear),
  // ear_rest_r, ear_rest_l (where a temple arm rests: the crease above the ear root).
  std::map<std::string, Eigen::Vector3f> landmarks;
  // The face's width at the temples, where a frame's temples pass: the head's sides at the height of
  // the outer eye corners, kTempleDepthShare of the way back from them to the ear rests (a share, so
  // it lies at the same place on heads of every size; kept out of `landmarks`, whose points all lie
  // on painted features or the ears).
  Eigen::Vector3f temple_r = Eigen::Vector3f::Zero(), temple_l = Eigen::Vector3f::Zero();
  float temple_width() const { return (temple_l - temple_r).norm(); }
};

constexpr float kTempleDepthShare = 0.25f;

// Throws std::runtime_error when the parameters are implausible (see validate()).
ProceduralHead make_procedural_head(const HeadParams& params, const HeadMeshOptions& options = {});

}  // namespace lorgnette::synth
