// Reading a conversion's report (NAME.report.json) back, for `preview`: untrusted text (anyone
// can edit the file), so bounded in size and nesting before nlohmann's parser and the page's
// recursive rendering see it.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

namespace ahd::cli {

// Deepest nesting of arrays and objects accepted in a report (ours nest 4 deep).
inline constexpr int kMaxReportDepth = 64;
// Largest report file read (ours are a few KiB).
inline constexpr size_t kMaxReportBytes = size_t(16) << 20;

// Parses `text` as a report: a JSON object nested at most kMaxReportDepth deep (checked by a scan
// of the text before parsing, so nothing recursive ever sees a deeper value). Throws
// ahd::Error("<path>: <cause>"). Safe on any bytes.
nlohmann::json parse_report_json(const std::string& text, const std::string& path);

// Reads (at most kMaxReportBytes) and parses a report file. Throws ahd::Error naming it.
nlohmann::json read_report_file(const std::string& path);

}  // namespace ahd::cli
