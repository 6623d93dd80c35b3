// Reading atlas placements (scene/placement.h) from the files that record them:
// - ahdpack's JSON: {"placements": [{"node": "Chair", "page": 0, "scale": [sx, sy], "offset": [ox, oy]}, …]}
//   (atlas_uv = uv · scale + offset, v up);
// - a Unity scene (.unity, YAML): per MeshRenderer, m_LightmapIndex (the page; 65535 or −1 = not
//   lightmapped, skipped) and m_LightmapTilingOffset {x, y, z, w} = (scale x, y, offset x, y),
//   named by its GameObject's m_Name.
#pragma once
#include <string>
#include <vector>

#include "scene/placement.h"

namespace ahd {

// By content: a file starting with "%YAML" is a Unity scene, anything else ahdpack's JSON. Throws
// ahd::Error("<path>: <cause>") for a missing or malformed file, a renderer whose GameObject is
// missing, or no placement at all.
std::vector<Placement> read_placements(const std::string& path);

}  // namespace ahd
