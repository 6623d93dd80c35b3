#include "cli/report_file.h"

#include "core/error.h"
#include "io/image_io.h"

namespace ahd::cli {

namespace {

// The deepest nesting of [ and { outside strings, stopping once past `limit`. Brackets that do not
// balance are left to the parser to refuse.
int nesting_depth(const std::string& t, int limit) {
  int depth = 0, deepest = 0;
  bool in_string = false;
  for (size_t i = 0; i < t.size() && deepest <= limit; ++i) {
    const char c = t[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return deepest;
}

}  // namespace

nlohmann::json parse_report_json(const std::string& text, const std::string& path) {
  if (nesting_depth(text, kMaxReportDepth) > kMaxReportDepth)
    throw file_error(path, "is not a report (nested deeper than " + std::to_string(kMaxReportDepth) + " levels)");
  nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) throw file_error(path, "is not a report (not a JSON object)");
  return j;
}

nlohmann::json read_report_file(const std::string& path) {
  const std::vector<uint8_t> bytes = read_file_bytes(path, kMaxReportBytes);
  return parse_report_json(std::string(bytes.begin(), bytes.end()), path);
}

}  // namespace ahd::cli
