// The OpenCL sources embedded at build time (kernels/**/*.cl, *.h) and their assembly into one
// translation unit: #include "x.h" lines are resolved from the embedded files (each at most once)
// and #line directives keep compiler messages pointing at the original file and line.
#pragma once
#include <map>
#include <string>

namespace lorgnette::cl {

// Path relative to kernels/ -> file text. Defined in the generated embedded_kernels.cpp.
const std::map<std::string, std::string>& embedded_kernel_files();

// The self-contained source for `root` (e.g. "hashgrid/hashgrid_encode.cl"). Include paths are
// relative to kernels/. Throws when a file or an include is missing.
std::string assemble_kernel_source(const std::string& root);

}  // namespace lorgnette::cl
