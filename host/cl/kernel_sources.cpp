// Include resolution for embedded kernels and build-log line mapping; see kernel_sources.h.
#include "host/cl/kernel_sources.h"

#include <algorithm>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>

namespace lorgnette::cl {
namespace {

struct Assembly {
  std::set<std::string> seen;
  AssembledSource out;
  void add_line(const std::string& text, const std::string& file, int line) {
    out.text += text;
    out.text += '\n';
    out.lines.push(file, line);
  }
};

void append_file(const std::string& path, Assembly& a) {
  if (!a.seen.insert(path).second) return;  // every header is #pragma once by construction
  const auto& files = embedded_kernel_files();
  auto it = files.find(path);
  if (it == files.end())
    throw std::runtime_error("Kernel source '" + path + "' is not embedded in this build (it must " +
                             "live under kernels/ and the build must be re-run after adding it)");
  static const std::regex include_re(R"(^\s*#\s*include\s*"([^"]+)\")");
  static const std::regex pragma_once_re(R"(^\s*#\s*pragma\s+once)");
  std::istringstream in(it->second);
  std::string line;
  int lineno = 0;
  a.add_line("#line 1 \"" + path + "\"", path, 0);
  while (std::getline(in, line)) {
    ++lineno;
    std::smatch m;
    if (std::regex_search(line, m, include_re)) {
      append_file(m[1].str(), a);
      a.add_line("#line " + std::to_string(lineno + 1) + " \"" + path + "\"", path, 0);
    } else if (std::regex_search(line, pragma_once_re)) {
      a.add_line("", path, lineno);
    } else {
      a.add_line(line, path, lineno);
    }
  }
}

}  // namespace

void LineMap::push(const std::string& file, int line) {
  auto it = std::find(files_.begin(), files_.end(), file);
  if (it == files_.end()) it = files_.insert(files_.end(), file);
  lines_.emplace_back(static_cast<int>(it - files_.begin()), line);
}

bool LineMap::find(int line, SourceLocation* out) const {
  if (line < 1 || line > size() || lines_[line - 1].second == 0) return false;
  out->file = files_[lines_[line - 1].first];
  out->line = lines_[line - 1].second;
  return true;
}

AssembledSource assemble_kernel_source_mapped(const std::string& root) {
  Assembly a;
  append_file(root, a);
  return std::move(a.out);
}

std::string assemble_kernel_source(const std::string& root) {
  return assemble_kernel_source_mapped(root).text;
}

std::string map_build_log(const std::string& log, const LineMap& lines) {
  // A placeholder name in angle brackets anywhere, or nothing at the start of a line, then :L:C.
  static const std::regex ref_re(R"((<[A-Za-z _-]*>|^):(\d{1,9}):(\d{1,9}))");
  std::string out;
  std::istringstream in(log);
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    if (!first) out += '\n';
    first = false;
    auto last = line.cbegin();
    for (std::sregex_iterator it(line.begin(), line.end(), ref_re), end; it != end; ++it) {
      const std::smatch& m = *it;
      SourceLocation loc;
      out.append(last, m[0].first);
      if (lines.find(std::stoi(m[2].str()), &loc))
        out += loc.file + ":" + std::to_string(loc.line) + ":" + m[3].str();
      else
        out.append(m[0].first, m[0].second);
      last = m[0].second;
    }
    out.append(last, line.cend());
  }
  if (!log.empty() && log.back() == '\n') out += '\n';
  return out;
}

}  // namespace lorgnette::cl
