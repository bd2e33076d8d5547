// Subcommand registry of the `lorgnette` CLI. Each cmd_*.cpp registers itself with
// LGN_REGISTER_COMMAND; commands stay thin wrappers over the libraries.
#pragma once
#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/cl/runtime.h"

namespace lorgnette::cli {

// Options every command accepts (parsed before the subcommand runs).
struct GlobalOptions {
  std::string device;        // --device: index or name substring (see `lorgnette devices`)
  std::string kernel_cache;  // --kernel-cache DIR ("off" disables the disk cache)
  bool verbose = false;
  bool quiet = false;

  cl::RuntimeOptions runtime() const { return {device, kernel_cache, false}; }
};

// Throws when `path` exists and `force` is false: existing outputs are never overwritten without
// --force (README). `option` names the flag that chose the path, for the message.
inline void refuse_existing_output(const std::string& path, bool force, const std::string& option = "-o") {
  if (force || path.empty() || !std::filesystem::exists(path)) return;
  throw std::runtime_error("'" + path + "' exists: pass --force to overwrite it or choose another " + option);
}

// Thrown by a command that ends with a status of its own (e.g. `job run`, whose status tells the
// executor whether to retry); main returns `code` without printing anything.
struct ExitStatus {
  int code;
};

// A command adds its CLI::App subcommand and sets its callback. The callback throws on failure;
// main turns any exception into "error: ..." on stderr and exit status 1.
using CommandFactory = std::function<void(CLI::App& app, GlobalOptions& global)>;

struct CommandRegistration {
  int order;  // position in `lorgnette --help`
  CommandFactory factory;
};

std::vector<CommandRegistration>& command_registry();

struct Registrar {
  Registrar(int order, CommandFactory f) { command_registry().push_back({order, std::move(f)}); }
};

}  // namespace lorgnette::cli

// The registrar is named after its factory, which is unique among the commands: a name built
// from __LINE__ collides when the unity build puts two commands registered on the same line into
// one translation unit.
#define LGN_REGISTER_COMMAND(order, factory) \
  static ::lorgnette::cli::Registrar lgn_registrar_##factory(order, factory)
