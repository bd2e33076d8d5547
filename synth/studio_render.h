// Offline rendering of a textured TriMesh for dataset synthesis: Embree primary rays with stratified
// anti-aliasing, a diffuse (Lambert) surface (with an optional highlight on the subject) shaded by a soft
// studio setup fixed in the world frame (key light with soft shadows, fill light, sky/ground ambient), so the
// lighting is baked consistently into every view; glowing surfaces (mesh::Material::emission) add their
// light. Outputs linear RGBA with coverage alpha (straight colour, as instant-ngp reads PNGs) and the depth
// of the pixel-centre ray.
#pragma once
#include <Eigen/Core>
#include <optional>

#include "common/camera_types.h"
#include "host/util/image_io.h"
#include "mesh/embree_scene.h"

namespace lorgnette::synth {

struct StudioLighting {
  Eigen::Vector3f key_dir{-0.45f, 0.55f, 0.70f};  // towards the light, world frame (normalised on use)
  float key = 0.85f;
  float key_radius_deg = 9.0f;  // angular radius of the key's disc: shadow softness
  Eigen::Vector3f fill_dir{0.65f, 0.15f, 0.75f};
  float fill = 0.30f;
  float sky = 0.30f;     // ambient from above (hemisphere, world +y)
  float ground = 0.12f;  // ambient from below
  bool shadows = true;
  // A white Blinn-Phong highlight of the key light on the subject (RenderSettings::subject_triangles),
  // added to its diffuse colour: oily skin's sheen on the forehead and the nose, which a room model
  // can explain with a pale wall's colour (#41). 0 = Lambert only.
  float specular = 0.0f;
  float shininess = 40.0f;
};

struct RenderSettings {
  int samples_per_axis = 3;                   // anti-aliasing: n x n stratified samples per pixel
  std::optional<Eigen::Vector3f> background;  // linear RGB; empty = transparent (alpha = coverage)
  int threads = 0;                            // 0 = hardware concurrency
  // Triangles [0, subject_triangles) are the subject, the rest its surroundings (a room): the view
  // then also gets the subject's matte, and depth counts the subject only. -1 = all are the subject.
  int subject_triangles = -1;
};

struct RenderedView {
  Image rgba;   // linear, 4 channels, straight (not premultiplied) colour
  Image depth;  // 1 channel: distance along the unit pixel-centre ray (scene units), +inf where no hit
  Image matte;  // 1 channel: the subject's coverage (fraction of the pixel's samples); only with a room
};

// The scene must be in the frame of the camera (the dataset frame).
RenderedView render_view(const mesh::EmbreeScene& scene, const Camera& camera, const StudioLighting& lighting,
                         const RenderSettings& settings);

}  // namespace lorgnette::synth
