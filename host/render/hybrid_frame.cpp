// A hybrid frame with the surface pass overlapped with the march: see hybrid_frame.h.
#include "host/render/hybrid_frame.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <future>
#include <stdexcept>
#include <utility>

namespace lorgnette::render {
namespace {
using Clock = std::chrono::steady_clock;

struct TimedSurfaces {
  lorgnette::SurfaceBuffers buffers;
  double seconds = 0.0;
};

TimedSurfaces run_surface_pass(const GlassesSurfaces& g, const Camera& cam, uint32_t spp) {
  auto t0 = Clock::now();
  TimedSurfaces t{g.render(cam, spp), 0.0};
  t.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return t;
}
}  // namespace

RenderResult render_hybrid_frame(Marcher& marcher, const VolumeScene& scene, const Camera& cam,
                                 const GlassesSurfaces* glasses, const FrameOptions& o) {
  if (!glasses) return marcher.render(scene, cam, nullptr, o.march);
  if (!glasses->render || !glasses->screen_rect)
    throw std::invalid_argument("render: the glasses have no surface pass or no screen bounds");
  if (o.surface_spp < 1 || o.surface_spp > 1024)
    throw std::invalid_argument(
        fmt::format("render: glasses samples per pixel must be 1..1024, not {}", o.surface_spp));
  auto t0 = Clock::now();
  if (!o.concurrent) {
    TimedSurfaces s = run_surface_pass(*glasses, cam, o.surface_spp);
    RenderResult r = marcher.render(scene, cam, &s.buffers, o.march);
    r.times.surface = s.seconds;
    r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    return r;
  }
  const std::array<uint32_t, 4> rect = glasses->screen_rect(cam);
  if (rect[0] >= std::min(rect[2], cam.width) || rect[1] >= std::min(rect[3], cam.height)) {
    RenderResult r = marcher.render(scene, cam, nullptr, o.march);  // the glasses are out of view
    r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    return r;
  }
  // The future's destructor joins the thread, also when the march throws first.
  std::future<TimedSurfaces> pending =
      std::async(std::launch::async, run_surface_pass, std::cref(*glasses), std::cref(cam), o.surface_spp);
  TimedSurfaces done;
  PendingSurfaces band;
  band.row_begin = std::min(rect[1], cam.height);
  band.row_end = std::min(rect[3], cam.height);
  band.wait = [&]() -> const lorgnette::SurfaceBuffers& {
    done = pending.get();
    return done.buffers;
  };
  RenderResult r = marcher.render(scene, cam, band, o.march);
  r.times.surface = done.seconds;
  r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return r;
}

}  // namespace lorgnette::render
