// `lorgnette devices [--json]`: every OpenCL device found, with the index `--device` accepts.
#include <iostream>
#include <nlohmann/json.hpp>

#include "host/cl/device.h"
#include "tools/lorgnette/command.h"

namespace lorgnette::cli {
namespace {

void add_devices(CLI::App& app, GlobalOptions& global) {
  auto* cmd = app.add_subcommand("devices", "list the OpenCL devices (use the index with --device)");
  auto json = std::make_shared<bool>(false);
  cmd->add_flag("--json", *json, "print one JSON array on stdout");
  cmd->callback([json, &global] {
    auto devices = cl::list_devices();
    cl::DeviceInfo chosen = cl::select_device(global.device);
    if (*json) {
      nlohmann::json out = nlohmann::json::array();
      for (const auto& d : devices)
        out.push_back({{"index", d.index},
                       {"name", d.name},
                       {"platform", d.platform_name},
                       {"vendor", d.vendor},
                       {"type", d.type_name()},
                       {"version", d.version},
                       {"driver", d.driver_version},
                       {"compute_units", d.compute_units},
                       {"global_mem_bytes", d.global_mem_bytes},
                       {"selected", d.index == chosen.index}});
      std::cout << out.dump(2) << "\n";
      return;
    }
    for (const auto& d : devices) std::cout << (d.index == chosen.index ? "* " : "  ") << d.summary() << "\n";
  });
}

}  // namespace
LGN_REGISTER_COMMAND(0, add_devices);
}  // namespace lorgnette::cli
