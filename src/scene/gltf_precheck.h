// A bounded pre-pass over a glTF (.gltf / .glb) file before Assimp walks it. Assimp recurses once
// per node level (a 20 000-deep chain of nodes overflowed its stack) and trusts buffer byteLength
// fields; this scan refuses such files with one error line first. JSON is parsed only after its
// nesting depth is known to be small, and the node graph is walked with an explicit stack.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

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

// The same checks on the file's bytes as read (`path` names it in messages and its extension picks
// the check; other extensions: none). `buffer_bytes(p)` gives the size of the external buffer file
// `p` (a path beside `path`), or −1 when it cannot be read (Assimp then names it). Also refuses an
// accessor whose elements (count × element size) exceed 16 × the input's bytes + 1 MiB or whose
// sparse count exceeds its count (a sparse accessor's count is otherwise unchecked: 1.4 KB asked
// for 2.4 GB), and a scene whose nodes instance more than kMaxSceneVertices vertices or
// kMaxSceneIndices indices in all (each node holding a mesh is a copy of it).
void check_gltf_bytes(const std::string& path, const std::vector<uint8_t>& bytes,
                      const std::function<int64_t(const std::string&)>& buffer_bytes);

}  // namespace ahd
