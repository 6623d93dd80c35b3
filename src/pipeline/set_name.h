// What a set's NAME may be (the stem of -o, the name given to ahd::convert / ahd_convert).
#pragma once
#include <cstddef>
#include <string>

namespace ahd {

// The longest set NAME: NAME.dirratio.<12 hex>.ktx2 and NAME.report.json stay well under the 255
// bytes a file name may have.
constexpr size_t kMaxSetNameBytes = 200;

// Why `name` cannot be a set's NAME ("" when it can), the one rule of the CLI (cook/publish.h
// output_paths) and the C/C++ API (api/options.h resolve_options): a plain file name
// (is_plain_file_name: not empty, not hidden, so not "." or "..", no '/', '\\', ':'), no control
// character (newline, tab), at most kMaxSetNameBytes bytes, and not ending in ".report": the set
// "room.report" would write room.report.json, the report of the set "room" in the same folder, and
// each would replace the other's file.
std::string set_name_problem(const std::string& name);

}  // namespace ahd
