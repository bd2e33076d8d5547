// All-or-nothing output directories: a dataset is written into a hidden staging directory beside
// the destination and renamed into place only when complete, so an error, a full disk or Ctrl-C
// never leaves a half-written dataset under the requested name (the staging directory is removed on
// failure). A non-empty destination is refused unless `force` is set.
#pragma once
#include <string>

namespace lorgnette::synth {

class StagedDir {
 public:
  // Checks the destination and creates the staging directory; throws with what to do when the
  // destination is a file, is non-empty without force, or its parent is not writable.
  StagedDir(const std::string& destination, bool force);
  ~StagedDir();  // removes the staging directory unless commit() succeeded
  StagedDir(const StagedDir&) = delete;
  StagedDir& operator=(const StagedDir&) = delete;

  const std::string& path() const { return staging_; }  // write files here
  // Replaces the destination with the staging directory (rename on the same filesystem).
  void commit();

 private:
  std::string destination_, staging_;
  bool force_ = false, committed_ = false;
};

}  // namespace lorgnette::synth
