// What Godot records beside a LightmapGI bake, read without Godot: the importer's slice count
// (NAME.exr.import), the engine version (project.godot) and the property names of the binary
// LightmapGIData resource (NAME.lmbake). Only text facts are read; the .lmbake's values are not
// decoded (its property names tell which Godot generation wrote it).
#pragma once
#include <string>
#include <vector>

namespace ahd {

struct GodotImport {
  bool found = false;          // NAME.exr.import exists
  std::string importer;        // e.g. "2d_array_texture"
  int slices_vertical = 0;     // [params] slices/vertical (0 when absent)
  int slices_horizontal = 0;   // [params] slices/horizontal
};

// Reads `exr_path` + ".import". Missing file: found = false. Throws ahd::Error("<file>: <cause>")
// for a slice count that is not a positive integer.
GodotImport read_godot_import(const std::string& exr_path);

// The engine version of the project holding `path` ("4.2"), from config/features of the nearest
// project.godot in `path`'s folder or above; empty when none is found. *project_file gets its path.
std::string godot_project_version(const std::string& path, std::string* project_file = nullptr);

// Whether a Godot version string ("4.2", "4.4.1") stores packed L1 (4.4 and later): 1 packed,
// 0 raw signed (4.0–4.3), −1 unknown (not a 4.x version).
int godot_version_packs_l1(const std::string& version);

// The property names of a Godot binary resource (.lmbake, .res): the strings of its string table
// as they appear in the file. Empty when the file is missing or not an RSRC file.
std::vector<std::string> godot_resource_names(const std::string& path);

}  // namespace ahd
