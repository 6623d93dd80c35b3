// Reports given to `preview` (seeds: the golden reports): read_report_file's parser with its size
// and nesting bounds, then the page. Whatever the report holds, the page has exactly the one
// <script> element preview writes itself: no value reaches the page unescaped.
#include <string>

#include "cli/preview_html.h"
#include "cli/report_file.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  ahd_fuzz::expect_clean([&] {
    ahd::cli::PreviewPage page;
    page.name = "fuzz";
    page.manifest.width = page.manifest.height = 4;
    page.report = ahd::cli::parse_report_json(std::string(reinterpret_cast<const char*>(data), size), "fuzz.report.json");
    const std::string html = ahd::cli::preview_html(page);
    size_t scripts = 0;
    for (size_t at = html.find("<script"); at != std::string::npos; at = html.find("<script", at + 1)) ++scripts;
    if (scripts != 1 || html.find("</textarea") != std::string::npos) __builtin_trap();
  });
  return 0;
}
