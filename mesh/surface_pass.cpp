// Surface pass: sampling, Disney shading, lens transmission, buffer accumulation; see surface_pass.h.
#include "mesh/surface_pass.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "mesh/disney_brdf.h"
#include "mesh/sampling.h"
#include "mesh/texture.h"

namespace lorgnette::mesh {
namespace {

// Karis' analytic fit of the GGX directional albedo (split-sum DFG): specular reflectance of the
// smooth ambient light as a function of F0, n.v and roughness.
Eigen::Vector3f env_specular_albedo(const Eigen::Vector3f& f0, float cos_v, float roughness) {
  const Eigen::Vector4f c0(-1.0f, -0.0275f, -0.572f, 0.022f), c1(1.0f, 0.0425f, 1.04f, -0.04f);
  Eigen::Vector4f r = roughness * c0 + c1;
  float a004 = std::min(r.x() * r.x(), std::exp2(-9.28f * cos_v)) * r.x() + r.y();
  float a = -1.04f * a004 + r.z(), b = 1.04f * a004 + r.w();
  return f0 * a + Eigen::Vector3f::Constant(b);
}

struct ShadeContext {
  const EmbreeScene* scene;
  const SurfaceParams* params;
  Eigen::Matrix3f to_canonical;  // scene direction -> canonical direction
  Eigen::Vector3f key_dir;       // scene space, unit
  float eps;                     // ray offset, scene units
};

// Radiance of an opaque Disney surface towards v (unit, pointing to the camera).
Eigen::Vector3f shade_opaque(const ShadeContext& c, const Hit& h, const BrdfParams& p,
                             const Eigen::Vector3f& n, const Eigen::Vector3f& v) {
  const Lighting& L = c.params->lighting;
  float cos_v = std::max(n.dot(v), 1e-4f);
  Eigen::Vector3f ambient_diffuse = environment(L, c.to_canonical * n);
  Eigen::Vector3f f0 =
      (1.0f - p.metallic) * Eigen::Vector3f::Constant(0.08f * p.specular) + p.metallic * p.base_color;
  Eigen::Vector3f r = 2.0f * n.dot(v) * n - v;
  Eigen::Vector3f out =
      p.base_color.cwiseProduct(ambient_diffuse) * (1.0f - p.metallic) +
      env_specular_albedo(f0, cos_v, p.roughness).cwiseProduct(environment(L, c.to_canonical * r));
  float cos_l = n.dot(c.key_dir);
  if (cos_l > 0.0f) {
    float vis = 1.0f;
    if (L.key_shadow > 0.0f && c.scene->occluded(h.position + c.eps * n, c.key_dir, 0.0f))
      vis = 1.0f - L.key_shadow;
    out += disney_brdf(p, n, c.key_dir, v).cwiseProduct(L.key_irradiance) * (cos_l * vis);
  }
  return out;
}

struct SampleResult {
  Eigen::Vector3f color = Eigen::Vector3f::Zero();
  float alpha = 0.0f;
  Eigen::Vector3f transmit = Eigen::Vector3f::Ones();  // per-channel transmittance to what lies behind
  float depth = std::numeric_limits<float>::infinity();
};

SampleResult trace_sample(const ShadeContext& c, Eigen::Vector3f origin, const Eigen::Vector3f& dir) {
  SampleResult s;
  Eigen::Vector3f throughput = Eigen::Vector3f::Ones();
  const TriMesh& mesh = c.scene->mesh();
  float tnear = 0.0f;
  for (int layer = 0; layer < c.params->max_layers && throughput.maxCoeff() > 1e-3f; ++layer) {
    Hit h = c.scene->intersect(origin, dir, tnear);
    if (!h.hit) break;
    if (layer == 0) s.depth = h.t;
    const Material& m =
        mesh.materials[std::clamp(h.material, 0, static_cast<int>(mesh.materials.size()) - 1)];
    Eigen::Vector4f tex =
        m.base_color_texture >= 0 && m.base_color_texture < static_cast<int>(mesh.textures.size())
            ? sample_texture(mesh.textures[m.base_color_texture], h.uv)
            : Eigen::Vector4f::Ones();
    BrdfParams p{m.base_color.cwiseProduct(tex.head<3>()), m.metallic, m.roughness, m.specular};
    const Eigen::Vector3f v = -dir;
    Eigen::Vector3f n = h.shading_normal;
    if (h.geometric_normal.dot(v) < 0.0f) n = -n;                       // double-sided: face the viewer
    if (n.dot(v) <= 0.0f) n = (n - 1.01f * n.dot(v) * v).normalized();  // keep the shading normal visible
    float a = std::clamp(m.alpha * tex.w(), 0.0f, 1.0f), tr = m.transmission;
    Eigen::Vector3f emitted = (1.0f - tr) * shade_opaque(c, h, p, n, v);
    Eigen::Vector3f pass = Eigen::Vector3f::Zero();
    if (tr > 0.0f) {
      float ior = m.ior > 1.01f ? m.ior : 1.5f;  // ior 1 (no interface) would hide the lens entirely
      float F = fresnel_dielectric(std::max(n.dot(v), 0.0f), ior);
      Eigen::Vector3f r = 2.0f * n.dot(v) * n - v;
      emitted += tr * F * environment(c.params->lighting, c.to_canonical * r);
      Eigen::Vector3f tint = m.tint.cwiseMax(c.params->min_lens_tint);
      pass = tr * (1.0f - F) * tint;
    }
    s.color += throughput.cwiseProduct(a * emitted);
    throughput = throughput.cwiseProduct(Eigen::Vector3f::Constant(1.0f - a) + a * pass);
    origin = h.position;
    tnear = c.eps;
  }
  s.alpha = 1.0f - throughput.mean();
  s.transmit = throughput;
  return s;
}

// See SurfacePass::screen_rect.
std::array<int, 4> screen_bounds(const Camera& cam, const Eigen::AlignedBox3f& box) {
  const std::array<int, 4> all = {0, 0, static_cast<int>(cam.width), static_cast<int>(cam.height)};
  float u0 = 1e30f, v0 = 1e30f, u1 = -1e30f, v1 = -1e30f;
  for (int i = 0; i < 125; ++i) {
    Eigen::Vector3f t(i % 5 / 4.0f, i / 5 % 5 / 4.0f, i / 25 / 4.0f);
    Eigen::Vector3f p = box.min() + t.cwiseProduct(box.sizes());
    float u, v;
    if (!(camera_project(&cam, lgn_vec3(p.x(), p.y(), p.z()), &u, &v) > 0.0f)) return all;
    u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
  }
  auto clampi = [](float x, int hi) { return static_cast<int>(std::clamp(x, 0.0f, static_cast<float>(hi))); };
  return {clampi(std::floor(u0) - 2, all[2]), clampi(std::floor(v0) - 2, all[3]),
          clampi(std::ceil(u1) + 2, all[2]), clampi(std::ceil(v1) + 2, all[3])};
}

}  // namespace

SurfacePass::SurfacePass(const TriMesh& canonical_mesh, const Eigen::Matrix4f& placement) {
  Eigen::Matrix3f lin = placement.topLeftCorner<3, 3>();
  Eigen::JacobiSVD<Eigen::Matrix3f> svd(lin, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3f rot = svd.matrixU() * svd.matrixV().transpose();  // nearest rotation
  scene_to_canonical_rot_ = rot.transpose();
  scene_ = std::make_unique<EmbreeScene>(canonical_mesh, placement);
}

SurfaceBuffers SurfacePass::render(const Camera& cam, const SurfaceParams& params) const {
  if (cam.width == 0 || cam.height == 0 || cam.width > 16384 || cam.height > 16384)
    throw std::runtime_error(
        fmt::format("surface pass: camera size {}x{} is invalid", cam.width, cam.height));
  if (params.samples_per_pixel < 1 || params.samples_per_pixel > 1024)
    throw std::runtime_error(
        fmt::format("surface pass: samples per pixel must be 1..1024, not {}", params.samples_per_pixel));
  SurfaceBuffers out(static_cast<int>(cam.width), static_cast<int>(cam.height));
  ShadeContext c{scene_.get(), &params, scene_to_canonical_rot_, Eigen::Vector3f::Zero(), 0.0f};
  c.key_dir = (scene_to_canonical_rot_.transpose() * params.lighting.key_direction.normalized()).normalized();
  c.eps = 1e-4f * std::max(1e-6f, scene_->bounds().sizes().norm());
  const Eigen::Vector3f origin(cam.c2w[3], cam.c2w[7], cam.c2w[11]);
  const int n = params.samples_per_pixel;
  const std::array<int, 4> rect =
      params.clip_to_bounds
          ? screen_rect(cam)
          : std::array<int, 4>{0, 0, static_cast<int>(cam.width), static_cast<int>(cam.height)};
  parallel_rows(rect[3] - rect[1], params.threads, [&](int row) {
    const int y = rect[1] + row;
    std::vector<Eigen::Vector2f> offsets;
    for (int x = rect[0]; x < rect[2]; ++x) {
      PixelRng rng(pixel_seed(params.seed, x, y));
      stratified_jitter(n, rng, offsets);
      Eigen::Vector3f color = Eigen::Vector3f::Zero(), transmit = Eigen::Vector3f::Zero();
      float alpha = 0.0f, depth = std::numeric_limits<float>::infinity();
      for (const auto& o : offsets) {
        LgnVec3 d = camera_ray_dir(&cam, x + o.x(), y + o.y());
        SampleResult s = trace_sample(c, origin, Eigen::Vector3f(d.x, d.y, d.z));
        color += s.color;
        alpha += s.alpha;
        transmit += s.transmit;
        depth = std::min(depth, s.depth);
      }
      size_t i = static_cast<size_t>(y) * out.width + x;
      for (int k = 0; k < 3; ++k) out.color_alpha[4 * i + k] = color[k] / n;
      out.color_alpha[4 * i + 3] = alpha / n;
      out.depth[i] = depth;
      // F = mean per-channel transmittance / its mean over channels (1 - S_α); 1 when nothing passes.
      const float mean_t = transmit.mean();
      for (int k = 0; k < 3; ++k) out.filter[3 * i + k] = mean_t > 1e-6f ? transmit[k] / mean_t : 1.0f;
    }
  });
  return out;
}

std::array<int, 4> SurfacePass::screen_rect(const Camera& camera) const {
  return screen_bounds(camera, scene_->bounds());
}

Camera look_at_camera(const Eigen::Vector3f& eye, const Eigen::Vector3f& target, const Eigen::Vector3f& up,
                      float fov_y_deg, int width, int height) {
  auto v = [](const Eigen::Vector3f& p) { return lgn_vec3(p.x(), p.y(), p.z()); };
  return camera_look_at(v(eye), v(target), v(up), fov_y_deg, static_cast<lgn_uint>(width),
                        static_cast<lgn_uint>(height));
}

}  // namespace lorgnette::mesh
