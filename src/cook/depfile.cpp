#include "cook/depfile.h"

#include <filesystem>

#include "core/error.h"
#include "files/output_set.h"

namespace ahd {
namespace fs = std::filesystem;

namespace {

std::string escaped(const std::string& path) {
  std::string out;
  for (char c : path) {
    if (c == '\n' || c == '\r') throw file_error(path, "a path with a line break cannot be written to a depfile");
    if (c == ' ' || c == '#') out += '\\';
    if (c == '$') out += '$';
    out += c;
  }
  return out;
}

}  // namespace

std::string depfile_text(const std::string& target, const std::vector<std::string>& deps) {
  std::string text = escaped(target) + ":";
  for (const std::string& d : deps) text += " \\\n  " + escaped(fs::absolute(d).lexically_normal().string());
  return text + "\n";
}

void write_depfile(const std::string& path, const std::string& target, const std::vector<std::string>& deps) {
  write_file_atomic(path, depfile_text(target, deps));
}

}  // namespace ahd
