// A fit's result as placement.json's contents: the pipeline's figures (fit.h FitResult) mapped onto
// the file's fields (placement_json.h). It lives beside the pipeline so that the file's owner
// (placement_json) knows nothing of the pipeline that fills it.
#pragma once
#include <string>

#include "fit/fit.h"
#include "fit/placement_json.h"

namespace lorgnette::fit {

// `glasses_path` is recorded with its content hash (file_hash) when not empty; `scale_policy` is
// the name the file stores ("stretch" or "true-size").
PlacementFile make_placement_file(const FitResult& r, const std::string& glasses_path,
                                  const std::string& scale_policy);

}  // namespace lorgnette::fit
