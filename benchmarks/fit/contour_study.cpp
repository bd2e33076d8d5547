// Study (not a benchmark): where the jaw-contour rays (dlib 0/16 = the temples) meet a NeRF and
// the subject's mesh. Per level view at each yaw: the density intervals along the ray through the
// detected point (M@m: mesh at the mesh's detection, N@m / N@n: NeRF at the mesh's / NeRF's
// detection) and the NeRF's opacity-0.5 depth (O@m / O@n), in the ground truth's head frame (mm from
// f_c: x = d_eye, y = d_up, z = d_fwd).
// Usage: contour_study --case MODEL DATASET
#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <iostream>
#include <tuple>

#include "eval/mesh_ground_truth.h"
#include "fit/camera_math.h"
#include "fit/fit.h"
#include "fit/glasses_input.h"
#include "fit/landmark_ids.h"
#include "fit/nerf_view_source.h"
#include "fit/ray_surface.h"
#include "subject_mesh.h"

using namespace lorgnette;
using namespace lorgnette::fit;

namespace {

struct Interval {
  double in, out;
};

std::vector<Interval> intervals(ViewSource& s, const Ray& r, double t0, double t1, float thr) {
  const int n = 4096;
  std::vector<Eigen::Vector3f> p;
  for (int i = 0; i < n; ++i) p.push_back((r.origin + (t0 + (t1 - t0) * i / (n - 1)) * r.dir).cast<float>());
  std::vector<float> d = s.density(p);
  std::vector<Interval> out;
  bool inside = false;
  for (int i = 0; i < n; ++i) {
    double t = t0 + (t1 - t0) * i / (n - 1);
    if (!inside && d[i] > thr)
      out.push_back({t, t1}), inside = true;
    else if (inside && d[i] <= thr)
      out.back().out = t, inside = false;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) return std::cerr << "usage: contour_study --case MODEL DATASET\n", 2;
  cl::Runtime rt;
  nerf::NerfModel model = nerf::NerfModel::load(rt, argv[2]);
  ViewPrior prior = prior_from_transforms(std::string(argv[3]) + "/transforms.json", model);
  NerfViewSource nerf(model, prior);
  auto mesh = subject_source(argv[3], model, prior, true);
  GlassesInput g =
      load_glasses_input(std::string(LORGNETTE_DATA_DIR) + "/glasses/glasses-06/scene.gltf", 500);
  FitOptions base;
  GlassesInput no_frame;  // the reference points alone: no contact stage, as only the orbit is used
  no_frame.ref = g.ref;
  FitResult ref = fit_glasses(*mesh, no_frame, base);
  GroundTruth gt = mesh_ground_truth(*mesh, ref.orbit, {-20, -10, 0, 10, 20}, g.ref, base);
  const double mm = gt.head.mm_per_unit;
  auto head = [&](const Eigen::Vector3d& p) {
    Eigen::Vector3d q = p - gt.f_c;
    return fmt::format("({:6.1f} {:6.1f} {:6.1f})", q.dot(gt.head.d_eye) * mm, q.dot(gt.head.d_up) * mm,
                       q.dot(gt.head.d_fwd) * mm);
  };
  for (int k : {lm::kTempleR, lm::kTempleL})
    std::cout << fmt::format("GT point {}: {}  ear {}\n", k, head(gt.points[k]),
                             head(k == lm::kTempleR ? gt.ears.f_r : gt.ears.f_l));
  LandmarkDetector det(base.detection.detector);
  const float thr = nerf.surface_density();
  const double t0 = 0.5 * ref.orbit.distance, t1 = 1.3 * ref.orbit.distance;
  for (double yaw = -40; yaw <= 40; yaw += 5) {
    Camera cam = orbit_camera(ref.orbit, yaw, 0.0);
    FaceDetection dm = det.detect(mesh->render(cam)), dn = det.detect(nerf.render(cam));
    if (!dm.found || !dn.found) {
      std::cout << fmt::format("yaw {:4.0f}: mesh {} nerf {}\n", yaw, dm.found, dn.found);
      continue;
    }
    for (int k : {lm::kTempleR, lm::kTempleL}) {
      std::string line =
          fmt::format("yaw {:4.0f} lm {:2d} duv ({:5.1f} {:5.1f})", yaw, k,
                      dn.points[k].x() - dm.points[k].x(), dn.points[k].y() - dm.points[k].y());
      auto show = [&](const char* name, ViewSource& s, const Eigen::Vector2d& uv, float th) {
        Ray r = camera_ray(cam, uv);
        auto iv = intervals(s, r, t0, t1, th);
        line += fmt::format(" | {}:", name);
        for (size_t i = 0; i < iv.size() && i < 2; ++i)
          line += fmt::format(" in{} len {:5.1f}", head(r.origin + iv[i].in * r.dir),
                              (iv[i].out - iv[i].in) * mm);
      };
      show("M@m", *mesh, dm.points[k], 10.0f);
      show("N@m", nerf, dm.points[k], thr);
      show("N@n", nerf, dn.points[k], thr);
      for (auto [name, src, uv] : {std::tuple{"O@m", (ViewSource*)&nerf, dm.points[k]},
                                   std::tuple{"O@n", (ViewSource*)&nerf, dn.points[k]}}) {
        Ray r = camera_ray(cam, uv);
        double t = 0;
        if (opacity_depth(*src, r.origin, r.dir, t0, t1, 0.5, &t))
          line += fmt::format(" | {} {}", name, head(r.origin + t * r.dir));
      }
      std::cout << line << "\n";
    }
  }
  return 0;
}
