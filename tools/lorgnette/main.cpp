// Entry point of the `lorgnette` CLI: global options, the registered subcommands, and one place
// where failures become a clear message and a non-zero exit status.
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>

#include "host/util/interrupt.h"
#include "host/util/version.h"
#include "tools/lorgnette/command.h"

namespace lorgnette::cli {
std::vector<CommandRegistration>& command_registry() {
  static std::vector<CommandRegistration> registry;
  return registry;
}
}  // namespace lorgnette::cli

int main(int argc, char** argv) {
  using namespace lorgnette;
  // Messages go to stderr so that --json output on stdout stays machine-readable.
  spdlog::set_default_logger(spdlog::stderr_color_mt("lorgnette"));
  spdlog::set_pattern("%^%l%$: %v");

  CLI::App app{"Lorgnette: view-consistent virtual try-on of glasses (NeRF head + ray-traced frame)"};
  app.require_subcommand(1);
  app.set_version_flag("--version",
                       std::string("lorgnette ") + version_string() + " (commit " + git_commit() + ")");
  cli::GlobalOptions global;
  app.add_option("--device", global.device,
                 "OpenCL device: index or name substring (see `lorgnette devices`)")
      ->envname("LORGNETTE_DEVICE");
  app.add_option("--kernel-cache", global.kernel_cache, "directory for compiled kernels ('off' disables)")
      ->envname("LORGNETTE_KERNEL_CACHE");
  app.add_flag("-v,--verbose", global.verbose, "more log output");
  app.add_flag("-q,--quiet", global.quiet, "only warnings and errors");
  app.fallthrough();

  auto& registry = cli::command_registry();
  std::stable_sort(registry.begin(), registry.end(),
                   [](const auto& a, const auto& b) { return a.order < b.order; });
  for (auto& r : registry) r.factory(app, global);

  app.parse_complete_callback([&] {
    spdlog::set_level(global.verbose ? spdlog::level::debug
                      : global.quiet ? spdlog::level::warn
                                     : spdlog::level::info);
  });
  install_interrupt_handler();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const cli::ExitStatus& s) {
    return s.code;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return interrupted() ? 130 : 1;  // a stop by signal keeps the shell's convention
  }
  return interrupted() ? 130 : 0;
}
