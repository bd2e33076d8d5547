// The ear rests found on the head's density: where a temple arm lowered onto the side of the head
// comes to rest on the ear's root, the crease between the skull and the top of the ear (the
// otobasion superius; synth's `ear_rest_l/r`). Eq. 2-3 estimate the ear from the temple landmark,
// the eye height and half the eye-corner distance back. With dlib's temples (0 / 16, already at the
// ear's root) that lands 21-35 mm behind the ear and 10-12 mm under it on the procedural heads
// (docs/bench/real-captures.md, "Eq. 3 with dlib temples").
//
// The search: a field of vertical rays cast down (along -d_up) beside the head, behind the temple.
// Along d_eye at one depth, the heights where the rays meet the head fall steeply down the skull's
// side, then turn flatter onto the ear's top (which stands out from the head): the crease is where
// the slope turns most, by at least `min_bend_deg`. Across depths the creases trace the ear's root,
// and the rest is the top of the highest such line that the caller's hair veto accepts (the arm
// rests on the top of the root), a fixed distance behind the line's front end (rest_behind_front_mm). Where
// hair covers the ear, the capture never saw it, or the window holds no crease, the side is not found; the
// caller mirrors the other side's rest or keeps Eq. 2-3 (apply_ear_roots).
#pragma once
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "fit/ears.h"
#include "fit/head_probe.h"

namespace lorgnette::fit {

struct EarRootOptions {
  bool enabled = true;
  // The window, in mm from the temple landmark: along d_fwd (negative = behind it), outwards along
  // the side's d_eye, and along d_up from the outer eye corners' height.
  // (The rests lie 7-33 mm behind dlib's temples on the procedural, scan and demo heads, meshes and
  // NeRFs; dlib's temple lies at the ear's front, and a line of creases in front of it was the edge
  // of hair over the temple: docs/bench/real-captures.md, "the fit's ears where the density search
  // falls short".)
  double back_mm = 35.0, front_mm = 0.0;
  double inward_mm = 12.0, outward_mm = 30.0;
  double above_mm = 50.0, below_mm = 30.0;
  double depth_step_mm = 2.0, lateral_step_mm = 1.0, ray_step_mm = 0.5;
  // A ray meets the head where its opacity from above reaches this level (ray_surface.h). A NeRF's
  // ear top is soft (the capture sees it only at grazing angles): from the ground truth's own frame,
  // the rays met the procedural heads' NeRF ears 1.3-3.1 mm under the exact mesh's at 0.5, and their
  // rests sat 1.7 mm low on average over 38 NeRFs. At 0.25 the rests lie within 4 mm of the mesh's on
  // 71 of 76 ears (0.5: 66; 0.35: 69; 0.3: 68; 0.2: 68; 0.1: 62, where the scans' lines run on into
  // the NeRF's fill behind the ear). Tried on 27 Nov with the rests at the middles of the lines and
  // not kept then, since the longer lines moved the scans' middles back; the rest now follows the
  // line's front (docs/bench/real-captures.md, "the ear's soft top").
  double opacity = 0.25;
  // The crease: where the heights' slope along d_eye turns flatter, from the skull's side onto the
  // ear's top, by at least this angle, the slopes taken over `bend_span_mm` either side.
  double min_bend_deg = 20.0, bend_span_mm = 3.0;
  // (Not bounded above: a skull side falls onto an ear's top at 26-32 deg on the procedural heads,
  // but where the skull bulges over the ear (the scan) the rays drop off it onto the ear, ~90 deg.)
  // ... from a skull side that falls at least this steeply (deg; a NeRF's hair and the inside of the
  // head make bends too, on flatter ground) ...
  double max_inner_slope_deg = -45.0;
  // ... onto an ear's top, not off an edge nor against a wall: its slope outwards (deg, + = rising)
  // within this range.
  double outer_slope_deg[2] = {-60.0, 30.0};
  // ... at a height above the outer eye corners within this band (mm): the procedural heads' rests
  // lie 11-16 mm above them, the scan's 0-5, the demo head's 1-3.
  double lowest_mm = -5.0, highest_mm = 30.0;
  // Creases at neighbouring depths belong to one ear's root only when they lie this close (mm, along
  // d_eye and d_up): an ear's root is a smooth line; hair gives creases that jump.
  double max_step_mm = 5.0;
  int min_slices = 3;  // depths (consecutive) that must hold a crease
  // The two sides' rests may differ this much in height (the ears' heights set the frame's pitch).
  // Their depths are averaged whatever their gap (unless another pair agrees better, below): the
  // rest's depth along the flat top of the root is loosely defined (the exact meshes' own searches
  // differ by up to 10.8 mm there), it moves the frame little, and the mean of two depths in the
  // window lies nearer either than Eq. 2-3's point, ~45 mm behind the temple and outside the window.
  double max_height_gap_mm = 15.0;
  // A head's ears lie at one depth too, give or take the scatter along the root's flat top (the
  // exact meshes' first lines differ by up to 9.4 mm over the 38 models' meshes; 10.8 mm, seed 11's,
  // with the rests at the middles of the tops). When the two sides' first lines lie
  // further apart than this along d_fwd, and another pair of accepted lines, one per side, agrees
  // within it and within max_height_gap_mm, that pair is used: the one whose lines rank highest
  // together (the least sum of their places in each side's order), then the closest. A line that
  // stands in for its side's first must span short_line_slices depths. (The scan
  // capture s_r2_y20: its left side's highest line lay 30 mm behind the temple, over the ear's back,
  // and the root's own line, 10 mm behind it, was the next; docs/bench/real-captures.md, "a pair of
  // lines that agree".) Infinity: each side's first accepted line, whatever the gap.
  double max_depth_gap_mm = 12.0;
  // Where a rest has no second witness, it must lie at most this high above its eye corner (the rests
  // of every head we know lie -5..+17 mm above them; the creases found in in2n-face's curls 29-30
  // mm): one side found, the other showing no crease (a narrow arc that saw one ear better, or a ray
  // field that missed it) or vetoed (hair over that ear; the found side passed the same veto), whose
  // rest is then mirrored onto the other side; and a line of creases under a higher one that the veto
  // refused (hair's lower edge makes creases too).
  double plausible_highest_mm = 20.0;
  // A line of creases over fewer depths than this, above a line at least this long, is passed over for
  // that one (it stays as the next candidate): a temple slides under hair's edge onto the ear's root.
  // (Procedural seed 13, whose dark hair ends just above its ears: the hair's edge made 3 depths at
  // +18.2 mm, 3 mm behind the temple, over the root's 12 depths at +9.8 mm, 23 mm behind it;
  // docs/bench/real-captures.md, "a short line above the ear's root".) Such a line, used opposite a
  // line at least this long, gives the rests no depth (apply_ear_roots): it is a fragment of its root,
  // whose front end is not where the root leaves the head (seed 13's left side: 4 of the mesh's 12
  // depths, at their back end; docs/bench/real-captures.md, "a fragment of the root").
  int short_line_slices = 5;
  // The rest's height: the mean of the creases whose height (a median over three depths) lies within
  // this of the highest (the top of the root is a plateau a few depths long; its first slice would
  // bias the rest forward or back).
  double plateau_mm = 1.5;
  // The rest's depth and width: the middle of the root's top, each crease weighted by how far its
  // (median) height lies above the highest minus this (mm). Along the flat top a NeRF's heights
  // scatter by a millimetre or two, so the hard plateau above picked a few depths anywhere along it
  // (p_r1_y40: 1 of 13 depths, at the run's front end); the soft weights keep the whole top. 0: the
  // plateau's mean, as the height.
  double depth_window_mm = 4.0;
  // The rest's depth, instead: this far behind the line's front end (mm; no further back than its
  // back end), where the ear's root leaves the head. A NeRF fills the gap between the ear's back and
  // the skull, so its lines run further back than the exact mesh's (the scan, s_r2_y40: to 23 / 21
  // mm behind the temple, against 15 / 11), and their middles with them; their front ends agree (3
  // against 5 mm). Over 38 NeRFs (rays at opacity 0.5) the NeRF's and the mesh's rests then lie
  // within 4 mm on 66 of 76 ears (57 from the middles). 9 mm keeps the fit as near synth's
  // anatomical rests as the middles did (6 mm: 0.7 mm nearer, but the frame 0.2 deg further from
  // theirs; 3 mm: further in both; docs/bench/real-captures.md, "the rest from the root's front").
  // Negative: the middle of the root's top, as above.
  double rest_behind_front_mm = 9.0;
};

struct EarRootSide {
  bool found = false;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // scene units
  double height_mm = 0.0;                           // the rest above the side's outer eye corner (along d_up)
  double depth_mm = 0.0;    // along d_fwd from the temple landmark (negative: behind it)
  double lateral_mm = 0.0;  // and outwards from it along the side's d_eye
  bool vetoed = false;      // found, then refused by the caller's veto (`why` says why)
  int higher_vetoed = 0;    // higher lines of creases on this side that the veto refused
  int passed_over = 0;      // higher lines it accepted too, passed over for a pair that agrees in depth
  double bend_deg = 0.0;    // how sharply the profile turns there
  int slices = 0;  // consecutive depths holding the chosen line of creases (or the longest, when too short)
  double back_mm = 0.0, front_mm = 0.0;  // the line's first and last depth (along d_fwd from the temple)
  int plateau = 0;                       // of them, those averaged into the rest
  std::vector<Eigen::Vector3d> ear_top;  // the plateau's ear top just outside each crease (scene), for the
                                         // caller's look at its colour (hair is not an ear)
  std::string why;                       // when not found: what the window showed
};

struct EarRootInputs {
  Eigen::Vector3d temple;              // the side's temple landmark (scene)
  Eigen::Vector3d eye_corner;          // the side's outer eye corner (scene): the window's height
  Eigen::Vector3d d_eye, d_up, d_fwd;  // the head frame (unit; d_eye towards the wearer's left)
  int side = +1;                       // +1 = the wearer's left, -1 = right
  double mm_per_unit = 0.0;
};

// One depth's profile: the heights (mm above the side's outer eye corner; NaN where the ray met
// nothing) where the search's vertical rays, at `lateral_mm` outwards from the temple, reach the
// options' opacity. What the search reads for its creases, for studies and charts.
struct EarRootProfile {
  double depth_mm = 0.0;  // along d_fwd from the temple landmark
  std::vector<double> lateral_mm, height_mm;
};
std::vector<EarRootProfile> ear_root_profiles(const DensityFn& density, const EarRootInputs& in,
                                              const EarRootOptions& options,
                                              const std::vector<double>& depths_mm);

// Searches one side's window in `density` (scene units; one query for all its rays). Throws on bad inputs (a
// non-positive scale or step, an empty window). The rest on the highest line of creases.
EarRootSide find_ear_root(const DensityFn& density, const EarRootInputs& in, const EarRootOptions& options);
// Every line of creases long enough, highest first (each `found`; lines shorter than
// `short_line_slices` above the highest line at least that long follow it); or one side not found, with
// why.
std::vector<EarRootSide> find_ear_root_lines(const DensityFn& density, const EarRootInputs& in,
                                             const EarRootOptions& options);

struct EarRoots {
  EarRootSide left, right;
  // Which ears `apply_ear_roots` put in place: Eq. 2-3's, both sides' rests, or one side's mirrored.
  enum class Use { kEq23, kBoth, kMirrored } use = Use::kEq23;
  bool from_density() const { return use != Use::kEq23; }
  std::string note;             // why one side found alone was not mirrored
  std::string summary() const;  // for the log: what each side showed and which ears were used
};

// Both sides' searches on `ears`' inputs, and the ears they give. `accept` may veto a line of creases
// (e.g. its ear top is hair-dark), with a reason: a side takes its highest line accepted, and is
// vetoed when it has lines and none is accepted. When both sides are found and their rests lie at
// one height within `max_height_gap_mm`, they replace Eq. 2-3's points, both at the mean height and
// depth of the two (an ear of each kind would roll and yaw the frame; the depth is the long line's alone
// where the other spans fewer than `short_line_slices` depths). Where the first accepted lines
// lie more than `max_depth_gap_mm` apart in depth, or too far apart in height, a lower pair that
// agrees in both is taken instead, if there is one. When one side is found, lies
// no higher than `plausible_highest_mm`, and the other side showed no ear (no line of creases, or
// every line vetoed), the found rest stands for both: the other side's rest lies at its height and
// depth, as far out from that side's temple as the found one. Otherwise `ears` stays as it is.
using EarVeto = std::function<std::string(const EarRootSide&)>;  // empty string: accepted
EarRoots apply_ear_roots(const DensityFn& density, const EarInputs& in, const Eigen::Vector3d& d_eye,
                         double mm_per_unit, const EarRootOptions& options, EarPoints& ears,
                         const EarVeto& accept = {});

}  // namespace lorgnette::fit
