// Helpers of detect_views (declared in fit/fit.h with triangulate_landmarks): rendering a framed view
// in part. Exposed for tests and benchmarks.
#pragma once
#include "common/camera_types.h"
#include "fit/view_source.h"

namespace lorgnette::fit {

// The view of `cam` where only the centred `keep` x `keep` fraction of the image is rendered (a
// sub-camera with shifted principal point: the same rays as the full view there) and the rest is
// white (3 channels; a 4th, alpha, is 0 there). keep <= 0 or >= 1 renders the whole view.
// Throws for cameras with lens distortion (the crop would not be the same rays).
Image render_cropped(ViewSource& source, const Camera& cam, double keep);

}  // namespace lorgnette::fit
