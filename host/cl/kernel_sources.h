// The OpenCL sources embedded at build time (kernels/**/*.cl, *.h) and their assembly into one
// translation unit: #include "x.h" lines are resolved from the embedded files (each at most once)
// and #line directives keep compiler messages pointing at the original file and line. Compilers
// that ignore #line (NVIDIA's reports `<kernel>:53:3: error: ...`) get their build logs mapped back
// on the host through the assembly's line map (map_build_log).
#pragma once
#include <map>
#include <string>
#include <vector>

namespace lorgnette::cl {

// Path relative to kernels/ -> file text. Defined in the generated embedded_kernels.cpp.
const std::map<std::string, std::string>& embedded_kernel_files();

struct SourceLocation {
  std::string file;  // relative to kernels/
  int line = 0;      // 1-based
};

// Where each line of an assembled source came from.
class LineMap {
 public:
  // Appends the next assembled line: line `line` of `file`, or (line 0) a line the assembly added.
  void push(const std::string& file, int line);
  // Location of assembled line `line` (1-based); false for added lines and lines out of range.
  bool find(int line, SourceLocation* out) const;
  int size() const { return static_cast<int>(lines_.size()); }

 private:
  std::vector<std::string> files_;
  std::vector<std::pair<int, int>> lines_;  // (index into files_, line in that file)
};

struct AssembledSource {
  std::string text;
  LineMap lines;
};

// The self-contained source for `root` (e.g. "hashgrid/hashgrid_encode.cl"), with its line map.
// Include paths are relative to kernels/. Throws when a file or an include is missing.
AssembledSource assemble_kernel_source_mapped(const std::string& root);
std::string assemble_kernel_source(const std::string& root);  // the text only

// Rewrites build-log references to lines of the assembled source that name no file — `<kernel>:L:C`
// (NVIDIA), `<source>:L:C` and the like, and `:L:C` at the start of a line — to `file:line:col` of
// the original file. References that name a file (compilers honouring #line, e.g. PoCL) and lines
// the map does not know are left as they are.
std::string map_build_log(const std::string& log, const LineMap& lines);

}  // namespace lorgnette::cl
