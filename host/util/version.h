// The version of this build: the project version from CMakeLists.txt and the git commit it was built
// from (cmake/GitVersion.cmake; "unknown" outside a git checkout, "-dirty" with uncommitted changes).
#pragma once

namespace lorgnette {
const char* version_string();
const char* git_commit();
}  // namespace lorgnette
