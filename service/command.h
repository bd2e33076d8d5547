// A short external command (a scheduler's client: sbatch, squeue, scancel) run to its end with
// fork + execv (no shell, so no argument is ever interpreted), its stdout and stderr captured, and
// killed when it overruns its time limit, so a hung controller never stalls the server's loop.
#pragma once
#include <string>
#include <vector>

namespace lorgnette::service {

struct CommandResult {
  int status = -1;  // the exit status; -1 when it could not start, was killed, or timed out
  std::string out, err;
  bool ok() const { return status == 0; }
};

// Runs argv (argv[0] a path) with the server's environment. Never throws for the command's own
// failure: a start failure or timeout is a CommandResult with status -1 and `err` saying why.
CommandResult run_command(const std::vector<std::string>& argv, double timeout_seconds);

// The absolute path of `name` found in the folders of $PATH, or in `dir` when given; "" when absent.
std::string find_program(const std::string& name, const std::string& dir = "");

}  // namespace lorgnette::service
