#include "cook/depfile.h"

#include <cctype>
#include <filesystem>

#include "core/error.h"
#include "files/output_set.h"
#include "files/utf8_path.h"

namespace ahd {
namespace fs = std::filesystem;

namespace {

// One path as GNU Make (4.3) and Ninja (1.11, src/depfile_parser.in.cc) both read it, checked
// with both (Cook.DepfileRebuildsWithMakeAndNinja):
//  - space, '#', ':' (not a Windows drive's): a backslash before them (Make's read.c quotes them,
//    Ninja's parser de-escapes "\\ ", "\\#" and, as a plain span followed by no blank, keeps ':');
//  - '$': "$$" (Make expands variables; Ninja's parser undoes the doubling);
//  - a backslash followed by an ordinary character: verbatim (both pass it through);
//  - refused (one error line, nothing written), as no spelling reads the same in both: control
//    characters (newline, tab), ';' (Make: the recipe follows, a command runs), '|' (Make:
//    order-only prerequisites), '*' '?' '[' ']' (Make: wildcards), '%' (Make: a pattern rule), '='
//    (Make: a target-specific variable), quotes, '&', '<', '>', '`', '^', DEL (Ninja ends a path
//    there), a backslash before a space, '#', ':', '$', a backslash or the path's end (the two
//    halve or keep backslash runs differently), a path starting with '~' (Make: a home folder) or
//    ending in ')' with a '(' (Make: an archive member).
std::string escaped(const std::string& path) {
  const auto refuse = [&path](const std::string& why) {
    throw file_error(path, "cannot be written to a depfile: " + why + " (rename the file or folder)");
  };
  if (path.empty()) refuse("an empty path");
  if (path[0] == '~') refuse("a leading '~' (Make reads a home folder)");
  if (path.back() == ')' && path.find('(') != std::string::npos) refuse("Make reads \"a(b)\" as an archive member");
  std::string out;
  for (size_t i = 0; i < path.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(path[i]);
    if (c < 0x20 || c == 0x7f) refuse(c == '\n' || c == '\r' ? "a line break" : c == '\t' ? "a tab" : "a control character");
    if (std::string(";|*?[]%=\"'&<>`^").find(char(c)) != std::string::npos)
      refuse(std::string("the character '") + char(c) + "', which Make or Ninja reads as syntax");
    if (c == '\\' && (i + 1 == path.size() || std::string(" #:$\\").find(path[i + 1]) != std::string::npos))
      refuse("a backslash before a space, '#', ':', '$', a backslash or the end");
#ifdef _WIN32
    const bool drive = c == ':' && i == 1 && std::isalpha(static_cast<unsigned char>(path[0]));
#else
    const bool drive = false;  // "C:/x" on POSIX is a relative path whose colon Make must not see
#endif
    if ((c == ' ' || c == '#' || c == ':') && !drive) out += '\\';
    if (c == '$') out += '$';
    out += char(c);
  }
  return out;
}

}  // namespace

std::string depfile_text(const std::string& target, const std::vector<std::string>& deps) {
  std::string text = escaped(target) + ":";
  for (const std::string& d : deps) text += " \\\n  " + escaped(utf8_string(fs::absolute(fs_path(d)).lexically_normal()));
  return text + "\n";
}

void write_depfile(const std::string& path, const std::string& target, const std::vector<std::string>& deps) {
  write_file_atomic(path, depfile_text(target, deps));
}

}  // namespace ahd
