#include "cli/report.h"

namespace ahd::cli {

void print_error_header(std::FILE* out) {
  std::fprintf(out, "  %-28s %-29s  %-29s  %s\n", "", "relative RMSE (mean p99 max)", "log2 RMSE (mean p99 max)",
               "I_z rel (max)");
}

void print_error_row(std::FILE* out, const char* label, const ErrorReport& e) {
  std::fprintf(out, "  %-28s %8.2e %8.2e %8.2e   %8.2e %8.2e %8.2e   %8.2e", label, e.relative.mean, e.relative.p99,
               e.relative.max, e.log2.mean, e.log2.p99, e.log2.max, e.normal_rel.max);
  if (e.negative) std::fprintf(out, "   (%zu texels with negative colours)", e.negative);
  std::fprintf(out, "\n");
}

}  // namespace ahd::cli
