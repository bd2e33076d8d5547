// Parametric glasses frames from the three numbers printed on every frame (lens width, bridge,
// temple length, in mm) and a shape (round, rect, aviator, cateye). The mesh is in the canonical
// frame with the origin at g_c; every part (two rims, bridge, two temples, two lenses) is a closed,
// watertight surface (swept rectangular sections with capped ends, lenses as capped slabs), and the
// reference points are exact by construction under the definitions of refpoints.h:
// g_c = underside of the bridge at x = 0 on the back face of the front; g_l/g_r = temple underside
// where the temple starts to bend down behind the ear (temple_length - 35 mm behind the hinge).
#pragma once
#include <Eigen/Core>
#include <string>

#include "mesh/refpoints.h"
#include "mesh/trimesh.h"

namespace lorgnette::mesh {

enum class FrameShape { kRound, kRect, kAviator, kCateye };

FrameShape parse_frame_shape(const std::string& name);  // throws with the valid names

struct FrameParams {
  float lens_width = 52.0f;      // mm, horizontal size of one lens
  float bridge = 18.0f;          // mm, gap between the lenses
  float temple_length = 140.0f;  // mm, hinge (the rims' back face) to the tip's end along the
                                 // temple's centre line, the bend included (as frame_metrics.h measures)
  FrameShape shape = FrameShape::kRect;
  float rim = 3.0f;  // mm, radial width of the rim around each lens
  float lens_height =
      0.0f;  // mm; 0 = from the shape (round 0.9, rect 0.72, aviator 0.9, cateye 0.78 x width)
  Eigen::Vector3f color{0.02f, 0.02f, 0.025f};     // frame base colour, linear RGB
  Eigen::Vector3f lens_tint{0.85f, 0.87f, 0.88f};  // transmitted colour of the lenses
  float metallic = 0.0f, roughness = 0.35f;
  int segments = 96;  // outline resolution per lens
};

struct ParametricFrame {
  TriMesh mesh;   // canonical mm, origin at g_c
  RefPoints ref;  // exact
};

// Throws OutOfRange (host/util/bounds.h) for an implausible size or material number, naming its
// range; std::runtime_error for a bad outline resolution.
ParametricFrame make_parametric_frame(const FrameParams& params);

// Parses "#rrggbb" (sRGB) or "r,g,b" (linear, 0..1) or a few names (black, tortoise, gold, silver,
// red, blue, clear, grey, green, brown) into linear RGB.
Eigen::Vector3f parse_color(const std::string& text);

}  // namespace lorgnette::mesh
