// The camera model shared by the host, the training and marching kernels, and the Embree surface
// pass: pinhole with OPENCV distortion (k1 k2 p1 p2), camera-to-world in the instant-ngp /
// nerfstudio convention (OpenGL style: the camera looks down -z, +y up, +x right; image y down).
// Pixel (u, v) in continuous coordinates: the centre of pixel (i, j) is (i + 0.5, j + 0.5).
#pragma once
#include "common/cl_compat.h"

typedef struct LgnVec3 {
  float x, y, z;
} LgnVec3;

typedef struct Camera {
  float c2w[12];           // row-major 3x4 camera-to-world: rotation columns are camera x, y, z axes
  float fx, fy, cx, cy;    // pixels
  float k1, k2, p1, p2;    // OPENCV distortion (0 for an ideal pinhole)
  lgn_uint width, height;  // pixels
  lgn_uint pad0, pad1;
} Camera;

LGN_STATIC_ASSERT(sizeof(Camera) == 96, "Camera layout is shared with OpenCL: keep it packed");

LGN_INLINE LgnVec3 lgn_vec3(float x, float y, float z) {
  LgnVec3 v;
  v.x = x;
  v.y = y;
  v.z = z;
  return v;
}

// Undistorts normalised image coordinates (x_d, y_d) -> (x, y) by fixed-point iteration (as OpenCV's
// undistortPoints); exact for zero distortion, converges in a few steps for phone-like lenses.
LGN_INLINE void camera_undistort(const Camera* cam, float xd, float yd, float* xo, float* yo) {
  float x = xd, y = yd;
  if (cam->k1 != 0.0f || cam->k2 != 0.0f || cam->p1 != 0.0f || cam->p2 != 0.0f) {
    for (int it = 0; it < 10; ++it) {
      float r2 = x * x + y * y;
      float radial = 1.0f + r2 * (cam->k1 + r2 * cam->k2);
      float dx = 2.0f * cam->p1 * x * y + cam->p2 * (r2 + 2.0f * x * x);
      float dy = cam->p1 * (r2 + 2.0f * y * y) + 2.0f * cam->p2 * x * y;
      x = (xd - dx) / radial;
      y = (yd - dy) / radial;
    }
  }
  *xo = x;
  *yo = y;
}

// Forward distortion of normalised coordinates (for projecting points into a distorted image).
LGN_INLINE void camera_distort(const Camera* cam, float x, float y, float* xo, float* yo) {
  float r2 = x * x + y * y;
  float radial = 1.0f + r2 * (cam->k1 + r2 * cam->k2);
  *xo = x * radial + 2.0f * cam->p1 * x * y + cam->p2 * (r2 + 2.0f * x * x);
  *yo = y * radial + cam->p1 * (r2 + 2.0f * y * y) + 2.0f * cam->p2 * x * y;
}

LGN_INLINE LgnVec3 camera_origin(const Camera* cam) {
  return lgn_vec3(cam->c2w[3], cam->c2w[7], cam->c2w[11]);
}

// Unit world-space direction of the ray through continuous pixel coordinates (u, v).
LGN_INLINE LgnVec3 camera_ray_dir(const Camera* cam, float u, float v) {
  float x, y;
  camera_undistort(cam, (u - cam->cx) / cam->fx, (v - cam->cy) / cam->fy, &x, &y);
  // Camera space (OpenGL): +x right, +y up (image v grows downwards), looking down -z.
  float cx = x, cy = -y, cz = -1.0f;
  const float* m = cam->c2w;
  float dx = m[0] * cx + m[1] * cy + m[2] * cz;
  float dy = m[4] * cx + m[5] * cy + m[6] * cz;
  float dz = m[8] * cx + m[9] * cy + m[10] * cz;
  float inv = 1.0f / sqrt(dx * dx + dy * dy + dz * dz);
  return lgn_vec3(dx * inv, dy * inv, dz * inv);
}

// Projects a world point to continuous pixel coordinates; returns the depth along the camera's
// viewing axis (positive in front of the camera, <= 0 behind it).
LGN_INLINE float camera_project(const Camera* cam, LgnVec3 p, float* u, float* v) {
  const float* m = cam->c2w;
  float px = p.x - m[3], py = p.y - m[7], pz = p.z - m[11];
  // Inverse rotation = transpose.
  float xc = m[0] * px + m[4] * py + m[8] * pz;
  float yc = m[1] * px + m[5] * py + m[9] * pz;
  float zc = m[2] * px + m[6] * py + m[10] * pz;
  float depth = -zc;
  float xn = xc / depth, yn = -yc / depth;
  float xd, yd;
  camera_distort(cam, xn, yn, &xd, &yd);
  *u = cam->fx * xd + cam->cx;
  *v = cam->fy * yd + cam->cy;
  return depth;
}

// An ideal pinhole at `eye` looking at `target` with `up` (not parallel to the view direction:
// callers check), vertical field of view in degrees, principal point at the image centre. The one
// look-at rule of the project: orbits, synthetic rigs, surface previews and fit views all use it.
LGN_INLINE Camera camera_look_at(LgnVec3 eye, LgnVec3 target, LgnVec3 up, float fov_y_deg, lgn_uint width,
                                 lgn_uint height) {
  float bx = eye.x - target.x, by = eye.y - target.y, bz = eye.z - target.z;  // camera +z (looks down -z)
  float bn = 1.0f / sqrt(bx * bx + by * by + bz * bz);
  bx *= bn, by *= bn, bz *= bn;
  float rx = up.y * bz - up.z * by, ry = up.z * bx - up.x * bz, rz = up.x * by - up.y * bx;  // up x back
  float rn = 1.0f / sqrt(rx * rx + ry * ry + rz * rz);
  rx *= rn, ry *= rn, rz *= rn;
  float ux = by * rz - bz * ry, uy = bz * rx - bx * rz, uz = bx * ry - by * rx;  // back x right
  Camera c;
  c.c2w[0] = rx, c.c2w[1] = ux, c.c2w[2] = bx, c.c2w[3] = eye.x;
  c.c2w[4] = ry, c.c2w[5] = uy, c.c2w[6] = by, c.c2w[7] = eye.y;
  c.c2w[8] = rz, c.c2w[9] = uz, c.c2w[10] = bz, c.c2w[11] = eye.z;
  c.fy = 0.5f * (float)height / tan(0.5f * fov_y_deg * 3.14159265358979f / 180.0f);
  c.fx = c.fy;
  c.cx = 0.5f * (float)width;
  c.cy = 0.5f * (float)height;
  c.k1 = c.k2 = c.p1 = c.p2 = 0.0f;
  c.width = width;
  c.height = height;
  c.pad0 = c.pad1 = 0;
  return c;
}
