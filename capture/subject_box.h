// Which box a NeRF of a dataset trains in ("subject box"): the dataset's own "aabb" (written by
// `lorgnette capture`), the visual hull of its alpha masks, the head box from landmarks triangulated
// on its photos (fit/head_box.h), or the automatic box around the cameras' look-at point. `auto`
// takes the first that applies in that order and says why; naming one forces it (with a clear
// error when it does not apply). Used by `lorgnette train --box`.
#pragma once
#include <array>
#include <optional>
#include <string>

#include "fit/head_box.h"
#include "host/dataset/dataset.h"
#include "host/nerf/subject_volume.h"
#include "host/nerf/train_job.h"
#include "host/util/bounds.h"

namespace lorgnette::capture {

enum class BoxSource { Auto, Dataset, Masks, Head, Cameras };

// "auto", "dataset", "masks", "head", "cameras"; box_source_from_string throws listing the names.
const char* to_string(BoxSource s);
BoxSource box_source_from_string(const std::string& name);

struct SubjectBoxChoice {
  BoxSource source = BoxSource::Cameras;  // never Auto
  // Dataset and Head: the box (scene units, [min, max]); Masks and Cameras: empty (the model
  // sizing carves the hull or builds the camera box itself).
  std::optional<std::array<std::array<float, 3>, 2>> aabb;
  bool use_masks = false;  // let the sizing carve the alpha-mask hull
  // Head: the head's volume in the box and its clearing zones (capture/head_volume.h: the neck kept,
  // the bare head as the core). The box is the oriented head box's axis-aligned bounds, so it holds
  // corners that are not head; training with a room model masks them out of the subject's occupancy.
  std::optional<nerf::SubjectZones> zones;
  std::string why;  // one sentence for the log
  // Why the subject cannot be separated from the room, with what to film differently ("" when it
  // can): auto found no face in a mask-less dataset, or the head runs off every frame
  // (subject_framing.h). Training goes on, but the model records it (ModelMetadata::subject_problem).
  std::string problem;
};

// True when any training image has a transparent pixel (Image::has_transparency, the sizing's test).
bool has_alpha_masks(const dataset::Dataset& ds);

// The most hair (or hat) above and behind the skull that `train --hair` and Python's
// train(hair_mm=) accept for the head box (fit::HeadExtents::hair_mm), in millimetres.
inline constexpr double kMaxHairMm = bounds::kHairMm.hi;

// Chooses the box for training on `ds`'s training frames. `masks_allowed` = false ignores alpha
// (train --no-masks). Throws when a forced source does not apply (no aabb, no masks, no faces).
SubjectBoxChoice choose_subject_box(const dataset::Dataset& ds, BoxSource requested,
                                    bool masks_allowed = true, const fit::HeadBoxOptions& head_options = {});

// Chooses the box (choose_subject_box) and sets the training job up for it, as `lorgnette train
// --box` and Python's train() do: an explicit box (with the head's volume in it, for the head box),
// or the dataset's aabb removed so the sizing carves the mask hull or builds the camera box. Logs
// the choice (and the problem, as a warning, into job.subject_problem); throws when the box is
// empty.
void apply_subject_box(dataset::Dataset& ds, BoxSource requested, bool masks_allowed, nerf::TrainJob& job,
                       const fit::HeadBoxOptions& head_options = {});

// The dataset's training frames as posed photos for fit::estimate_head_box (pointers into `ds`).
std::vector<fit::PosedPhoto> posed_photos(const dataset::Dataset& ds);

}  // namespace lorgnette::capture
