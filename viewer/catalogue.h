// The frames a viewer offers and where their placements live. The catalogue is fixed by the command
// line (--glasses FRAME or --catalogue DIR): clients pick by index and never name a path. A frame's
// placement is the file given with --placement, else <frame>.placement.json beside it (written by
// an earlier viewer fit or save), else none (the viewer fits it). Saving writes
// <frame>.placement.json: an existing file is replaced only when the client confirmed, and then a
// timestamped backup of it is kept beside it.
#pragma once
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "fit/placement_json.h"
#include "viewer/protocol.h"

namespace lorgnette::viewer {

struct FrameEntry {
  std::string name;       // shown to the user: the file's (or its folder's) name
  std::string path;       // the frame file
  std::string placement;  // --placement for a single frame; empty otherwise
  std::string save_path() const { return path + ".placement.json"; }
};

// Frame files (.glb .gltf .obj .ply) in `dir`, and folders in it holding exactly one such file
// (e.g. glasses-01/scene.gltf), sorted by name. Throws when `dir` has none.
std::vector<FrameEntry> catalogue_from_dir(const std::string& dir);
std::vector<FrameEntry> catalogue_single(const std::string& frame, const std::string& placement);

// The placement file to read for an entry, if any.
std::optional<std::string> existing_placement(const FrameEntry& e);

// The placement after a hand nudge: transform' = transform * nudge_matrix(n), n moving the frame in
// its own canonical axes (placement.json's "nudge", fit/placement_json.h).
using Nudge = fit::PlacementNudge;
using fit::nudge_matrix;
// Bounds of the accumulated nudge (a frame cannot be pushed off the face by repeated clicks).
constexpr double kMaxNudgeMm = 15.0, kMaxNudgeTiltDeg = 20.0;
Nudge accumulate(const Nudge& n, const NudgeMsg& delta);

struct SaveResult {
  bool ok = false;
  std::string path, backup;  // backup: the replaced file's copy, when there was one
  ProtocolError error;       // code "exists" (needs overwrite) or "io"
};

// Writes `p` with the nudge applied to its transform and recorded as its "nudge" (write_placement:
// atomic, the glasses path relative to the file); see the header comment.
SaveResult save_placement(const std::string& path, const fit::PlacementFile& p, const Nudge& nudge,
                          bool overwrite);

}  // namespace lorgnette::viewer
