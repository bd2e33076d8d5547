// Many file or frame names in one message: the first few, quoted, and how many more
// ("'a', 'b', 'c' and 4 more"), so an error about 300 missing images stays one readable line.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace lorgnette {

// The first `shown` names, each in single quotes, comma-separated, then " and N more" if any were
// left out; "" for no names.
std::string name_list(const std::vector<std::string>& names, size_t shown = 5);

}  // namespace lorgnette
