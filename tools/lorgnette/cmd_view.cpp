// `lorgnette view MODEL [--glasses FRAME [--placement P] | --catalogue DIR] [--host 127.0.0.1] [--port
// 8080]`: serves the interactive try-on viewer (viewer/) and prints its URL; Ctrl-C stops it.
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <thread>
#include <tuple>

#include "host/util/bounds.h"
#include "host/util/interrupt.h"
#include "tools/lorgnette/command.h"
#include "viewer/server.h"
#include "viewer/viewer_service.h"

namespace lorgnette::cli {
namespace {

struct ViewArgs {
  std::string model, glasses, catalogue, placement, host = "127.0.0.1", size = "854x480";
  int port = 8080;  // wider than the port's type, so 70000 is refused with the range, not wrapped
  int coarse = 3;
  int fit_views = 12;
  int max_per_address = int(viewer::ServerOptions{}.max_per_address);
  bool no_fit = false;
};

// "WxH" within the viewport's bounds; anything else names the flag and its ranges.
std::pair<uint32_t, uint32_t> parse_viewport(const std::string& text) {
  int w = 0, h = 0;
  char extra = 0;
  if (std::sscanf(text.c_str(), "%dx%d%c", &w, &h, &extra) != 2)
    throw std::runtime_error("--size must be WxH (e.g. 854x480), found '" + text + "'");
  check_bound(bounds::kViewWidth, w);
  check_bound(bounds::kViewHeight, h);
  return {uint32_t(w), uint32_t(h)};
}

void validate(const ViewArgs& a) {
  check_bound(bounds::kPort, a.port);
  check_bound(bounds::kCoarse, a.coarse);
  check_bound(bounds::kViewFitViews, a.fit_views);
  check_bound(bounds::kMaxPerAddress, a.max_per_address);
  parse_viewport(a.size);
}

void run_view(const ViewArgs& a, GlobalOptions& global) {
  using namespace viewer;
  validate(a);  // before the model and the catalogue are loaded
  if (a.glasses.empty() == a.catalogue.empty())
    throw std::runtime_error("give either --glasses FRAME or --catalogue DIR (one of them)");
  if (!a.placement.empty() && a.glasses.empty())
    throw std::runtime_error(
        "--placement goes with --glasses (a catalogue's placements lie beside its frames)");
  if (!is_loopback_host(a.host))
    spdlog::warn(
        "--host {}: the viewer is reachable from other machines; it has no authentication, and anyone "
        "who can reach it can render views and save placements beside your frames",
        a.host);
  ViewerConfig config;
  config.model_path = a.model;
  config.catalogue =
      a.catalogue.empty() ? catalogue_single(a.glasses, a.placement) : catalogue_from_dir(a.catalogue);
  config.runtime = global.runtime();
  std::tie(config.width, config.height) = parse_viewport(a.size);
  config.coarse_divisor = uint32_t(a.coarse);
  config.fit.enabled = !a.no_fit;
  config.fit.settings.views = a.fit_views;
  spdlog::info("view: loading {} and {} frame(s)", a.model, config.catalogue.size());
  ViewerService service(config);
  ServerOptions so;
  so.host = a.host;
  so.port = uint16_t(a.port);
  so.max_per_address = size_t(a.max_per_address);
  Server server(service, so);
  std::cout << "lorgnette view: open " << server.url() << "  (" << service.device_name() << "; Ctrl-C stops)"
            << std::endl;
  server.start();
  while (!interrupted()) std::this_thread::sleep_for(std::chrono::milliseconds(200));
  spdlog::info("view: stopping");
  server.stop();
}

void add_view(CLI::App& app, GlobalOptions& global) {
  auto a = std::make_shared<ViewArgs>();
  auto* cmd = app.add_subcommand("view", "interactive try-on viewer in the browser (prints its URL)");
  cmd->add_option("model", a->model, "trained model (.lnerf)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--glasses", a->glasses, "one glasses frame (glTF/GLB/OBJ/PLY)")->check(CLI::ExistingFile);
  cmd->add_option("--catalogue", a->catalogue, "a folder of frames (files, or folders holding one each)")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--placement", a->placement,
                  "placement.json for --glasses (default: <frame>.placement.json, "
                  "else the viewer fits it)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--host", a->host, "address to listen on (anything but loopback is reachable by others)")
      ->capture_default_str();
  cmd->add_option("--port", a->port, "port (0: any free one)")->capture_default_str();
  cmd->add_option("--size", a->size, "default viewport WxH (the page sends its own)")->capture_default_str();
  cmd->add_option("--coarse", a->coarse, "coarse frames at 1/N resolution while interacting")
      ->capture_default_str();
  cmd->add_option("--fit-views", a->fit_views, "views rendered when fitting a frame")->capture_default_str();
  cmd->add_option("--max-per-address", a->max_per_address,
                  "connections one remote address may hold (a page uses up to 7); more are closed at once")
      ->capture_default_str();
  cmd->add_flag("--no-fit", a->no_fit, "frames without a placement get a rough stand-in instead of a fit");
  cmd->callback([a, &global] { run_view(*a, global); });
}

}  // namespace
LGN_REGISTER_COMMAND(65, add_view);
}  // namespace lorgnette::cli
