// Printing what a conversion cost and what error it added (terminal text and JSON).
#pragma once
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "fit/hemisphere_error.h"
#include "pipeline/convert.h"

namespace ahd::cli {

// One row of the error table: "name  mean p99 max" for relative and log2 errors.
void print_error_row(std::FILE* out, const char* label, const ErrorReport& e);
void print_error_header(std::FILE* out);

nlohmann::json error_json(const ErrorReport& e);
nlohmann::json convert_report_json(const ConvertResult& r, double total_seconds);

}  // namespace ahd::cli
