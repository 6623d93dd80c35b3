#include "bakers/godot/godot_import.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "files/input_file.h"
#include "files/input_record.h"
#include "files/utf8_path.h"

namespace ahd {
namespace fs = std::filesystem;

namespace {

std::string trim(std::string s) {
  const auto a = s.find_first_not_of(" \t\r");
  const auto b = s.find_last_not_of(" \t\r");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

std::string unquote(std::string s) {
  s = trim(s);
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
  return s;
}

int positive_int(const std::string& file, const std::string& key, const std::string& value) {
  try {
    size_t used = 0;
    const int n = std::stoi(value, &used);
    if (used == value.size() && n > 0) return n;
  } catch (const std::exception&) {
  }
  throw file_error(file, key + " is '" + value + "', not a positive integer");
}

}  // namespace

GodotImport read_godot_import(const std::string& exr_path) {
  GodotImport gi;
  const std::string path = exr_path + ".import";
  if (!probe_regular_file(path)) return gi;  // absent: a fact the conversion depends on, too
  std::istringstream f(read_input_text(path, InputKind::kSceneText));  // the opener (files/input_file.h)
  gi.found = true;
  std::string line, section;
  while (std::getline(f, line)) {
    line = trim(line);
    if (line.empty() || line[0] == ';') continue;
    if (line.front() == '[') {
      section = line;
      continue;
    }
    const auto eq = line.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = trim(line.substr(0, eq)), value = unquote(line.substr(eq + 1));
    if (section == "[remap]" && key == "importer") gi.importer = value;
    if (section == "[params]" && key == "slices/vertical") gi.slices_vertical = positive_int(path, key, value);
    if (section == "[params]" && key == "slices/horizontal") gi.slices_horizontal = positive_int(path, key, value);
  }
  return gi;
}

std::string godot_project_version(const std::string& path, std::string* project_file) {
  fs::path dir = fs::absolute(fs_path(path)).parent_path();
  for (int up = 0; up < 32 && !dir.empty(); ++up) {
    const fs::path p = dir / "project.godot";
    if (probe_input_file(utf8_string(p))) {
      std::istringstream f(read_input_text(utf8_string(p), InputKind::kSceneText));
      std::string line;
      while (std::getline(f, line)) {
        // config/features=PackedStringArray("4.2", "Forward Plus")
        if (line.rfind("config/features", 0) != 0) continue;
        const auto q = line.find('"');
        const auto e = q == std::string::npos ? q : line.find('"', q + 1);
        if (e == std::string::npos) break;
        if (project_file) *project_file = utf8_string(p);
        return line.substr(q + 1, e - q - 1);
      }
      return "";
    }
    if (dir == dir.parent_path()) break;
    dir = dir.parent_path();
  }
  return "";
}

int godot_version_packs_l1(const std::string& version) {
  int major = 0, minor = 0;
  if (std::sscanf(version.c_str(), "%d.%d", &major, &minor) != 2 || major != 4) return -1;
  return minor >= 4 ? 1 : 0;
}

std::vector<std::string> godot_resource_names(const std::string& path) {
  std::vector<std::string> names;
  if (!probe_regular_file(path)) return names;
  std::istringstream f(read_input_text(path, InputKind::kLmbake));
  char magic[4] = {};
  if (!f.read(magic, 4) || std::string(magic, 4) != "RSRC") return names;
  // Property names are stored as length-prefixed identifiers; collecting the printable runs of
  // identifier characters finds them without decoding the resource's values.
  std::string run;
  char c;
  while (f.get(c)) {
    const bool ident = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
    if (ident) {
      run += c;
    } else {
      if (run.size() >= 4) names.push_back(run);
      run.clear();
    }
  }
  if (run.size() >= 4) names.push_back(run);
  return names;
}

}  // namespace ahd
