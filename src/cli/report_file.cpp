#include "cli/report_file.h"

#include "core/error.h"
#include "core/json_depth.h"
#include "files/file_io.h"

namespace ahd::cli {


nlohmann::json parse_report_json(const std::string& text, const std::string& path) {
  if (json_nesting_depth(text.data(), text.size(), kMaxReportDepth) > size_t(kMaxReportDepth))
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
