// The 68-point mean face that the head frame aligns (head_frame.h): built into the binary
// (mean_face_68.cpp, with its source and licence), or read from a file the user names. The fit and
// the head box use the built-in one unless told otherwise, so they need no data file at run time.
#pragma once
#include <string>

#include "fit/head_frame.h"

namespace lorgnette::fit {

// The built-in mean face, converted to the head frame once.
const Face68& builtin_mean_face();

// The mean face from three columns in the file's frame (mm; x image-right, y down, z away from the
// viewer), converted to the head frame (x wearer's left, y up, z forward).
Face68 mean_face_from_columns(const double* x, const double* y, const double* z);

// Reads a mean face file (204 numbers: all x, all y, all z, in the frame above). Throws naming the
// file when it cannot be read or is malformed.
Face68 load_mean_face(const std::string& path);

// `path` empty: the built-in mean face; otherwise the file (load_mean_face).
Face68 mean_face_or_builtin(const std::string& path);

// The centroid of a face's four eye corners (dlib 36, 39, 42, 45).
Eigen::Vector3d eye_corners_centroid(const Face68& face);

// The head box's anchor on a face (head_box.h): the eye corners' centroid moved to the inner corners'
// depth, a point between the eyes that a frontal and a turned photo both see well.
Eigen::Vector3d face_anchor(const Face68& face);

}  // namespace lorgnette::fit
