// What the API tells a client about its job: the paths of the files it can fetch, and text without
// any path on the server. Where the server keeps files (its data folder, the shop's catalogue) is
// not the client's business: a worker's message such as a loader's "cannot load mesh
// '/srv/shop/catalogue/round.glb': ..." reaches the client naming the file by its name only, and
// the capture folder's inner files (the model, the dataset), which the API never serves, are not
// listed.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

namespace lorgnette::service {

// `text` with every absolute path replaced by its last component (the file's or folder's name). A
// path starts with '/' at the start of the text or after a space, a quote, '(', '[' or '=', and
// ends at its closing quote when quoted, else at the next space, less any trailing ':,;.)]'.
std::string without_server_paths(const std::string& text);

// The job's artifacts as a client sees them: `preview`, `views` and `fits` (the capture-relative
// paths GET .../artifacts/{path} serves), `unavailable` (frame name -> why, without server paths)
// and `pending` (frame names); nothing else.
nlohmann::json client_artifacts(const nlohmann::json& artifacts);

}  // namespace lorgnette::service
