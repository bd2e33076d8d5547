// The head's framing in the posed frames (see subject_framing.h).
#include "capture/subject_framing.h"

#include <fmt/format.h>

#include <cmath>

namespace lorgnette::capture {
namespace {

// The box holds a 99th-percentile head plus margins for ears, hair and neck (fit::HeadExtents: 105 x
// 170 x 150 mm half sizes); three quarters of it is an average adult head (ANSUR II breadth 157 mm,
// length 198 mm; vertex to menton ~225 mm), so a tightly but fully framed head does not count.
constexpr double kHeadOfBox = 0.75;

// Points on the head's ellipsoid from the crown down to latitude -30 deg (about the mouth: the box's
// centre is near eye level and its lower half reaches the neck), every 10 deg of latitude and 15 of
// longitude.
std::vector<Eigen::Vector3d> head_points(const fit::HeadBox& box) {
  std::vector<Eigen::Vector3d> pts;
  const double k = 3.14159265358979323846 / 180.0;
  const Eigen::Vector3d h = kHeadOfBox * box.half_extent;
  for (int lat = -30; lat <= 90; lat += 10)
    for (int lon = 0; lon < 360; lon += 15) {
      Eigen::Vector3d local(h.x() * std::cos(lat * k) * std::cos(lon * k), h.y() * std::sin(lat * k),
                            h.z() * std::cos(lat * k) * std::sin(lon * k));
      pts.push_back(box.center + box.axes * local);
    }
  return pts;
}

bool crosses_edge(const Camera& cam, const std::vector<Eigen::Vector3d>& pts) {
  for (const auto& p : pts) {
    float u, v;
    float depth = camera_project(&cam, lgn_vec3(float(p.x()), float(p.y()), float(p.z())), &u, &v);
    if (!(depth > 0.0f)) return true;  // the camera is inside the head's extent
    if (!(u >= 0.0f && u <= float(cam.width) && v >= 0.0f)) return true;  // left, right or top edge
  }
  return false;
}

}  // namespace

std::string FramingReport::advice() const {
  if (!every_frame()) return "";
  return fmt::format(
      "the head runs off the edge of the picture in all {} frames, so the room is never seen beside it and "
      "the subject cannot be separated from it (and its hair and ears are cut off): film from further "
      "away, about arm's length (50-70 cm), with the whole head, hair and ears inside the frame and some "
      "room visible around it",
      frames);
}

FramingReport check_head_framing(const fit::HeadBox& box, const std::vector<Camera>& cameras) {
  FramingReport r;
  // The head, not the hair declared beyond the standard (train --hair: a hat or a bun may leave the
  // frame, and its larger box would put the average head's sides and top beyond a well framed one's).
  fit::HeadBox head = box;
  if (fit::declared_hair_mm(box.extents) > 0.0) {
    fit::HeadExtents standard = box.extents;
    standard.hair_mm -= fit::declared_hair_mm(standard);
    head = fit::head_box_from_frame(box.head, box.anchor, standard);
  }
  std::vector<Eigen::Vector3d> pts = head_points(head);
  for (const Camera& cam : cameras) {
    ++r.frames;
    r.touching += crosses_edge(cam, pts);
  }
  return r;
}

}  // namespace lorgnette::capture
