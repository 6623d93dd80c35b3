// Printing what a conversion cost and what error it added (terminal text; the JSON report is
// pipeline/report_json.h).
#pragma once
#include <cstdio>
#include <string>

#include "fit/hemisphere_error.h"
#include "pipeline/convert.h"

namespace ahd::cli {

// One row of the error table: "name  mean p99 max" for relative and log2 errors.
void print_error_row(std::FILE* out, const char* label, const ErrorReport& e);
void print_error_header(std::FILE* out);

}  // namespace ahd::cli
