// Whether a capture framed its subject with room around it: the head (an average head's ellipsoid in
// the landmark head box, fit/head_box.h, from the crown down to about the mouth: the neck and
// shoulders may leave the frame) projected into every posed frame. When the head runs off the left,
// right or top edge of every frame, the room is never seen beside the head, so the subject cannot be
// separated from it (and the ears and hair are cut off): `train` says what to film differently and
// records the problem in the model, so the fit cannot pass it as good.
#pragma once
#include <string>
#include <vector>

#include "fit/head_box.h"

namespace lorgnette::capture {

struct FramingReport {
  size_t frames = 0;    // frames checked
  size_t touching = 0;  // frames where the head crosses the left, right or top edge (or the camera)
  bool every_frame() const { return frames > 0 && touching == frames; }
  // What to film differently when every frame cuts the head; "" otherwise.
  std::string advice() const;
};

FramingReport check_head_framing(const fit::HeadBox& box, const std::vector<Camera>& cameras);

}  // namespace lorgnette::capture
