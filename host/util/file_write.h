// Checked file writes: every byte goes through write(2) and the file is closed with each call's
// result checked, so a full disk (ENOSPC), a quota or an I/O error is an
// exception naming the file, never a short file. Writes go to a temporary file beside the target
// that is renamed into place only after all of it was written and synced to disk, and the folder is
// synced after the rename, so the target is either the old file or the complete new one, even after
// a power cut.
#pragma once
#include <string>
#include <string_view>

namespace lorgnette {

// Writes `bytes` to `path` atomically (temporary file + rename); throws std::runtime_error saying
// what failed (e.g. "No space left on device") and what to do. The temporary file is removed on
// failure.
void write_file_atomic(const std::string& path, std::string_view bytes);

// The temporary name write_file_atomic uses for `path`: hidden, beside it, with the process id and
// `path`'s extension last (so writers that pick a format by extension still see it).
std::string temporary_path_for(const std::string& path);

// Throws unless a file can be created and written in `dir` (checked by writing and removing a small
// probe file): a read-only folder or a full disk is found before any long work starts. `what`
// names the output for the message (e.g. "the model '-o head.lnerf'").
void check_writable_folder(const std::string& dir, const std::string& what);

// Throws unless `path`, a file that was written by another library (a video encoder), exists and
// holds at least `min_bytes`: a writer that does not report a full disk leaves a short file.
void check_written_file(const std::string& path, long long min_bytes = 1);

}  // namespace lorgnette
