// Silhouette landmarks placed on the head's surface instead of triangulated. dlib's jaw contour
// (0-16, which holds the temple points 0 and 16) follows the silhouette, so the same index marks
// different 3D points in different views and its rays do not meet: triangulating them put the
// temples ~25 mm too far forward on the Lee Perry-Smith scan. Here each such landmark is the
// component-wise median of its rays' surface points (the ground-truth rule, with the view
// source's own density instead of the mesh), taken only from the views that turn its side of the
// face towards the camera. In a view that turns that side away, the point lies on the silhouette:
// its ray grazes the skin, and a lateral shift of a pixel or a slightly softer surface moves the hit
// by centimetres along the ray (and onto the ear or the cheek behind). From the near side the ray
// meets the skin at an angle and the hit is stable (docs/fit.md, "The temples from the near side").
#pragma once
#include <Eigen/Core>
#include <vector>

#include "fit/landmarks_dlib.h"
#include "fit/triangulate.h"
#include "fit/view_planning.h"
#include "fit/view_source.h"

namespace lorgnette::fit {

struct ViewRecord;  // detect_views.h

// Per-axis median of 3D points (robust centre of a landmark's surface hits); throws on none.
Eigen::Vector3d component_median(std::vector<Eigen::Vector3d> points);

struct SurfaceCastOptions {
  int first = 0, last = 16;       // landmark index range (the jaw contour)
  double max_yaw_deg = 25.0;      // only views this close to the front
  double side_tolerance = 0.025;  // see contour_side_visible
  // The surface point of a ray: where its opacity reaches this level (0, 1), as a render shows it;
  // 0 = the first density crossing of the skin's density (stops at a NeRF's haze and floaters).
  double opacity = 0.5;
  double near = 0.5, far = 1.3;  // search range along the ray, as fractions of the orbit distance
};

// Whether a detection shows jaw-contour landmark `k`'s side of the face turned towards the camera:
// 0-7 are the subject's right, 9-16 the left (by face_asymmetry, the image half-widths), with
// `tolerance` of asymmetry (0.025 is about 1 deg of yaw) so that a frontal view serves both sides.
// The chin (8) and landmarks off the contour are visible in every view.
bool contour_side_visible(int k, const FaceDetection& detection, double tolerance);

// Replaces points[first..last] with surface casts where at least one view hits; others unchanged. A
// landmark that no view shows from its side (a cap far off the face's front) uses all views.
// `density_threshold`: the skin (used with opacity 0).
void cast_surface_landmarks(ViewSource& source, const std::vector<ViewRecord>& views, const Orbit& orbit,
                            const SurfaceCastOptions& options, float density_threshold,
                            std::vector<TriangulatedPoint>& points);

// Moves each triangulated landmark (outside the cast range) onto the skin: along the mean direction
// of its inlier rays, to the first density hit within +-`reach` scene units of the triangulated
// point. Landmarks lie on the skin, while least squares over rays that dlib places slightly
// inconsistently across views can end a few mm in front of or behind it (the depth is the poorly
// constrained direction). Returns how many moved; the move is added to the point's sigma.
// `opacity` > 0: to the depth where the opacity from the search's start reaches it instead of the
// first density hit (ray_surface.h), unless the start already lies in the skin.
// `nearest`: to the nearest of the first hits along five directions instead: the mean ray, the two
// inlier rays most apart, and both ways square to the mean ray in their plane. Where the skin is
// steep to the rays (the outer eye corners, where the face turns to its sides) a point a little beside
// the skin lies a little inside it, and the mean ray alone carries it to the face's front, several mm
// too far forward; the nearest skin is the smallest correction.
int snap_to_surface(ViewSource& source, const std::vector<ViewRecord>& views, double reach,
                    float density_threshold, std::vector<TriangulatedPoint>& points, int skip_first = 0,
                    int skip_last = 16, double opacity = 0.0, bool nearest = false);

}  // namespace lorgnette::fit
