// Where a ray meets the head in a ViewSource's density: the first threshold crossing (the skin for
// the contact, framing and snapping) and the depth at which the ray's accumulated opacity reaches a
// level (the volume-rendering surface, which is what a render shows at that pixel). On a mesh source
// (a step from 0 to 1e4) both are the mesh's first hit; on a NeRF the first crossing stops at the
// faint haze and thin floaters in front of the skin, the opacity depth does not.
#pragma once
#include <Eigen/Core>

#include "fit/view_source.h"

namespace lorgnette::fit {

// First point along the ray where density exceeds `threshold`, searched in [t0, t1]; returns false
// when none.
bool first_surface_hit(ViewSource& source, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                       double t0, double t1, float threshold, double* t_hit);

// First depth in [t0, t1] at which the opacity 1 - exp(-integral of density) reaches `level` (0, 1);
// `dir` must be unit length (density is per scene unit). Returns false when the ray stays clearer.
bool opacity_depth(ViewSource& source, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t0,
                   double t1, double level, double* t_hit);

}  // namespace lorgnette::fit
