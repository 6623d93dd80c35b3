// Manifests and their planes on disk: the file-system edge of pipeline/manifest.h.
#pragma once
#include <string>

#include "pipeline/manifest.h"

namespace ahd {

// Reads (at most 16 MiB) and validates a manifest file.
Manifest read_manifest_file(const std::string& path);

// Reads one plane of a manifest at `manifest_path`: the file's byte size and SHA-256 must be the
// manifest's (else "<plane file>: does not match the manifest …": a set mixed by an interrupted
// write or edited by hand is reported, never decoded), then it must hold the format, size and
// level count the manifest states. Throws ahd::Error naming the file.
Texture read_manifest_plane(const std::string& manifest_path, const ManifestPlane& plane);

}  // namespace ahd
