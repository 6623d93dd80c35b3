// Which atlas page a Unity or Bakery lightmap file is, from its name: Unity writes page N as
// `Lightmap-N_comp_light.exr` / `_comp_dir.png` (LightmapSettings.lightmaps[N], the page a
// renderer's `m_LightmapIndex` / Renderer.lightmapIndex names), Bakery as `Scene_LMN_L0.hdr` ….
// A placement (Unity scene YAML, the editor script's JSON) names pages by that index, so a file of
// page 1 must select the instances of page 1.
#pragma once
#include <string>

namespace ahd {

// The page N named by the file name of `path` (any directory is ignored): a name starting with
// `Lightmap-N` followed by `_`, `.` or the end, or holding `_LMN` followed by `_`, `.` or the end.
// −1 when the name says nothing. *why (optional) names the rule that matched. Pure.
int lightmap_page_from_name(const std::string& path, std::string* why = nullptr);

}  // namespace ahd
