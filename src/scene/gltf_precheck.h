// A bounded pre-pass over a glTF (.gltf / .glb) file before Assimp walks it. Assimp recurses once
// per node level (a 20 000-deep chain of nodes overflowed its stack) and trusts buffer byteLength
// fields; this scan refuses such files with one error line first. JSON is parsed only after its
// nesting depth is known to be small, and the node graph is walked with an explicit stack.
#pragma once
#include <cstddef>
#include <string>

namespace ahd {

// The deepest node chain accepted: real scenes are a few dozen levels deep; Assimp itself
// survived 10 000 levels and crashed at 20 000.
constexpr size_t kMaxGltfNodeDepth = 1024;
// The deepest JSON nesting accepted (glTF itself needs about 8).
constexpr size_t kMaxGltfJsonDepth = 128;

// Throws ahd::Error("<path>: <cause>") when the glTF's JSON nests deeper than kMaxGltfJsonDepth,
// its node graph is deeper than kMaxGltfNodeDepth or has a cycle or a child index out of range,
// or a buffer claims more bytes (byteLength) than its data has (GLB BIN chunk, data: URI, or the
// file it names). Safe on untrusted input; reads the .gltf/.glb (bounded by read_file_bytes) and
// only the sizes of external buffers. Other extensions: no check.
void check_gltf_structure(const std::string& path);

}  // namespace ahd
