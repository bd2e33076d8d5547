// The sphere a try-on view frames: the wearer's head from the crown to the chin, placed by a
// placement (its transform gives the head's axes at the nose bridge, its mm_per_unit the scale) and
// sized from the anthropometric head extents of fit/head_box.h. A model's box holds more than the
// head (the neck, hair room, and for captures trained with a room the room around it), so an orbit
// framing the box draws the head small; framing this sphere makes the head fill most of the view.
#pragma once
#include "fit/head_box.h"
#include "fit/placement_json.h"
#include "host/render/render_settings.h"

namespace lorgnette::fit {

// The head's sphere in the scene: centred on the head's middle (half way between crown and chin,
// half a head length behind the glabella) with half the crown-to-chin height as its radius.
// Millimetres per unit come from the placement, else from its transform's scale (a hand-written
// placement). Throws std::invalid_argument when the placement has no usable transform.
render::FramedSphere head_framing(const PlacementFile& placement, const HeadExtents& extents = {});

// The head's forward direction in the scene (the placement's canonical +z), for an orbit's front.
render::Vec3 head_front(const PlacementFile& placement);

}  // namespace lorgnette::fit
