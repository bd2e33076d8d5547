// Placing the frame (paper Sec. 3.1, Eq. 4-5): scale (the paper's stretch from temple distances, or
// true size from the estimated millimetres per scene unit), rotation by Kabsch with the reflection
// check, translation putting the bridge point g_c on the nose point f_c. Then a contact refinement
// the paper lacks: slide the frame along d_fwd so that its front rests on the skin with nothing
// inside the head, judged by density queries, and measure what still penetrates.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "fit/head_probe.h"

namespace lorgnette::fit {

// Reference points annotated on the glasses, canonical frame (mm; x = wearer's left, y up, z forward).
struct GlassesRefPoints {
  Eigen::Vector3d g_c{0, 0, 0};                         // nose bridge (the canonical origin)
  Eigen::Vector3d g_l{70, 0, -100}, g_r{-70, 0, -100};  // temple tips where they rest on the ears
  // Where the temples join the front (mesh/temple_bend.h), for the temple spread; without them the
  // temples stay rigid.
  bool has_hinges = false;
  Eigen::Vector3d hinge_l{0, 0, 0}, hinge_r{0, 0, 0};
};

// R minimising sum w_i |R a_i - b_i|^2 over proper rotations (det R = +1: the SVD's smallest
// direction is flipped when the optimum would be a reflection). Works with two pairs (rank 2).
// Throws when the pairs do not determine a rotation (fewer than 2 non-parallel vectors).
Eigen::Matrix3d kabsch(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                       const std::vector<double>& weights = {});

// kAuto: true size when the scale is metric (a card or the irises), else stretch (scale_chain.h
// resolves it once the scale's source is known; place_glasses needs it resolved).
enum class ScalePolicy { kStretch, kTrueSize, kAuto };
const char* scale_policy_name(ScalePolicy p);
ScalePolicy parse_scale_policy(const std::string& s);  // "stretch" | "true-size" | "auto"; throws otherwise

struct Placement {
  Eigen::Matrix4d transform = Eigen::Matrix4d::Identity();  // canonical mm -> scene
  double scale = 1.0;                                       // scene units per mm
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
};

// Eq. 4-5 with a uniform scale: scene = scale * R * g + t, t = f_c - scale * R * g_c.
// stretch: scale = |t_l - t_r| / |g_l - g_r|; true-size: scale = 1 / mm_per_unit; auto: throws.
struct PlaceInputs {
  Eigen::Vector3d f_c, f_l, f_r, t_l, t_r;
  double mm_per_unit = 0.0;
};
Placement place_glasses(const GlassesRefPoints& g, const PlaceInputs& in, ScalePolicy policy);

struct ContactResult {
  double shift_mm = 0.0;  // applied along d_fwd (+ = away from the face)
  double rise_mm = 0.0;   // applied along the head's up: the frame rode up the nose (nose_rest.h)
  double penetration_before_mm = 0.0, penetration_mm = 0.0;  // deepest front/arm point inside the head
  double tip_penetration_mm = 0.0;    // deepest temple-tip point (behind the ear rests)
  double front_penetration_mm = 0.0;  // deepest point of the front (rims, bridge, pads) alone
  int points_inside = 0;              // front/arm points inside after refinement
  bool refined = false;
};

// Penetration (mm) of each sample point: 0 when it is outside; else k * step_mm for the first of the
// probes k = 1..max_probes, taken outwards (horizontally away from the head's vertical axis through
// the probe's axis point), that is outside; (max_probes + 1) * step_mm when every probe is still
// inside. One density query per probe step for all points, so callers batch (the temple search: 8
// angles).
std::vector<double> penetration_depths_mm(const HeadProbe& head,
                                          const std::vector<Eigen::Vector3d>& scene_points, int max_probes);

// Deepest penetration (mm) of the frame's sample points (the above, probing up to 2 max_shift_mm).
double penetration_depth_mm(const HeadProbe& head, const std::vector<Eigen::Vector3d>& scene_points,
                            int* inside_count = nullptr);

// Fills penetration_mm (front and arms), points_inside, front_penetration_mm and tip_penetration_mm
// of `res` for the frame as placed. The probe's frame points (canonical mm) decide which group a
// sample is in; `deformed` (same size, or empty = undeformed) are where the samples actually are (the
// temple spread, mesh/temple_bend.h).
void measure_contact(ContactResult& res, const Placement& placement, const HeadProbe& head,
                     const std::vector<Eigen::Vector3d>& deformed = {});

// Raises `placement` along the head's up to where its front rests on its bridge (nose_rest.h), then
// slides it along d_fwd: outwards until the front clears the head, or inwards until it first touches
// (the bridge or the pads resting on the skin).
ContactResult refine_contact(Placement& placement, const HeadProbe& head, const Eigen::Vector3d& d_fwd);

}  // namespace lorgnette::fit
