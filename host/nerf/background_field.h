// The room around the subject on mask-less captures (docs/room-training.md): a second, coarse NeRF
// over a large box around the cameras, trained jointly with the subject's model. Every training
// ray is rendered by both: the room's colour, sampled from the subject's distance on, is the
// background the subject composites over (C = C_subject + T_subject * C_room), so the room need
// not be painted onto the subject box's faces and the subject's opacity becomes a matte. The room
// model is for training only: renders, the fit and snapshots use the subject model alone.
//
// The gradient reaches the room model without touching the kernels: the L2 loss kernel computes
// dL/dC = 2 * grad_scale * (C - target), so setting the room rays' target to
// C_room - T_subject * dL/dC_subject / (2 * grad_scale) back-propagates exactly
// T_subject * dL/dC_subject, the chain rule through the compositing.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "host/field/field_config.h"
#include "host/nerf/model.h"
#include "host/nerf/occupancy_update.h"
#include "host/nerf/ray_batch.h"
#include "host/nerf/subject_volume.h"
#include "host/nerf/views.h"

namespace lorgnette::nerf {

struct BackgroundOptions {
  bool enabled = false;
  float box_scale = 4.0f;  // room box half-size = box_scale * farthest camera distance
  uint32_t levels = 10, log2_table = 17, finest_resolution = 512, occupancy_resolution = 64;
  // The room model's marching step = its box's diagonal / this. The room is a blurred backdrop;
  // a finer step fills the step's rays with room samples and leaves fewer to the subject.
  uint32_t steps_per_diagonal = 128;
  // Colour without view dependence (SH degree 1): a room model that could change colour with the
  // direction would paint the subject, as each view sees it, onto the wall behind it.
  uint32_t sh_degree = 1;
  // Without `subject`: the subject box grown by this fraction of its size sideways, backwards,
  // forwards and upwards is cut out of the room model, so it cannot paint the face on a surface just
  // behind the head. Not downwards: the shoulders and body below the head box are the room's.
  float cutout_margin = 0.5f;
  // The subject's volume in its box and its clearing zones, when known (a head's volume from its
  // landmark box, capture/head_volume.h). The subject's model is masked to the volume, and the
  // room's cutout is that volume grown by `volume_cutout_margin` x the subject box's largest side:
  // the room model covers what the subject may not hold (the box's corners, the space beside and
  // behind the head) and the zones' `body` (below a head's box), which would otherwise belong to
  // neither model and be painted onto the subject box's bottom.
  std::optional<SubjectZones> subject;
  float volume_cutout_margin = 0.1f;
  float lr_scale = 1.0f;  // the room model's learning rate relative to the subject's
  // The room model's sample capacity per step relative to the subject's batch. The step's rays are
  // the leading rays that fit both batches. At 1 (with the spread below) the subject keeps its full
  // batch and the room model trains enough to explain the room; at less, the subject rebuilds the
  // room inside its volume.
  float batch_scale = 1.0f;
  // Spread the room model's batch evenly over the step's rays: each ray gets at most
  // (room batch / rays) room samples (the nearest ones), so every ray the subject's batch holds also
  // fits the room's. Off, rays are cut where the room's batch is full, and the subject's batch runs
  // half empty.
  bool spread_over_rays = true;
  // Weight of the binary-opacity prior on the subject's rays (kernels/train/render.h): with a room
  // model behind it, a ray through the subject should be opaque and one past it clear, so the
  // semi-transparent fringe and haze the colour loss alone leaves is pushed to 0 or 1. 0 = off.
  // 0.03 clears the faint haze outside the outline; much stronger costs IoU and face quality. It
  // and the clearing below ramp in linearly over `opacity_prior_ramp` steps after step
  // `opacity_prior_start` (opacity_prior_share; train --prior-start). Not from step 0: it would push
  // the still transparent subject of the first steps to clear. The default waits for the end of the
  // occupancy grid's warm-up. Earlier (128), the clearing meets the haze of the wall's colour that the
  // subject paints around the head in the warm-up while it is still partly transparent (the clearing
  // pulls the ray's opacity, whose gradient vanishes once the haze is opaque): the leak before a
  // plain wall falls by a quarter or more, but the dark head before a dark wall gets more holes, so
  // it is an option (docs/room-training.md, "The opacity prior and the room-explained clearing").
  float opacity_prior = 0.03f;
  uint32_t opacity_prior_start = 256, opacity_prior_ramp = 256;
  // Room-explained clearing (kernels/train/render.h): on a ray whose pixel the room model's colour
  // already matches (RMS sRGB difference under `room_clear_tolerance`, a linear gate), the prior
  // pulls the subject's opacity to 0 with `room_clear` x its weight instead of pushing it to 0 or 1,
  // so the subject does not keep a wall that the room model explains (a frontal capture's wall in
  // the head volume's rim). 0 = off.
  float room_clear = 1.0f;
  float room_clear_tolerance = 0.05f;
  // The clearing's gate closes as far as the subject explains the pixel better than the room alone
  // (kernels/train/render.h render_ray_clear_gate): fully where the ray's render lies this much
  // (RMS sRGB) nearer the pixel than the room's colour. Hair of the wall's colour, shaded strand by
  // strand, and a pale face's shading before a wall of its colour carry what the flat room lacks;
  // the haze that paints the room's own colour does not. 0 = off (the room gate alone).
  float subject_explains = 0.0f;
  // subject->keep is where the clearing does not apply (the binary prior does) when `keep_neck`: the
  // part of the subject that the room model's own surfaces lie right behind (a head's neck, with the
  // body below the box in the room model), where the room can match the subject's colour without the
  // subject being a backdrop. Off, the haze of the wall's colour beside the neck clears, but so does
  // the neck below the jaw (the room's body behind it explains it), before an off-white wall as before
  // a wall of the skin's colour: a hole in the subject is worse than haze beside it
  // (docs/room-training.md, "Zones"). Off only for measurement (bench_room_budget's keep=0);
  // `neck_clear` below clears the haze on the rays whose pixel is no skin colour.
  // subject->core is the bare head (skull, face and neck without the hair margins). In the
  // subject's volume outside it (hair margins, nape) the clearing's gate is at least `lean_gate`
  // whether the room explains the pixel yet or not: side views see that space against the wall,
  // the room model, trained there only through the haze, never learns it, and the binary prior
  // would make the haze solid. Hair there stays where its colour differs from the room's. 0 = off.
  float lean_gate = 1.0f;
  bool keep_neck = true;
  // The subject's certain interior (subject->solid: behind a face's skin, in the skull, a neck's
  // core). The room model holds only what lies beyond the subject's volume, so a ray that crosses the
  // interior ends in the subject before the wall and the room cannot explain it, whatever its colour
  // matches: no sample of that ray gets the room-explained clearing, and its samples in the interior
  // are pulled towards an opaque ray at this times the prior's weight; the interior's cells stay
  // occupied. Colour cannot tell a pale face from a pale wall behind it; the geometry can
  // (docs/room-training.md, "A whole subject"). 0 = off (the clearing as everywhere else).
  float solid_pull = 1.0f;
  // How far beyond the certain interior (mm, towards the skin) a ray counts as crossing it. The
  // interior lies 4-20 mm inside the skin (12 mm below a p1 adult skull's top, 10 mm inside its
  // sides), so a ray that grazes the top of the skull through its hair passes over it, and the
  // clearing took hair and skin of the wall's colour there (docs/room-training.md, "The interior's
  // reach"). Within 15 mm a ray lies in the skin or its hair for most heads and at most about 10 mm
  // beside the skin where the interior comes nearest it: the head's edge, where haze is the lesser
  // flaw. The growth applies to subject->reach when it has one (the interior with a head's skull
  // stretched for the scale's error, capture/face_hull.h). The pull stays in the interior itself.
  // 0 = the interior (or that reach) alone.
  float solid_reach_mm = 15.0f;
  // The clearing in the neck's keep zone, on rays whose pixel is no colour of the subject's skin
  // (subject->skin, sampled on the face): its chromaticity lies further than this from every skin
  // chromaticity (and it is bright enough to judge; kernels/train/render.h render_ray_skin_like).
  // Such a ray passes no bare neck (a visual-hull argument), so the room's colour explaining it is
  // not the body behind a neck but the wall beside it: the slab of the wall's colour beside the neck
  // clears, while a wall of the skin's own colour keeps the binary prior as before. The samples'
  // own spread is added, so a capture whose skin varies more widens what counts as skin. 0.02: on
  // the hard cases an off-white wall lies 0.035 from pale skin's colours (with their sheen), a dark
  // wall 0.075 from dark skin's, and the skin's samples 0.002-0.007 from one another; the keep zone's
  // share of the off-white capture's leak fell 7.0 -> 1.4 points with no row's holes rising
  // (docs/room-training.md, "Zones"). 0 = off.
  float neck_clear = 0.02f;
  // Steps the room model trains alone before the subject's first, on the rays that miss the
  // subject's volume (no subject sample: their pixel is the room's for certain) and whose pixel is no
  // colour of the subject's skin, each teaching the room its pixel; the other rays teach it nothing. Trained
  // side by side from step 0, the subject's fine grid paints the wall around the head faster than the coarse
  // room learns it (a haze the binary prior then keeps), and the room may take a head's colour where the head
  // has not formed yet. A room that already explains the skin's own colour (a wall of that colour) keeps the
  // colour loss from forming the head where its shading matches the wall (an ear before a wall of its
  // colour), so such pixels wait for the subject (docs/room-training.md, "The room model first").
  // 0 = off.
  uint32_t room_first = 0;
  // In the neck's keep zone, the samples within the certain interior's reach (the neck's core grown by
  // solid_reach_mm) are pulled towards an opaque ray at this times the prior's weight, as the
  // interior's own are. The neck continues below the head box into the room model's body, whose
  // coarse neck there explains the lowest band of the neck (rays that run down through it) as well
  // as the subject does, and the binary prior alone leaves that band to whichever formed first: the
  // reach lies in the neck for most necks, so the subject keeps it (docs/room-training.md, "Zones").
  // 0 = off.
  float keep_pull = 1.0f;
  // In the neck's keep zone, a ray whose pixel may be skin gets the clearing as far as the room's
  // colour behind it comes from beyond the subject's surroundings: its box grown by this many mm (the
  // room's samples outside that: kernels/train/render.h render_ray_share_beyond). The keep zone keeps
  // the binary prior because the room's body right below a head's box (the neck's base) can explain
  // the neck's pixel; a room colour from further away is a wall's or the room's, no body's, so such a
  // ray is the core's case, and the slab of the wall's colour beside the neck, before a wall of the
  // skin's own colour, clears as the core's haze does. The margin trades that slab against the neck's
  // lowest band, whose rays run down into the room's neck base within a few cm of the box: at 0 the
  // slab went (leak 9.68 -> 1.07 %) but so did that band with hair of the wall's colour (IoU 0.949 ->
  // 0.936); at 25 mm 3.81 % and 0.946; at 50 mm 5.55 % and 0.950, the band kept; at 150 mm 7.92 %
  // (docs/room-training.md, "Zones"). Needs the subject's zones and their millimetres; 0 = off.
  float keep_far_mm = 50.0f;
  // Before a wall that may be skin (most of SkinChroma::beside_neck is skin-like, or no skin colours
  // are known), below the subject's volume (SubjectZones::base, a head box's bottom) only the room's
  // samples within this many mm of the neck's axis count as the subject's surroundings: the neck's
  // base is there, the shoulders beside it are the room's. The slab of the wall's colour beside the
  // neck's lowest band has its rays pass just over the shoulders, which the room's coarse model blurs
  // over them; counted as the body's, they kept that slab (leak 5.88 % before a wall of the skin's
  // colour). 70 mm: a p99 man's neck (ANSUR II circumference ~425 mm, a radius of 68 mm). Before a
  // wall of another colour the skin test clears that slab, and the whole grown box stays the body's,
  // so a neck wider than the column or turned off its axis by a nod keeps its band
  // (docs/room-training.md, "Zones"). 0 = the whole grown box always.
  float keep_far_neck_mm = 70.0f;
};

// The chromaticity distance within which a pixel may be the subject's skin (neck_clear plus the
// skin samples' own spread; kernels/train/render.h render_ray_skin_like).
float skin_tolerance(const BackgroundOptions& options);

// Whether the subject's neck keep cells apply (keep_neck, the clearing on, a keep zone given):
// trainer.cpp's prior zones build them, and only their rays read a far share.
bool keep_cells_apply(const BackgroundOptions& options);
// Whether the far-wall rule applies (keep_far_mm): the keep cells, a margin and the zones' millimetres.
bool keep_far_applies(const BackgroundOptions& options);
// The far-wall rule's column (keep_far_neck_mm): how many of SkinChroma::beside_neck's patches may be
// skin (render_ray_skin_like as the neck's keep zone judges a pixel) of how many, and whether the rule
// narrows the body below the box to the column: the rule applies, the zones know the neck's base, and
// the wall beside the neck may be skin (at least half the patches, or no skin colours are known).
struct NeckColumn {
  size_t skin_like = 0, patches = 0;
  bool applies = false;
};
NeckColumn neck_column(const BackgroundOptions& options);

// The share of the opacity prior's weight (and the clearing's) at training step `step`: 0 until
// `opacity_prior_start`, rising linearly to 1 over `opacity_prior_ramp` steps.
float opacity_prior_share(const BackgroundOptions& options, uint64_t step);

class BackgroundField {
 public:
  // subject: the subject's model (its box is cut out of the room's occupancy); views: the training
  // views (camera positions size the room box).
  BackgroundField(cl::Runtime& rt, const NerfModel& subject, const DeviceViews& views,
                  const BackgroundOptions& options, uint32_t max_batch, uint32_t seed);
  ~BackgroundField();

  NerfModel& model() { return *model_; }
  std::string summary() const;
  uint64_t samples_done() const { return samples_; }  // room samples trained so far
  // The state a training checkpoint keeps beside the model's (checkpoint.h).
  OccupancyUpdater& occupancy_updater() { return *occupancy_; }
  const OccupancyUpdater& occupancy_updater() const { return *occupancy_; }
  const NerfModel& model() const { return *model_; }
  void set_samples_done(uint64_t n) { samples_ = n; }

  // Counts the room samples of the same rays the subject's sampler draws (p: the subject step's
  // SampleParams); returns how many leading rays fit the room model's batch.
  uint32_t count(const SampleParams& subject_params, const DeviceViews& views);
  // Writes and renders rays [0, end) through the room model (forward, kept for backward) and puts
  // their colours, and their far shares (keep_far_mm), as the background of the subject's written
  // rays (subject.ray_info()).
  void render_backgrounds(const SampleParams& subject_params, const DeviceViews& views, uint32_t end,
                          RayBatch& subject);
  // After the subject batch's render(): back-propagates T_subject * dL/dC into the room model and
  // takes its Adam step (lr: the subject's current learning rate), then its occupancy update.
  void backward(RayBatch& subject, uint32_t loss_kind, const field::AdamConfig& adam, uint32_t step);
  // After render_backgrounds() without the subject's render: one step of the room model alone
  // (BackgroundOptions::room_first) on the written rays whose subject_counts[r] is 0, each taught
  // its pixel (subject.ray_info()'s target) as a subject-free ray is; the other rays teach nothing.
  void train_alone(RayBatch& subject, const std::vector<uint32_t>& subject_counts, uint32_t loss_kind,
                   const field::AdamConfig& adam, uint32_t step);
  // What train_alone() did so far: its rays, those that missed the subject's volume, and those of
  // them that taught the room (no skin colour).
  std::string alone_summary() const;

 private:
  // Whether a pixel (linear RGB) may be the subject's skin, as the neck's keep zone judges it
  // (kernels/train/render.h render_ray_skin_like with the skin's colours and neck_clear's tolerance);
  // false when no skin colours are known.
  bool skin_like(const float* pixel) const;
  // dL/d(room colour) of ray r (into g[3], zeroed) from its pixel `target` and the batch's grad_scale.
  using RayGradient = std::function<void(uint32_t r, const float* target, float grad_scale, float* g)>;
  // Teaches the room model each written ray's gradient (as the target of its own L2 loss), then takes
  // its Adam step (lr: the subject's, times lr_scale) and its occupancy update.
  void teach(RayBatch& subject, const RayGradient& gradient, const field::AdamConfig& adam, uint32_t step);

  BackgroundOptions options_;
  std::unique_ptr<NerfModel> model_;
  std::unique_ptr<RayBatch> batch_;
  std::unique_ptr<OccupancyUpdater> occupancy_;
  SampleParams params_{};
  float near_t_ = 0.0f;  // room samples start this far from the camera: at the subject's depth
  uint32_t written_ = 0;
  uint64_t samples_ = 0;
  std::vector<float> colors_;       // room colour + opacity per written ray
  std::vector<float> skin_chroma_;  // the subject's skin chromaticities (r, g pairs) for skin_like()
  // The subject's surroundings in the room's normalised positions (keep_far_mm; empty: off).
  std::optional<NearRegion> near_;
  uint64_t alone_rays_ = 0, alone_missed_ = 0, alone_taught_ = 0;  // train_alone()'s rays
};

}  // namespace lorgnette::nerf
