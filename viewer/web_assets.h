// The viewer's page (HTML, JS, CSS from viewer/web/), embedded at build time by
// viewer/embed_assets.cmake and served by the HTTP server under "/<relative path>".
#pragma once
#include <map>
#include <string>

namespace lorgnette::viewer {

struct WebAsset {
  std::string content_type;
  std::string body;
};

const std::map<std::string, WebAsset>& web_assets();

}  // namespace lorgnette::viewer
