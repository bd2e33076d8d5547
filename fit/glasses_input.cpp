// Glasses reference points and frame samples from the mesh module (see glasses_input.h).
#include "fit/glasses_input.h"

#include "mesh/frame_samples.h"
#include "mesh/glasses.h"
#include "mesh/refpoints.h"
#include "mesh/temple_bend.h"

namespace lorgnette::fit {

GlassesInput load_glasses_input(const std::string& path, int samples, unsigned seed) {
  mesh::GlassesOptions opt;
  opt.load.load_textures = false;
  mesh::Glasses g = mesh::load_glasses(path, opt);
  GlassesInput in;
  in.path = path;
  in.ref.g_c = g.ref.g_c.cast<double>();
  in.ref.g_l = g.ref.g_l.cast<double>();
  in.ref.g_r = g.ref.g_r.cast<double>();
  const mesh::FrameMetrics& m = g.metrics;
  in.sizes = {m.total_width_mm,   m.lens_width_mm, m.lens_height_mm,
              m.lens_centre_y_mm, m.bridge_mm,     m.temple_length_mm};
  if (const auto& h = g.metrics.hinges) {  // detected once, by the load's measurements
    in.ref.has_hinges = true;
    in.ref.hinge_l = h->left;
    in.ref.hinge_r = h->right;
  } else {
    in.notes.push_back(g.metrics.no_hinges + ": the temples stay rigid in the fit");
  }
  for (const auto& p : mesh::sample_frame_surface(g.mesh, samples, seed))
    in.frame_points.push_back(p.cast<double>());
  in.notes.insert(in.notes.begin(), g.notes.begin(), g.notes.end());
  return in;
}

}  // namespace lorgnette::fit
