// A glasses frame ready for fitting and rendering: the mesh in the canonical frame (millimetres,
// x to the wearer's left, +y up, +z forward, origin at g_c), its reference points, measurements,
// and what was detected or assumed on the way. load_glasses() is the one entry point for files.
#pragma once
#include <string>
#include <vector>

#include "mesh/canonical.h"
#include "mesh/frame_metrics.h"
#include "mesh/loader.h"
#include "mesh/refpoints.h"

namespace lorgnette::mesh {

struct Glasses {
  std::string path;
  TriMesh mesh;   // canonical mm, origin at g_c
  RefPoints ref;  // canonical mm (g_c = 0)
  FrameMetrics metrics;
  Canonicalization canonical;      // file -> canonical (with the final translation to g_c)
  std::vector<std::string> notes;  // loader warnings, assumptions, detection notes
};

struct GlassesOptions {
  LoadOptions load;
  // > 0 overrides unit detection (the sidecar may also set it), within bounds::kMmPerUnit; 0 detects;
  // anything else (negative, NaN) is refused.
  double mm_per_unit = 0.0;
  bool use_sidecar = true;  // read <file>.refpoints.json when it exists
};

Glasses load_glasses(const std::string& path, const GlassesOptions& options = {});

// Canonicalises an in-memory frame (the part of load_glasses after reading the file).
Glasses canonicalize_glasses(TriMesh mesh, const GlassesOptions& options,
                             const RefPointsSidecar* sidecar = nullptr);

}  // namespace lorgnette::mesh
