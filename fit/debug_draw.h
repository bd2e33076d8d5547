// `--debug DIR` output of the fit: every view with the detected landmarks (green), the triangulated
// 3D landmarks reprojected (red; the placement's key points larger), the face box, and a line of text
// with the view's yaw/pitch and RMS residual; written as view_NN.png plus views.txt.
#pragma once
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "fit/detect_views.h"
#include "host/util/image_io.h"

namespace lorgnette::fit {

// A linear-RGB image as an 8-bit sRGB BGR matrix for OpenCV's drawing and writing.
cv::Mat to_bgr8(const Image& img);

// Creates `dir` when needed; throws std::runtime_error when it cannot write there.
// `views` are the fit's (images kept), `points` its 68 landmarks.
void write_debug_views(const std::string& dir, const std::vector<ViewRecord>& views,
                       const std::vector<TriangulatedPoint>& points);

}  // namespace lorgnette::fit
