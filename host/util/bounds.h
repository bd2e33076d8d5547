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
inline constexpr Bound kLeanGate{"--lean-gate", "", 0, 1, "clearing gate beyond the bare head"};
inline constexpr Bound kSolidPull{"--solid-pull", "", 0, 100, "pull towards opaque in the head's interior"};

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
