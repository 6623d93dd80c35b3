// The 3D view of `ahdpack preview` (view3d.html beside index.html): the conversion's planes light
// a mesh (--mesh) or the built-in sample's plane in WebGL2 through three.js, with the source SH and
// a plain lightmap for A/B/difference, a detail normal map, exposure, mip level and page, and the
// lightmap itself with the UV wireframe, coverage and a texel readout. Offline from file://: the
// page uses classic scripts only (three.js is turned into one from the installed ES modules).
#pragma once
#include <filesystem>
#include <string>

#include "bakers/scene_export.h"
#include "cli/conversion_view.h"
#include "sh/sh_image.h"

namespace ahd::cli {

// The folder of the three npm package (holding build/three.core.js and build/three.module.js):
// $AHD_THREE_DIR when set (then only there), else <formats>/../three (the installed share/ahdpack/three), else the source
// tree's tests/tools/node_modules/three. "" when none exists; `searched` lists where it looked.
std::string find_three(std::string* searched);

struct Preview3dInput {
  std::string manifest_path;
  std::string mesh_path;     // "" = the built-in sample's plane (a unit quad over the whole lightmap)
  int uv_set = -1;           // the mesh's lightmap UV set (read_mesh_lightmap's rule when −1)
  const ShImage* source = nullptr;  // the source SH (A/B, coverage, rules), or null
  // The input's placed scene (a Godot project, --mesh with --placement: bakers/scene_export.h), or
  // null: when it has triangles, the view shows it in place of mesh_path, each instance at its
  // atlas rectangle, the shown page's instances only.
  const PlacedSceneMesh* placed = nullptr;
};

// Writes view3d.html, view3d.js, view3d_data.js and three_classic.js as new files into `dir` (the
// preview's temporary folder, which its rename publishes) and returns the
// HTML (escaped) that index.html shows: a link to the view, or — when three.js cannot be found or
// the lightmap is too large for the page (more than 512² texels per page) — a note saying why, and
// nothing else is written. Throws ahd::Error("<file>: <cause>") for an unreadable mesh.
std::string write_preview_3d(const std::filesystem::path& dir, const Preview3dInput& in);

}  // namespace ahd::cli
