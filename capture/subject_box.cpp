// The subject-box choice for training (see subject_box.h).
#include "capture/subject_box.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <stdexcept>

#include "capture/face_hull.h"
#include "capture/head_volume.h"
#include "capture/skin_colours.h"
#include "capture/subject_framing.h"

namespace lorgnette::capture {
namespace {

std::array<std::array<float, 3>, 2> to_array(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  return {{{float(lo.x()), float(lo.y()), float(lo.z())}, {float(hi.x()), float(hi.y()), float(hi.z())}}};
}

SubjectBoxChoice head_choice(const dataset::Dataset& ds, const fit::HeadBoxOptions& opt) {
  std::vector<fit::PosedPhoto> photos = posed_photos(ds);
  fit::HeadBox box = fit::estimate_head_box(photos, opt);
  SubjectBoxChoice c;
  c.source = BoxSource::Head;
  c.aabb = to_array(box.min, box.max);
  c.zones = nerf::SubjectZones{head_volume(box),      head_clear_keep(box),        head_clear_core(box),
                               head_cut_rim(box),     head_room_body(box),         head_solid_hulls(box),
                               head_solid_core(box),  float(box.head.mm_per_unit), skin_colours(box, photos),
                               head_solid_reach(box), head_neck_base(box)};
  c.why = box.summary();
  std::vector<Camera> cams;
  for (const auto& p : photos) cams.push_back(p.camera);
  FramingReport framing = check_head_framing(box, cams);
  if (framing.every_frame()) c.problem = "the subject cannot be separated from the room: " + framing.advice();
  return c;
}

SubjectBoxChoice cameras_choice(const std::string& why) {
  SubjectBoxChoice c;
  c.source = BoxSource::Cameras;
  c.why = why;
  return c;
}

}  // namespace

const char* to_string(BoxSource s) {
  switch (s) {
    case BoxSource::Auto:
      return "auto";
    case BoxSource::Dataset:
      return "dataset";
    case BoxSource::Masks:
      return "masks";
    case BoxSource::Head:
      return "head";
    case BoxSource::Cameras:
      return "cameras";
  }
  return "?";
}

BoxSource box_source_from_string(const std::string& name) {
  for (BoxSource s :
       {BoxSource::Auto, BoxSource::Dataset, BoxSource::Masks, BoxSource::Head, BoxSource::Cameras})
    if (name == to_string(s)) return s;
  throw std::runtime_error(
      fmt::format("unknown box source '{}': use auto, dataset, masks, head or cameras", name));
}

bool has_alpha_masks(const dataset::Dataset& ds) {
  if (!ds.has_alpha) return false;
  auto train = ds.split(dataset::Split::Train);
  return std::any_of(train.begin(), train.end(),
                     [](const dataset::Frame* f) { return f->image.has_transparency(); });
}

std::vector<fit::PosedPhoto> posed_photos(const dataset::Dataset& ds) {
  std::vector<fit::PosedPhoto> out;
  for (const dataset::Frame* f : ds.split(dataset::Split::Train))
    out.push_back({f->camera, f->image.empty() ? nullptr : &f->image, f->image_path});
  return out;
}

SubjectBoxChoice choose_subject_box(const dataset::Dataset& ds, BoxSource requested, bool masks_allowed,
                                    const fit::HeadBoxOptions& head_options) {
  const bool masks = masks_allowed && has_alpha_masks(ds);
  SubjectBoxChoice c;
  switch (requested) {
    case BoxSource::Dataset:
      if (!ds.aabb)
        throw std::runtime_error("--box dataset: the dataset has no 'aabb' (use --box auto or head)");
      break;
    case BoxSource::Masks:
      if (!masks)
        throw std::runtime_error("--box masks: the training images have no alpha masks" +
                                 std::string(masks_allowed ? "" : " (or --no-masks was given)"));
      c.source = BoxSource::Masks, c.use_masks = true,
      c.why = "the visual hull of the alpha masks (--box masks)";
      return c;
    case BoxSource::Head:
      return head_choice(ds, head_options);
    case BoxSource::Cameras:
      return cameras_choice("the box around the cameras' look-at point (--box cameras)");
    case BoxSource::Auto:
      break;
  }
  if (ds.aabb) {
    c.source = BoxSource::Dataset;
    c.aabb = *ds.aabb;
    c.why = requested == BoxSource::Dataset ? "the dataset's 'aabb' (--box dataset)"
                                            : "the dataset's own subject box 'aabb' (auto: it has one)";
    return c;
  }
  if (masks) {
    c.source = BoxSource::Masks, c.use_masks = true;
    c.why = "the visual hull of the alpha masks (auto: no 'aabb' in the dataset, the images have alpha)";
    return c;
  }
  try {
    SubjectBoxChoice h = head_choice(ds, head_options);
    h.why += " (auto: no 'aabb', no alpha masks, faces found)";
    return h;
  } catch (const std::exception& e) {
    SubjectBoxChoice c =
        cameras_choice(fmt::format("the box around the cameras' look-at point (auto: no 'aabb', no alpha "
                                   "masks, and no head box: {})",
                                   e.what()));
    c.problem = fmt::format(
        "the subject cannot be separated from the room: no face was found in the frames ({}). Film the face "
        "itself: in focus, well lit, unobstructed (no hand, hair or mask over the eyes and nose), filling "
        "about a third of the frame, from the front round to each ear",
        e.what());
    return c;
  }
}

void apply_subject_box(dataset::Dataset& ds, BoxSource requested, bool masks_allowed, nerf::TrainJob& job,
                       const fit::HeadBoxOptions& head_options) {
  SubjectBoxChoice c = choose_subject_box(ds, requested, masks_allowed, head_options);
  spdlog::info("subject box: {}", c.why);
  if (c.source != BoxSource::Head && head_options.extents.hair_mm != fit::HeadExtents{}.hair_mm)
    spdlog::warn(
        "the hair allowance (--hair) sizes only the landmark head box, and this box is {}: it is "
        "not used (--box head forces the head box)",
        to_string(c.source));
  if (!c.problem.empty()) spdlog::warn("{}", c.problem);
  job.subject_problem = c.problem;
  ds.aabb.reset();
  job.sizing.use_masks = c.use_masks;
  if (c.aabb) {
    nerf::Aabb box;
    box.min = (*c.aabb)[0];
    box.max = (*c.aabb)[1];
    if (!box.valid())
      throw std::runtime_error(
          "the chosen subject box is empty: give a box yourself or use the cameras' box");
    job.sizing.aabb = box;
    job.subject = c.zones;
  }
}

}  // namespace lorgnette::capture
