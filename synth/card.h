// The ID-1 card (ISO/IEC 7810: 85.60 x 53.98 mm) a shopper holds flat against the forehead so a
// capture knows millimetres, and the finger that partly covers it: the ground truth of the card
// scale (capture/card_scale.h). The card is a flat textured quad resting on the forehead (its plane
// fitted to the forehead under it and moved forward until no part of the head pokes through) with a
// printed pattern of strong edges on a pale body, as bank and loyalty cards have. The finger is a
// capsule lying on the card's face across one of its edges or corners.
#pragma once
#include <Eigen/Core>
#include <array>

#include "mesh/trimesh.h"

namespace lorgnette::synth {

constexpr float kCardWidthMm = 85.60f, kCardHeightMm = 53.98f;

struct HeldCard {
  // Millimetres in the head frame (x to the wearer's left, y up, z out of the face): top-left,
  // top-right, bottom-right, bottom-left as a camera in front of the face sees them.
  std::array<Eigen::Vector3f, 4> corners;
  Eigen::Vector3f normal{0, 0, 1};  // out of the card's printed face, towards the cameras
  Eigen::Vector3f centre() const { return 0.25f * (corners[0] + corners[1] + corners[2] + corners[3]); }
};

// The card on the forehead of `head` (a mesh in millimetres, head frame), its lower edge
// `above_eyes_mm` above eye level. Throws std::runtime_error when the head has no forehead there.
HeldCard card_on_forehead(const mesh::TriMesh& head, float above_eyes_mm);

// Points of a head's midline profile found from its shape alone (millimetres, +y up, facing +z), for
// a head whose landmarks are not known (a scan): the nose tip (the most forward point of the mesh
// seen from the front), the sellion (the deepest point of the nose's bridge, at most 80 mm above
// the tip) and the glabella (the brow's most forward point, at most 35 mm above the sellion).
struct MidlineProfile {
  Eigen::Vector3f nose_tip, sellion, glabella;
};
// `to_mm` maps the mesh's coordinates to that frame. Throws std::runtime_error when the profile
// above the most forward point is not a nose's bridge and a brow (not a face seen from +z).
MidlineProfile midline_profile(const mesh::TriMesh& head, const Eigen::Matrix4f& to_mm);

// The card on the forehead of a head whose landmarks are not known (a scan; `to_mm` as above),
// resting on it as card_on_forehead does, centred on the nose tip's x with its lower edge
// `above_glabella_mm` above the glabella. Millimetres in the to_mm frame.
HeldCard card_on_scanned_forehead(const mesh::TriMesh& head, const Eigen::Matrix4f& to_mm,
                                  float above_glabella_mm);

// The card as a textured two-triangle mesh (part "card"), millimetres, head frame.
mesh::TriMesh card_mesh(const HeldCard& card);

// Where the finger lies: across the lower long edge, or over the lower right corner.
enum class FingerPlacement { LowerEdge, LowerRightCorner };

// A finger-sized capsule (16 mm thick, part "finger") on the card's face, millimetres, head frame.
mesh::TriMesh finger_mesh(const HeldCard& card, FingerPlacement where);

}  // namespace lorgnette::synth
