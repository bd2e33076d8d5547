// Include resolution for embedded kernels; see kernel_sources.h.
#include "host/cl/kernel_sources.h"

#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>

namespace lorgnette::cl {
namespace {

void append_file(const std::string& path, std::set<std::string>& seen, std::string& out) {
  if (!seen.insert(path).second) return;  // every header is #pragma once by construction
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
  out += "#line 1 \"" + path + "\"\n";
  while (std::getline(in, line)) {
    ++lineno;
    std::smatch m;
    if (std::regex_search(line, m, include_re)) {
      append_file(m[1].str(), seen, out);
      out += "#line " + std::to_string(lineno + 1) + " \"" + path + "\"\n";
    } else if (std::regex_search(line, pragma_once_re)) {
      out += "\n";
    } else {
      out += line + "\n";
    }
  }
}

}  // namespace

std::string assemble_kernel_source(const std::string& root) {
  std::set<std::string> seen;
  std::string out;
  append_file(root, seen, out);
  return out;
}

}  // namespace lorgnette::cl
