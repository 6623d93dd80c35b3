// Text for the HTML and SVG the CLI writes (preview page, plots).
#pragma once
#include <string>

namespace ahd::cli {

// `s` with &, <, >, " and ' escaped: safe inside XML/HTML text and quoted attributes (never inside
// <script> or <style>, where the page puts none of its data).
std::string xml_escape(const std::string& s);

// One number printed with a printf format taking one double (e.g. "%.3g").
std::string format_number(double v, const char* format);

}  // namespace ahd::cli
