// Finding the front of an unknown head and framing the face: a coarse yaw sweep (or the capture's
// prior front) picks the view where dlib sees the most frontal face, then the face box and a density
// ray cast through its centre give the distance and orbit centre so the face fills a set share of
// the image. The result is the Orbit that the cap of views is planned on.
#pragma once
#include <vector>

#include "fit/landmarks_dlib.h"
#include "fit/view_planning.h"
#include "fit/view_source.h"

namespace lorgnette::fit {

struct FrontSearchOptions {
  int width = 384, height = 384;
  double fov_y_deg = 25.0;
  int sweep_views = 8;
  double face_fraction = 0.5;  // face box width / image width after framing
  // Then the yaw is refined by a secant search on the signed asymmetry (about 0.025 per degree near
  // the front) until it is below `asymmetry_tolerance`, at most `refine_views` more renders. Without
  // it a capture whose first camera is 20 deg off the face planned the cap 20 deg off, and the fit
  // had to re-plan and render every view a second time.
  int refine_views = 3;
  double asymmetry_tolerance = 0.06;
  int refine_size = 256;  // refinement renders (px; 0 = the sweep's size)
};

struct FrontSearchResult {
  Orbit orbit;                     // framed on the face, yaw 0 = the most frontal view found
  std::vector<double> tried_yaws;  // relative to the initial front, sweep then refinement
  std::vector<bool> found;         // per tried yaw
  double surface_distance = 0.0;   // camera to face surface along the box centre (scene units)
};

// Left/right asymmetry of a 68-point face in the image: 0 frontal, +-1 full profile.
double face_asymmetry(const FaceDetection& d);

// `density_threshold`: the skin, for the ray cast that frames the face. Throws std::runtime_error
// naming the yaws tried when no view shows a face.
FrontSearchResult find_front(ViewSource& source, const LandmarkDetector& detector,
                             const FrontSearchOptions& opt, float density_threshold);

}  // namespace lorgnette::fit
