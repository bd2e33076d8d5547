// The layout of one capture's folder, which is its whole life: the shopper's upload, the dataset
// the capture stage makes, the model, one fit per catalogue frame, the job's settings and its
// progress. Deleting a capture deletes this folder; nothing made from it lives anywhere else.
#pragma once
#include <filesystem>
#include <string>

namespace lorgnette::service {

struct JobFolder {
  std::filesystem::path root;

  std::filesystem::path upload() const { return root / "upload"; }  // written by the server only
  std::filesystem::path dataset() const { return root / "dataset"; }
  std::filesystem::path model_dir() const { return root / "model"; }
  std::filesystem::path model() const { return model_dir() / "head.lnerf"; }
  // The training checkpoint (host/nerf/checkpoint.h): outside the train stage's temporary folder, so
  // a worker killed during training leaves it for the retry to resume from.
  std::filesystem::path train_checkpoint() const { return root / "train.ckpt"; }
  std::filesystem::path fits() const { return root / "fits"; }
  std::filesystem::path fit_dir(const std::string& frame_key) const { return fits() / frame_key; }
  std::filesystem::path settings() const { return root / "job.json"; }
  std::filesystem::path progress() const { return root / "progress.json"; }
};

// A frame's name as a folder name: letters, digits, '.', '-' and '_' kept, anything else '_', and
// never "." or ".." (a catalogue file name must not lead a fit outside fits/).
std::string frame_key(const std::string& frame_name);

// A catalogue frame file's content hash (fit::file_hash), "" when it cannot be read: what a frame
// that could not be fitted failed with, so that the shop's replacement of the file is tried again.
std::string frame_file_hash(const std::string& path);

}  // namespace lorgnette::service
