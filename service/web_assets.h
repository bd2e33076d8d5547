// The shopper's pages (HTML, JS, CSS from service/web/: upload, status, try-on), embedded at build
// time by viewer/embed_assets.cmake and served by `lorgnette serve` under "/<relative path>".
#pragma once
#include <map>
#include <string>

#include "viewer/web_assets.h"

namespace lorgnette::service {

using viewer::WebAsset;

const std::map<std::string, WebAsset>& web_assets();

}  // namespace lorgnette::service
