// Godot's side files: byte 0 picks the reader, the rest is the file. 0: NAME.exr.import (INI-like
// text, read_godot_import); 1: NAME.lmbake (binary resource, godot_resource_names); 2: the
// project.godot version line (godot_project_version). Seeds: minimal files from scripts/fuzz.sh.
#include "fuzz_common.h"
#include "bakers/godot/godot_import.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const int which = data[0] % 3;
  if (which == 0) {
    const std::string imp = ahd_fuzz::write_temp(data + 1, size - 1, ".exr.import");
    const std::string exr = imp.substr(0, imp.size() - 7);
    ahd_fuzz::expect_clean([&] { ahd::read_godot_import(exr); });
  } else if (which == 1) {
    const std::string p = ahd_fuzz::write_temp(data + 1, size - 1, ".lmbake");
    ahd_fuzz::expect_clean([&] { ahd::godot_resource_names(p); });
  } else {
    ahd_fuzz::expect_clean([&] { ahd::godot_version_packs_l1(std::string(reinterpret_cast<const char*>(data + 1), size - 1)); });
  }
  return 0;
}
