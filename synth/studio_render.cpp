// Studio rendering for dataset synthesis; see studio_render.h. Each pixel averages n x n stratified
// sub-pixel rays; each sub-sample also takes one stratified point on the key light's disc for its
// shadow ray, so n^2 samples give both anti-aliasing and soft shadows. Shadow rays start a small
// offset along the geometric normal (relative to the scene size) to avoid self-intersection.
// Emissive surfaces (a window) add their radiance to the lit colour and let the key light through:
// they are the opening the light comes in by, so a shadow ray whose first hit glows is lit.
#include "synth/studio_render.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "mesh/texture.h"

namespace lorgnette::synth {
namespace {

using V3 = Eigen::Vector3f;

V3 to_v3(LgnVec3 v) { return {v.x, v.y, v.z}; }

// Point on the light's disc around `dir` for stratified sample (a, b) in [0, 1)^2.
V3 disc_direction(const V3& dir, float radius_rad, float a, float b) {
  V3 w = dir.normalized();
  V3 t = (std::abs(w.x()) < 0.9f ? V3(1, 0, 0) : V3(0, 1, 0)).cross(w).normalized();
  V3 s = w.cross(t);
  float r = std::tan(radius_rad) * std::sqrt(a), phi = 2.0f * float(M_PI) * b;
  return (w + r * (std::cos(phi) * t + std::sin(phi) * s)).normalized();
}

V3 albedo_at(const mesh::TriMesh& m, const mesh::Hit& h) {
  if (h.material < 0 || h.material >= int(m.materials.size())) return V3(0.8f, 0.8f, 0.8f);
  const mesh::Material& mat = m.materials[h.material];
  V3 c = mat.base_color;
  if (mat.base_color_texture >= 0 && mat.base_color_texture < int(m.textures.size()) && !m.uvs.empty())
    c = c.cwiseProduct(mesh::sample_texture(m.textures[mat.base_color_texture], h.uv).head<3>());
  return c;
}

V3 emission_at(const mesh::TriMesh& m, const mesh::Hit& h) {
  if (h.material < 0 || h.material >= int(m.materials.size())) return V3::Zero();
  return m.materials[size_t(h.material)].emission;
}

bool has_emission(const mesh::TriMesh& m) {
  for (const mesh::Material& mat : m.materials)
    if (mat.emission.maxCoeff() > 0.0f) return true;
  return false;
}

struct Shader {
  const mesh::EmbreeScene& scene;
  const StudioLighting& light;
  V3 key, fill;
  float eps;
  int subject = -1;       // triangles [0, subject) take the highlight (-1: all)
  bool emitters = false;  // the scene has emissive surfaces (costs a full hit on blocked shadow rays)

  bool key_blocked(const V3& p, const V3& kd) const {
    if (!scene.occluded(p, kd)) return false;
    return !emitters || emission_at(scene.mesh(), scene.intersect(p, kd)).maxCoeff() <= 0.0f;
  }

  V3 shade(const mesh::Hit& h, const V3& ray_dir, float la, float lb) const {
    V3 n = h.shading_normal, ng = h.geometric_normal;
    if (ng.dot(ray_dir) > 0) ng = -ng;  // face the viewer (open or inconsistently wound meshes)
    if (n.dot(ng) < 0) n = -n;
    V3 p = h.position + eps * ng;
    float e = light.sky * (0.5f + 0.5f * n.y()) + light.ground * (0.5f - 0.5f * n.y());
    V3 kd = disc_direction(key, light.key_radius_deg * float(M_PI) / 180.0f, la, lb);
    float k = std::max(0.0f, n.dot(kd));
    if (k > 0 && light.shadows && key_blocked(p, kd)) k = 0;
    e += light.key * k + light.fill * std::max(0.0f, n.dot(fill));
    V3 c = e * albedo_at(scene.mesh(), h) + emission_at(scene.mesh(), h);
    if (light.specular > 0.0f && k > 0.0f && (subject < 0 || h.triangle < subject)) {
      const V3 half = (kd - ray_dir.normalized()).normalized();
      c += V3::Constant(light.specular * light.key * std::pow(std::max(0.0f, n.dot(half)), light.shininess));
    }
    return c;
  }
};

}  // namespace

RenderedView render_view(const mesh::EmbreeScene& scene, const Camera& cam, const StudioLighting& lighting,
                         const RenderSettings& settings) {
  const int w = int(cam.width), hgt = int(cam.height), n = settings.samples_per_axis;
  if (w <= 0 || hgt <= 0 || w > 16384 || hgt > 16384)
    throw std::runtime_error(fmt::format("render: image size {}x{} is out of range (1..16384)", w, hgt));
  if (n < 1 || n > 16)
    throw std::runtime_error(fmt::format("render: samples per axis {} is out of range (1..16)", n));
  RenderedView out{Image(w, hgt, 4), Image(w, hgt, 1), Image()};
  const int subject = settings.subject_triangles;
  if (subject >= 0) out.matte = Image(w, hgt, 1);
  auto is_subject = [subject](const mesh::Hit& h) { return subject < 0 || h.triangle < subject; };
  const float diag = scene.bounds().diagonal().norm();
  Shader shader{scene,        lighting, lighting.key_dir.normalized(), lighting.fill_dir.normalized(),
                1e-4f * diag, subject,  has_emission(scene.mesh())};
  const V3 origin = to_v3(camera_origin(&cam));
  mesh::parallel_rows(hgt, settings.threads, [&](int y) {
    for (int x = 0; x < w; ++x) {
      V3 sum = V3::Zero();
      float cover = 0.0f, matte = 0.0f;
      for (int sy = 0; sy < n; ++sy)
        for (int sx = 0; sx < n; ++sx) {
          float fx = (sx + 0.5f) / n, fy = (sy + 0.5f) / n;
          V3 d = to_v3(camera_ray_dir(&cam, x + fx, y + fy));
          mesh::Hit h = scene.intersect(origin, d);
          if (!h.hit) continue;
          // Light-disc sample decorrelated from the pixel sample (a fixed permutation of strata).
          int s = sy * n + sx, ls = (s * 7 + 3) % (n * n);
          sum += shader.shade(h, d, (ls / n + 0.5f) / n, (ls % n + 0.5f) / n);
          cover += 1.0f;
          if (is_subject(h)) matte += 1.0f;
        }
      float alpha = cover / float(n * n);
      V3 c = cover > 0 ? V3(sum / cover) : V3::Zero();  // straight colour
      if (settings.background) {
        c = alpha * c + (1.0f - alpha) * *settings.background;
        alpha = 1.0f;
      }
      for (int k = 0; k < 3; ++k) out.rgba.at(x, y, k) = c[k];
      out.rgba.at(x, y, 3) = alpha;
      mesh::Hit centre = scene.intersect(origin, to_v3(camera_ray_dir(&cam, x + 0.5f, y + 0.5f)));
      out.depth.at(x, y, 0) =
          centre.hit && is_subject(centre) ? centre.t : std::numeric_limits<float>::infinity();
      if (subject >= 0) out.matte.at(x, y, 0) = matte / float(n * n);
    }
  });
  return out;
}

}  // namespace lorgnette::synth
