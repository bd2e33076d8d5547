// The painted albedo of the procedural head: skin with blush, hair cap with a natural hairline and
// strands, brows, eyes (sclera, iris, pupil, lash line, lid crease, socket shading), nostrils, lips
// with a dark lip line, ears. Features are painted by frontal projection from the facial layout, so
// every landmark sits exactly on the feature it names. `bake_latlong_texture` evaluates the albedo
// on the head's latitude-longitude texture (texel -> surface point through the vertex grid).
#pragma once
#include <Eigen/Core>
#include <functional>

#include "host/util/image_io.h"
#include "synth/face_layout.h"
#include "synth/head_params.h"

namespace lorgnette::synth {

class HeadPainter {
 public:
  // ear_centre (x > 0 side) and ear_radii: the ear ellipsoid; face_front_z: features are painted on
  // points in front of this plane only (the back of the head is never "a face").
  HeadPainter(const HeadParams& params, const FaceLayout& layout, const Eigen::Vector3f& ear_centre,
              const Eigen::Vector3f& ear_radii, float face_front_z);
  // Linear RGB albedo at a surface point (head frame, mm).
  Eigen::Vector3f albedo(const Eigen::Vector3f& p) const;

 private:
  float hair_coverage(const Eigen::Vector3f& p) const;
  Eigen::Vector3f paint_eye(const EyeShape& eye, const Eigen::Vector2f& q, const Eigen::Vector3f& skin) const;
  Eigen::Vector3f paint_mouth(const Eigen::Vector2f& q, const Eigen::Vector3f& skin) const;
  Eigen::Vector3f paint_brows(const Eigen::Vector2f& q, const Eigen::Vector3f& skin) const;
  Eigen::Vector3f paint_nose(const Eigen::Vector2f& q, const Eigen::Vector3f& skin) const;
  Eigen::Vector3f paint_ear(const Eigen::Vector3f& p, const Eigen::Vector3f& skin) const;

  HeadParams p_;
  FaceLayout f_;
  Eigen::Vector3f ear_c_, ear_r_;
  float front_z_;
};

// Texture of `width` x `width/2` texels; surface(u, v) returns the surface point for texture
// coordinates in [0, 1]^2 (glTF convention, v down).
Image bake_latlong_texture(const HeadPainter& painter, int width,
                           const std::function<Eigen::Vector3f(float u, float v)>& surface);

}  // namespace lorgnette::synth
