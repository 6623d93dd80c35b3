// Running a page in headless Chromium through tests/tools/chromium_cdp.mjs: it loads `url`
// (served from `serve` when given: "{origin}" in the url is its address), runs `script` in it and
// writes the script's result as JSON to `out` (and a screenshot when asked).
#pragma once
#include <filesystem>
#include <string>

#include "cli_runner.h"
#include "test_data.h"

namespace ahd_test {

struct ChromiumPage {
  std::filesystem::path serve;       // a folder served on 127.0.0.1, or empty (a file:// url)
  std::string url;                   // "{origin}/page/x.html" or "file:///…"
  std::filesystem::path script;      // the JavaScript run in the page, returning the result
  std::filesystem::path out;         // the result, as JSON
  std::filesystem::path screenshot;  // or empty
  int timeout_seconds = 90;
};

// Runs the page; returns what chromium_cdp.mjs printed (the result is in page.out).
inline std::string run_chromium_page(const ChromiumPage& page) {
  std::string cmd = "node '" + (kSourceDir / "tests" / "tools" / "chromium_cdp.mjs").string() + "' --chromium '" +
                    chromium_binary() + "'";
  if (!page.serve.empty()) cmd += " --serve '" + page.serve.string() + "'";
  cmd += " --url '" + page.url + "' --script '" + page.script.string() + "' --out '" + page.out.string() + "'";
  if (!page.screenshot.empty()) cmd += " --screenshot '" + page.screenshot.string() + "'";
  return run_shell(cmd + " --timeout " + std::to_string(page.timeout_seconds) + " 2>&1");
}

}  // namespace ahd_test
