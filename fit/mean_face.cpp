// The mean face from a file or from the built-in table (see mean_face.h).
#include "fit/mean_face.h"

#include <fmt/format.h>

#include <fstream>
#include <stdexcept>
#include <vector>

#include "fit/landmark_ids.h"

namespace lorgnette::fit {

Face68 mean_face_from_columns(const double* x, const double* y, const double* z) {
  Face68 face(lm::kCount);
  // File frame: x image-right (= wearer's left), y down, z into the face -> flip y and z.
  for (int i = 0; i < lm::kCount; ++i) face[i] = Eigen::Vector3d(x[i], -y[i], -z[i]);
  return face;
}

Face68 load_mean_face(const std::string& path) {
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error(
        fmt::format("cannot open the mean face '{}': give a readable file of 204 numbers, or "
                    "leave the option out to use the built-in mean face",
                    path));
  std::vector<double> v;
  double x;
  while (in >> x) v.push_back(x);
  if (v.size() != 3 * lm::kCount)
    throw std::runtime_error(
        fmt::format("mean face '{}': expected 204 numbers (68 x, y, z), found {}", path, v.size()));
  return mean_face_from_columns(v.data(), v.data() + lm::kCount, v.data() + 2 * lm::kCount);
}

Face68 mean_face_or_builtin(const std::string& path) {
  return path.empty() ? builtin_mean_face() : load_mean_face(path);
}

Eigen::Vector3d eye_corners_centroid(const Face68& face) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int k : {lm::kEyeOuterR, lm::kEyeInnerR, lm::kEyeInnerL, lm::kEyeOuterL}) c += 0.25 * face[size_t(k)];
  return c;
}

Eigen::Vector3d face_anchor(const Face68& face) {
  Eigen::Vector3d a = eye_corners_centroid(face);
  a.z() = 0.5 * (face[size_t(lm::kEyeInnerR)].z() + face[size_t(lm::kEyeInnerL)].z());
  return a;
}

}  // namespace lorgnette::fit
