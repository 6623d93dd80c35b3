// The conversion report (NAME.report.json) as JSON: fit rules, errors per stage and level, codec
// clamps, the direction decision, seconds per stage; the input's L1 figures and the warnings; for
// an atlas, every page's totals and each page's own figures (docs/container-format.md "The report").
#pragma once
#include <nlohmann/json.hpp>

#include "fit/hemisphere_error.h"
#include "pipeline/convert.h"

namespace ahd {

nlohmann::json error_json(const ErrorReport& e);
nlohmann::json convert_report_json(const PipelineResult& r, double total_seconds);

}  // namespace ahd
