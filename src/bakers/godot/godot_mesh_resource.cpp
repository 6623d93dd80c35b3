// A stub: the primitive-mesh and ArrayMesh decoders are written separately and replace it. Every
// instance routed here is left out with a note naming it and this cause.
#include "bakers/godot/godot_mesh_resource.h"

#include <filesystem>

#include "core/error.h"

namespace ahd {

MeshTriangles godot_sub_resource_mesh(const GodotTscnSub& sub, const std::string& source) {
  throw file_error(source, (sub.type.empty() ? std::string("untyped") : sub.type) + " meshes are not read yet");
}

MeshTriangles godot_mesh_resource_path(const std::string& path, const std::string& source) {
  const std::string ext = std::filesystem::path(path).extension().string();
  throw file_error(source, "mesh resource files (" + (ext.empty() ? path : ext) + ") are not read yet: " + path);
}

}  // namespace ahd
