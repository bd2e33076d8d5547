// `--debug DIR` output of the fit: every view with the detected landmarks (green), the triangulated
// 3D landmarks reprojected (red; the placement's key points larger), the face box, and a line of text
// with the view's yaw/pitch and RMS residual; written as view_NN.png plus views.txt.
#pragma once
#include <string>

namespace lorgnette::fit {

struct FitResult;

// Creates `dir` when needed; throws std::runtime_error when it cannot write there.
void write_debug_views(const std::string& dir, const FitResult& result);

}  // namespace lorgnette::fit
