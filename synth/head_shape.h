// The procedural head's geometry as a signed distance function in the head frame (millimetres,
// origin at the head centre, x towards the wearer's left, y up, z forward out of the face, eye
// level at y = 0): ellipsoids for cranium, lower face, jaw, cheekbones and brow ridge, eye sockets
// carved out and eyeballs set in, a nose from a rounded cone with alae, lips, chin, ears and a neck,
// blended with smooth minimum so the surface has no creases. The head is star-shaped about the
// centre, so `surface_radius` (the outermost crossing along a ray from the centre) turns it into a
// watertight latitude-longitude mesh.
#pragma once
#include <Eigen/Core>

#include "synth/face_layout.h"
#include "synth/head_params.h"

namespace lorgnette::synth {

class HeadShape {
 public:
  HeadShape(const HeadParams& params, const FaceLayout& layout);
  // Signed distance bound (negative inside; never overestimates by more than a few per cent).
  float sdf(const Eigen::Vector3f& p) const;
  // The same with the neck continued downwards past its flat cut, as the body's loft continues it
  // (synth/body.h: the same axis, a radius 1.5 mm larger, widening into the shoulders), so inside
  // means inside the subject's neck below the head's own mesh too.
  float sdf_with_body_neck(const Eigen::Vector3f& p) const;
  // Distance from the centre to the outermost surface point along the unit direction `dir`.
  float surface_radius(const Eigen::Vector3f& dir) const;
  Eigen::Vector3f ear_centre(int side) const {
    return {side * ear_centre_.x(), ear_centre_.y(), ear_centre_.z()};
  }
  const Eigen::Vector3f& ear_radii() const { return ear_radii_; }
  float eye_corner_z() const { return glabella_z_ - 12.0f; }

 private:
  float face_part(const Eigen::Vector3f& p) const;
  float nose_part(const Eigen::Vector3f& p) const;
  float side_part(const Eigen::Vector3f& p) const;
  // The neck's vertical cylinder, cut flat at its top only.
  float neck_cylinder(const Eigen::Vector3f& p) const;

  HeadParams params_;
  FaceLayout layout_;
  float glabella_z_ = 96.0f;
  float neck_bottom_ = -175.0f;
  Eigen::Vector3f ear_centre_, ear_radii_;
  float bound_ = 320.0f;
};

}  // namespace lorgnette::synth
