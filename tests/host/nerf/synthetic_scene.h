// A small analytic scene for the NeRF tests: a sphere whose colour varies with the surface normal,
// rendered exactly (2x2 supersampled coverage as alpha) into RGBA views from cameras on a ring
// around it. Cameras use the OpenGL convention of camera_types.h.
#pragma once
#include <cmath>
#include <vector>

#include "common/camera_types.h"
#include "host/nerf/views.h"
#include "host/util/image_io.h"

namespace lorgnette::nerf::nerftest {

inline Camera look_at_camera(float ex, float ey, float ez, int size, float fov_deg) {
  // z axis points from the target (origin) to the eye: the camera looks down -z.
  float zx = ex, zy = ey, zz = ez, zn = std::sqrt(zx * zx + zy * zy + zz * zz);
  zx /= zn, zy /= zn, zz /= zn;
  float xx = zz, xy = 0.0f, xz = -zx;  // up (0,1,0) x z
  float xn = std::sqrt(xx * xx + xz * xz);
  xx /= xn, xz /= xn;
  float yx = zy * xz - zz * xy, yy = zz * xx - zx * xz, yz = zx * xy - zy * xx;
  Camera c{};
  float m[12] = {xx, yx, zx, ex, xy, yy, zy, ey, xz, yz, zz, ez};
  for (int i = 0; i < 12; ++i) c.c2w[i] = m[i];
  c.fx = c.fy = 0.5f * size / std::tan(0.5f * fov_deg * 3.14159265f / 180.0f);
  c.cx = c.cy = 0.5f * size;
  c.width = c.height = uint32_t(size);
  return c;
}

struct SphereScene {
  float radius = 0.5f;
  // Colour (linear) of the surface point with unit normal n.
  static void color(float nx, float ny, float nz, float* rgb) {
    rgb[0] = 0.15f + 0.7f * (0.5f + 0.5f * nx);
    rgb[1] = 0.15f + 0.7f * (0.5f + 0.5f * ny);
    rgb[2] = 0.15f + 0.7f * (0.5f + 0.5f * nz);
  }
  Image render(const Camera& cam) const {
    Image im(int(cam.width), int(cam.height), 4);
    LgnVec3 o = camera_origin(&cam);
    for (int y = 0; y < im.height; ++y)
      for (int x = 0; x < im.width; ++x) {
        float acc[4] = {0, 0, 0, 0};
        for (int s = 0; s < 4; ++s) {
          LgnVec3 d = camera_ray_dir(&cam, x + 0.25f + 0.5f * (s & 1), y + 0.25f + 0.5f * (s >> 1));
          float b = o.x * d.x + o.y * d.y + o.z * d.z;
          float c = o.x * o.x + o.y * o.y + o.z * o.z - radius * radius;
          float disc = b * b - c;
          if (disc < 0.0f) continue;
          float t = -b - std::sqrt(disc);
          float rgb[3];
          color((o.x + t * d.x) / radius, (o.y + t * d.y) / radius, (o.z + t * d.z) / radius, rgb);
          for (int k = 0; k < 3; ++k) acc[k] += 0.25f * rgb[k];
          acc[3] += 0.25f;
        }
        // Straight alpha: colour of the covered part.
        for (int k = 0; k < 3; ++k) im.at(x, y, k) = acc[3] > 0.0f ? acc[k] / acc[3] : 0.0f;
        im.at(x, y, 3) = acc[3];
      }
    return im;
  }
};

// `n` cameras at distance `dist` around the origin, alternating elevations; `offset` shifts the
// azimuths (held-out views between the training ones).
inline std::vector<Camera> ring_cameras(int n, float dist, int size, float offset = 0.0f) {
  std::vector<Camera> cams;
  for (int i = 0; i < n; ++i) {
    float az = 6.2831853f * (i + offset) / n, el = (i % 3 - 1) * 0.45f;
    cams.push_back(look_at_camera(dist * std::cos(el) * std::sin(az), dist * std::sin(el),
                                  dist * std::cos(el) * std::cos(az), size, 45.0f));
  }
  return cams;
}

struct SceneViews {
  std::vector<Image> images;
  std::vector<View> views;
};

inline SceneViews render_views(const std::vector<Camera>& cams) {
  SphereScene scene;
  SceneViews out;
  out.images.reserve(cams.size());
  for (const auto& c : cams) out.images.push_back(scene.render(c));
  for (size_t i = 0; i < cams.size(); ++i) out.views.push_back(View{cams[i], &out.images[i]});
  return out;
}

}  // namespace lorgnette::nerf::nerftest
