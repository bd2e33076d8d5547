// The fit's views and their landmarks: rendering a set of views (optionally only the centred part the
// face lies in), detecting the 68 landmarks in each (on a worker thread while the next view renders),
// and triangulating them from the views with a face. The stages of fit_glasses (fit.h) and the surface
// casts (surface_landmarks.h, temple_depth.h, head_box.h) read the views through ViewRecord.
#pragma once
#include <vector>

#include "common/camera_types.h"
#include "fit/landmarks_dlib.h"
#include "fit/triangulate.h"
#include "fit/view_source.h"

namespace lorgnette::fit {

struct ViewRecord {
  Camera camera{};
  double yaw_deg = 0.0, pitch_deg = 0.0;
  FaceDetection detection;
  Image image;  // the rendered view, kept only when asked (ViewDetectOptions::keep_images)
};

struct ViewDetectOptions {
  DetectorOptions detector;  // the crop, the overlap and the HOG hint (landmarks_dlib.h)
  double face_fraction =
      0.0;  // the face's expected width / the view's (the front search's framing); 0: unknown
  bool keep_images = false;  // keep each rendered view in its record (debug pictures)
};

// Renders and detects every view of `cameras`, in order.
std::vector<ViewRecord> detect_views(ViewSource& source, const LandmarkDetector& detector,
                                     const std::vector<Camera>& cameras, const ViewDetectOptions& options);

// Triangulates the 68 landmarks from the views with a face; each point's inliers and residuals are
// indexed by view (`views`), as the surface casts' are.
std::vector<TriangulatedPoint> triangulate_landmarks(const std::vector<ViewRecord>& views,
                                                     const TriangulateOptions& options);

// The view of `cam` where only the centred `keep` x `keep` fraction of the image is rendered (a
// sub-camera with shifted principal point: the same rays as the full view there) and the rest is
// white (3 channels; a 4th, alpha, is 0 there). keep <= 0 or >= 1 renders the whole view.
// Throws for cameras with lens distortion (the crop would not be the same rays).
Image render_cropped(ViewSource& source, const Camera& cam, double keep);

}  // namespace lorgnette::fit
