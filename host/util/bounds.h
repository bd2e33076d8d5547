// The range of every number a flag, a Python argument or a file carries, in one table, and the one
// error all of them raise outside it. The CLI, the Python module and the file readers check the same
// Bound, so a value is refused with the same words wherever it comes from (docs/input-limits.md
// lists the table). Header-only: the file parsers' fuzzers link no more than their parser.
//
// Why bounds at all: a value outside them never means anything useful, and several are costly in a
// way the user does not see coming (a marching step of 1e-9 marches a billion samples per ray, an
// orbit of 10^9 views allocates until the machine runs out of memory, NaN turns a background black).
#pragma once
#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace lorgnette {

// A number outside its Bound. Python raises it as lorgnette.RangeError (a lorgnette.Error and a
// ValueError) with the same text the CLI prints after "error: ".
class OutOfRange : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

struct Bound {
  const char* flag;    // the CLI's name ("--step-scale"), or the file key ("step")
  const char* python;  // Python's argument name, "" where Python has none
  double lo, hi;       // inclusive
  const char* what;    // what the number is, in a few words
};

// "--step-scale (Python: step_scale)", or the flag alone.
inline std::string bound_name(const Bound& b) {
  return *b.python ? fmt::format("{} (Python: {})", b.flag, b.python) : std::string(b.flag);
}

[[noreturn]] inline void throw_out_of_range(const Bound& b, double v) {
  throw OutOfRange(
      fmt::format("{} must be within {:g}..{:g} ({}), found {:g}", bound_name(b), b.lo, b.hi, b.what, v));
}

// `v` when it lies in [b.lo, b.hi]; NaN never does.
inline double check_bound(const Bound& b, double v) {
  if (!(v >= b.lo && v <= b.hi)) throw_out_of_range(b, v);
  return v;
}

// The same for a value where 0 means "automatic" (a default chosen from the data).
inline double check_bound_or_zero(const Bound& b, double v) { return v == 0.0 ? v : check_bound(b, v); }

// The same for a value a file holds: the message names the file first.
inline double check_file_bound(const std::string& file, const Bound& b, double v) {
  if (!(v >= b.lo && v <= b.hi))
    throw OutOfRange(fmt::format("'{}': '{}' must be within {:g}..{:g} ({}), found {:g}", file, b.flag, b.lo,
                                 b.hi, b.what, v));
  return v;
}

namespace bounds {

// Scene-frame coordinates (dataset units after its applied transform): far beyond any capture the
// dataset writers produce (capture normalises to a few units), short of float's loss of precision.
inline constexpr double kSceneCoord = 1e5;
// Marching steps across the box's diagonal: the default is 512 (sizing.h); 8 is too coarse to show a
// head, and more than 16384 only multiplies the work (and the samples a ray may hold).
inline constexpr double kMinStepsPerDiagonal = 8, kMaxStepsPerDiagonal = 16384;

// `train` (Python: train()).
inline constexpr Bound kTrainSteps{"--steps", "steps", 1, 1e7,
                                   "training steps; leave it out for the default"};
inline constexpr Bound kTrainSeconds{"--seconds", "seconds", 0.1, 604800,
                                     "seconds of training, at most a week"};
inline constexpr Bound kBatchLog2{"--batch-log2", "batch_log2", 10, 22, "log2 of the samples per step"};
inline constexpr Bound kDownscale{"--downscale", "downscale", 1, 16, "integer image downscale factor"};
inline constexpr Bound kMaxSide{"--max-side", "max_side", 16, 32768,
                                "longest image side in pixels; 0: no limit"};
inline constexpr Bound kTrainStep{"--step", "", 1e-6, 1e4, "marching step in scene units"};
inline constexpr Bound kAabbCoord{"--aabb", "", -kSceneCoord, kSceneCoord,
                                  "box corner coordinate, scene units"};
inline constexpr Bound kAabbScale{"--aabb-scale", "", 0.01, 128, "box size factor; 0: the dataset's"};
inline constexpr Bound kLearningRate{"--lr", "", 1e-6, 1, "base learning rate"};
inline constexpr Bound kSnapshotEvery{"--snapshot-every", "", 0, 604800,
                                      "seconds between snapshots; 0: at the end"};
inline constexpr Bound kFinestRes{"--finest-res", "", 16, 1 << 20, "finest hash-grid resolution"};
inline constexpr Bound kLog2Table{"--log2-table", "", 8, 24, "log2 of the hash-table size per level"};
inline constexpr Bound kLevels{"--levels", "", 1, 32, "hash-grid levels"};
inline constexpr Bound kOccRes{"--occ-res", "", 8, 512, "occupancy grid resolution"};
inline constexpr Bound kHairMm{"--hair", "hair_mm", 0, 300,
                               "millimetres of hair or hat above and behind the skull"};
inline constexpr Bound kOpacityPrior{"--opacity-prior", "", 0, 1, "weight of the room model's opacity prior"};
inline constexpr Bound kRoomClear{"--room-clear", "", 0, 100, "room clearing weight"};
inline constexpr Bound kRoomClearTolerance{"--room-clear-tolerance", "", 0.001, 1, "RMS sRGB difference"};
inline constexpr Bound kSubjectExplains{"--subject-explains", "", 0, 1, "RMS sRGB margin"};
inline constexpr Bound kSolidReach{"--solid-reach", "", 0, 100, "reach beyond the certain interior"};
inline constexpr Bound kNeckClear{"--neck-clear", "", 0, 1, "chromaticity distance from the skin's"};
inline constexpr Bound kLeanGate{"--lean-gate", "", 0, 1, "clearing gate beyond the bare head"};
inline constexpr Bound kSolidPull{"--solid-pull", "", 0, 100, "pull towards opaque in the head's interior"};
inline constexpr Bound kPriorStart{"--prior-start", "", 0, 1000000, "step the opacity prior ramps in from"};
inline constexpr Bound kKeepPull{"--keep-pull", "", 0, 100, "pull towards opaque in the neck's zone"};
inline constexpr Bound kKeepFar{"--keep-far", "", 0, 2000,
                                "mm beyond the subject's box that count as its body"};
inline constexpr Bound kKeepFarNeck{"--keep-far-neck", "", 0, 500,
                                    "mm about the neck's axis that count as its body below the box"};
inline constexpr Bound kRoomFirst{"--room-first", "", 0, 100000, "steps of the room model alone"};

// `render` (Python: Model.render(), Model.orbit()) and the renders the demo and the viewer make.
inline constexpr Bound kSpp{"--spp", "spp", 1, 64, "NeRF rays per pixel"};
inline constexpr Bound kSurfaceSpp{"--surface-spp", "surface_spp", 1, 256, "glasses samples per pixel"};
inline constexpr Bound kStepScale{"--step-scale", "step_scale", 0.25, 8, "marching step multiplier"};
inline constexpr Bound kBackground{"--background", "background", 0, 1, "linear RGB background channel"};
inline constexpr Bound kOrbitViews{"--orbit", "views", 1, 3600, "views around the head"};
inline constexpr Bound kImageSide{"--size", "size", 1, 8192, "image width or height in pixels"};
inline constexpr Bound kFovDeg{"--fov", "fov_y_deg", 5, 120, "vertical field of view in degrees"};
inline constexpr Bound kElevationDeg{"--elevation", "elevation_deg", -80, 80, "orbit elevation in degrees"};
// The most samples one ray marches: the finest model step (kMaxStepsPerDiagonal) at the finest
// step scale (kStepScale.lo). The marcher refuses anything beyond it instead of marching for hours.
inline constexpr double kMaxStepsPerRay = kMaxStepsPerDiagonal / 0.25;

// A placement by hand (`render --translate/--rotate/--scale`, Python's trs()): scene units, degrees,
// scene units per millimetre of the frame.
inline constexpr Bound kTranslate{"--translate", "translate", -kSceneCoord, kSceneCoord,
                                  "glasses translation in scene units"};
inline constexpr Bound kRotateDeg{"--rotate", "rotate_deg", -360, 360, "glasses rotation in degrees"};
inline constexpr Bound kGlassesScale{"--scale", "scale", 1e-9, 1e6,
                                     "scene units per millimetre of the frame"};

// Glasses files (`glasses inspect --mm-per-unit`, Glasses.load(mm_per_unit=), the sidecar's key):
// from micrometres to 100 m per file unit; 0 means "detect the units".
inline constexpr Bound kMmPerUnit{"--mm-per-unit", "mm_per_unit", 1e-3, 1e5,
                                  "millimetres per file unit; 0: detect"};
// A reference point in a mesh file's own coordinates (any unit from micrometres to metres).
inline constexpr double kMeshCoord = 1e7;

// `fit` (Python: fit()), the viewer's and the service's fits.
inline constexpr Bound kFitViews{"--views", "views", 2, 200, "views rendered for the fit"};
inline constexpr Bound kFitYawRange{"--yaw-range", "yaw_range", 0, 60,
                                    "views span +-this yaw in degrees (the detector works to about 45)"};
inline constexpr Bound kFitPitchRange{"--pitch-range", "pitch_range", 0, 45,
                                      "views span +-this pitch in degrees"};
inline constexpr Bound kFitResolution{"--resolution", "resolution", 64, 4096, "fit view size in pixels"};
inline constexpr Bound kFitCapResolution{"--cap-resolution", "", 64, 4096,
                                         "face view size in pixels; 0: --resolution"};
inline constexpr Bound kFitUpsample{"--upsample", "upsample", 0, 3, "detector up-sampling steps"};

// `view`: the viewer's viewport, its port and its fits.
inline constexpr Bound kViewWidth{"--size", "", 32, 1920, "viewport width in pixels"};
inline constexpr Bound kViewHeight{"--size", "", 32, 1080, "viewport height in pixels"};
inline constexpr Bound kPort{"--port", "", 0, 65535, "TCP port; 0: any free one"};
inline constexpr Bound kCoarse{"--coarse", "", 1, 8, "coarse frames at 1/N resolution"};
inline constexpr Bound kViewFitViews{"--fit-views", "", 4, 64, "views rendered when fitting a frame"};
inline constexpr Bound kMaxPerAddress{"--max-per-address", "", 1, 1024, "connections per remote address"};

// `capture` (and the service's captures): video sampling, frame count and size, features.
inline constexpr Bound kCaptureFps{"--fps", "", 0.01, 60, "video frames sampled per second"};
inline constexpr Bound kCaptureMaxFrames{"--max-frames", "", 1, 100000, "frames kept; 0: all"};
inline constexpr Bound kCaptureSide{"--size", "", 64, 8192, "longer frame side in pixels; 0: keep"};
inline constexpr Bound kMaxFeatures{"--max-features", "", 64, 65536, "SIFT features per frame"};

// `synth`.
inline constexpr Bound kSynthViews{"--views", "", 1, 100000, "views rendered"};
inline constexpr Bound kSynthSide{"--size", "", 16, 8192, "image width or height in pixels"};
inline constexpr Bound kSynthYaw{"--yaw-range", "", -180, 180, "camera yaw in degrees"};
inline constexpr Bound kSynthPitch{"--pitch-range", "", -80, 80, "camera pitch in degrees"};
inline constexpr Bound kSynthSamples{"--samples", "", 1, 16, "anti-aliasing samples per pixel axis"};
inline constexpr Bound kLookAt{"--look-at", "", -kSceneCoord, kSceneCoord, "aim point, dataset units"};
inline constexpr Bound kFrameRadius{"--frame-radius", "", 1e-4, kSceneCoord,
                                    "dataset units each view must contain; 0: the subject's"};
inline constexpr Bound kSynthFov{"--fov", "", 10, 120, "vertical field of view in degrees"};
inline constexpr Bound kPhoneDistance{"--phone-distance", "", 150, 3000, "camera distance in mm"};
inline constexpr Bound kSpecular{"--specular", "", 0, 2, "key-light highlight strength"};
inline constexpr Bound kWallMm{"--wall-mm", "", 200, 5000, "wall distance behind the eyes in mm"};
// Head sizes of adults around the procedural mean (about +-15 % spans the population's face widths).
inline constexpr Bound kHeadScale{"--head-scale", "", 0.85, 1.15, "the procedural head's size factor"};
inline constexpr Bound kMeshMmPerUnit{"--mesh-mm-per-unit", "", kMmPerUnit.lo, kMmPerUnit.hi,
                                      "millimetres per mesh unit; 0: unknown"};

// `eval` (its --downscale and --max-side are training's).
inline constexpr Bound kEvalMaxViews{"--max-views", "", 1, 100000, "views evaluated; 0: all"};

// `bench frames` (its --surface-spp and --step-scale are render's).
inline constexpr Bound kBenchRepeats{"--repeats", "", 1, 100, "timed frames per row"};
inline constexpr Bound kWaves{"--waves", "", 1, 256, "segments per ray and wave"};

// `demo` (0: the variant's default for each).
inline constexpr Bound kDemoViews{"--views", "", 8, 1000, "dataset views; 0: the default"};
inline constexpr Bound kDemoImageSize{"--image-size", "", 32, 2048, "dataset image size; 0: the default"};
inline constexpr Bound kDemoOrbitSize{"--orbit-size", "", 16, 8192, "orbit image size; 0: the default"};
inline constexpr Bound kDemoFitViews{"--fit-views", "", kFitViews.lo, kFitViews.hi,
                                     "views rendered for the fit; 0: the default"};

// `serve`: the service's own numbers; the job settings it passes on share the stages' ranges.
inline constexpr Bound kWorkers{"--workers", "", 1, 256, "local worker slots"};
inline constexpr Bound kRetentionDays{"--retention-days", "", 1, 3650, "days a capture is kept"};
inline constexpr Bound kMaxUploadMb{"--max-upload-mb", "", 1, 65536, "largest upload in MiB"};
inline constexpr Bound kMaxAttempts{"--max-attempts", "", 1, 20, "worker starts per job"};
inline constexpr Bound kJobCaptureFps{"--capture-fps", "", kCaptureFps.lo, kCaptureFps.hi, kCaptureFps.what};
inline constexpr Bound kJobCaptureMaxFrames{"capture_max_frames", "", kCaptureMaxFrames.lo,
                                            kCaptureMaxFrames.hi, kCaptureMaxFrames.what};
inline constexpr Bound kJobCaptureSide{"--capture-max-side", "", kCaptureSide.lo, kCaptureSide.hi,
                                       kCaptureSide.what};
inline constexpr Bound kJobTrainSteps{"--train-steps", "", kTrainSteps.lo, kTrainSteps.hi,
                                      "training steps; 0: the default"};
inline constexpr Bound kJobBatchLog2{"--train-batch-log2", "", kBatchLog2.lo, kBatchLog2.hi,
                                     "log2 of the samples per step; 0: the device's"};
inline constexpr Bound kJobTrainSnapshot{"train_snapshot_seconds", "", kSnapshotEvery.lo, kSnapshotEvery.hi,
                                         "seconds between training checkpoints; 0: at the end"};
inline constexpr Bound kJobTrainSide{"train_max_side", "", kMaxSide.lo, kMaxSide.hi, kMaxSide.what};
inline constexpr Bound kJobFitViews{"--fit-views", "", kFitViews.lo, kFitViews.hi, kFitViews.what};
inline constexpr Bound kJobFitResolution{"--fit-resolution", "", kFitResolution.lo, kFitResolution.hi,
                                         kFitResolution.what};
// The try-on pictures rendered per fitted frame: a turn of the head in steps a slider can show, at a
// side a phone shows sharply.
inline constexpr Bound kJobTryonViews{"--tryon-views", "", 1, 72, "try-on views per fitted frame"};
inline constexpr Bound kJobTryonSize{"--tryon-size", "", 64, 2048, "try-on view side in px"};

// `glasses make` (Python: Glasses.make()): a plausible adult frame, in millimetres.
inline constexpr Bound kLensWidth{"--lens", "lens", 30, 80, "lens width in mm"};
inline constexpr Bound kBridge{"--bridge", "bridge", 8, 30, "bridge in mm"};
inline constexpr Bound kTempleLength{"--temple", "temple", 100, 175, "temple length in mm"};
inline constexpr Bound kRim{"--rim", "", 0.8, 8, "rim width in mm"};
inline constexpr Bound kLensHeight{"--lens-height", "", 15, 80, "lens height in mm; 0: from the shape"};
inline constexpr Bound kMetallic{"--metallic", "", 0, 1, "frame metallic"};
inline constexpr Bound kRoughness{"--roughness", "", 0, 1, "frame roughness"};

// The .lnerf header.
inline constexpr Bound kNormalisationScale{"normalisation.scale", "", 1e-6, 1e6, "dataset to model scale"};
inline constexpr Bound kNormalisationOffset{"normalisation.offset", "", -1e7, 1e7, "dataset to model offset"};

}  // namespace bounds

// Throws OutOfRange unless `step` gives kMinStepsPerDiagonal..kMaxStepsPerDiagonal steps across a
// box of `diagonal` (scene units). `source` names where the step came from ("--step", a file).
inline void check_steps_per_diagonal(double diagonal, double step, const std::string& source) {
  const double n = diagonal / step;
  if (!(n >= bounds::kMinStepsPerDiagonal && n <= bounds::kMaxStepsPerDiagonal))
    throw OutOfRange(fmt::format(
        "{}: the marching step {:g} gives {:g} steps across the box's diagonal ({:g} scene units), outside "
        "{:g}..{:g}: the step must lie within diagonal/{:g} and diagonal/{:g} (the default is diagonal/512)",
        source, step, n, diagonal, bounds::kMinStepsPerDiagonal, bounds::kMaxStepsPerDiagonal,
        bounds::kMaxStepsPerDiagonal, bounds::kMinStepsPerDiagonal));
}

}  // namespace lorgnette
