// Output folders a command owns, and the one rule for replacing them (--force): a command replaces
// only an earlier output of its own, recognised by the marker file it writes into each output,
// never a folder of other files, never the working directory or a folder above it, and never a
// folder holding one of its inputs (which the replacement would delete before they are read).
// StagedOutput builds the new result in a hidden sibling folder and swaps it in only when it is
// complete, so an error, a full disk or Ctrl-C leaves the old result whole.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace lorgnette {

// The marker file at the top of every output folder a command owns (JSON naming the command).
inline constexpr const char* kOutputMarker = ".lorgnette-output";

// The command that owns an output folder and how its outputs are recognised.
struct OutputOwner {
  std::string command;        // "synth", "demo", "capture": the name the marker holds
  std::string noun;           // for messages: "synthetic dataset", "capture", "demo output"
  std::string legacy_marker;  // a file its outputs held before the marker existed ("": none)
};

// True when `dir` holds the marker naming owner.command (or owner.legacy_marker).
bool is_output_of(const std::filesystem::path& dir, const OutputOwner& owner);

// Writes the marker for `owner` into `dir` (atomically, checked).
void mark_output(const std::filesystem::path& dir, const OutputOwner& owner);

// The --force rule, checked before any work. `dir` must be missing, an empty folder, or (with
// `force`) an earlier output of owner.command; it must not be or contain the working directory,
// nor contain any of `inputs`. Returns true when `dir` holds an earlier output that will be
// replaced; throws with what to do otherwise (nothing is changed).
bool check_output_folder(const std::filesystem::path& dir, const OutputOwner& owner, bool force,
                         const std::vector<std::string>& inputs = {});

// Throws when the output file `output` is one of `inputs` (the same path, or the same file through a
// link): even with --force, a command never writes its result over a file it reads, which would
// lose the input the user made (a placement over the model, a preview over the frame). `option`
// names the output's flag for the message. Missing files compare by their absolute paths.
void refuse_output_onto_input(const std::string& output, const std::vector<std::string>& inputs,
                              const std::string& option = "-o");

// An output folder built beside its destination and swapped in when complete.
class StagedOutput {
 public:
  // Runs check_output_folder and creates the hidden staging folder next to the destination; throws
  // when the check fails or the parent folder is not writable.
  StagedOutput(const std::string& destination, OutputOwner owner, bool force,
               const std::vector<std::string>& inputs = {});
  ~StagedOutput();  // removes the staging folder unless commit() succeeded
  StagedOutput(const StagedOutput&) = delete;
  StagedOutput& operator=(const StagedOutput&) = delete;

  const std::string& path() const { return staging_; }             // write the new result here
  const std::string& destination() const { return destination_; }  // absolute final path
  bool replaces_earlier() const { return replaces_; }              // an earlier output is at the destination
  // Marks the staging folder as this command's output and swaps it in for the destination (the old
  // folder is moved aside first and put back if the swap fails; removed once the new one is in).
  void commit();

 private:
  std::string destination_, staging_;
  OutputOwner owner_;
  bool force_ = false, replaces_ = false, committed_ = false;
};

// The folder nearest `path` that exists: `path` itself, or the closest of its parents (the working
// directory for a relative path with none).
std::filesystem::path nearest_existing_folder(const std::filesystem::path& path);

// The files a command writes straight into a folder (not staged: `render -o DIR` adds frames to a
// folder the user may already keep other files in), undone unless the command finishes. The
// constructor creates `dir` and any missing parents, and moves those of `names` that are already
// there (an earlier render that --force replaces) into a hidden folder in `dir`
// (".lorgnette-replaced-PID"). Without keep(), the destructor removes the folders it created, or the
// files of `names` and puts the moved files back: a full disk or an error never leaves an empty or
// half-filled folder that looks like a result, nor half of an earlier result replaced. With keep()
// (the command finished, or stopped with whole files), the moved files it wrote again are deleted
// and the others put back. Killed outright, the earlier files stay in the hidden folder.
class NewOutputs {
 public:
  NewOutputs(const std::filesystem::path& dir, const std::vector<std::string>& names);
  ~NewOutputs();
  NewOutputs(const NewOutputs&) = delete;
  NewOutputs& operator=(const NewOutputs&) = delete;
  void keep() { keep_ = true; }

 private:
  void put_back();  // the moved-aside files whose names are free again, then the hidden folder

  std::filesystem::path created_;           // the topmost folder this made ("": none)
  std::filesystem::path dir_, aside_;       // the folder; where replaced files wait ("": none)
  std::vector<std::string> names_, moved_;  // the command's files; those moved aside
  bool keep_ = false;
};

}  // namespace lorgnette
