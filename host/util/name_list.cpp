// Short lists of names for messages: see name_list.h.
#include "host/util/name_list.h"

#include <fmt/format.h>

namespace lorgnette {

std::string name_list(const std::vector<std::string>& names, size_t shown) {
  std::string out;
  for (size_t i = 0; i < names.size() && i < shown; ++i) out += (i ? ", '" : "'") + names[i] + "'";
  if (names.size() > shown) out += fmt::format(" and {} more", names.size() - shown);
  return out;
}

}  // namespace lorgnette
