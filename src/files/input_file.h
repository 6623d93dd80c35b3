// The one opener of reader input files: regular files only (a device, FIFO or socket is refused
// without blocking), bounded by a size per kind, read whole into memory once and noted in the
// current input record (files/input_record.h). Readers parse the bytes this returns, never the
// path again, so what a pre-check saw is what the parser reads (docs/robustness-input.md
// "Reader input files").
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ahd {

// What a file is read as; each kind has its own size bound (input_file_bound).
enum class InputKind {
  kImage,        // EXR, HDR, PNG, TGA… (image/)
  kText,         // profiles, placements, layout presets, manifests: JSON and small text
  kSceneText,    // Godot project.godot, .tscn, .tres, .import
  kLmbake,       // Godot .lmbake (binary resource)
  kUnwrapCache,  // Godot NAME.glb.unwrap_cache
  kMesh,         // .glb, .gltf and its buffers, .obj, .fbx, .res mesh resources
};

// The largest file of `kind` read (bytes): far above any real one, below what would exhaust memory.
size_t input_file_bound(InputKind kind);

// Reads `path` whole. Throws ahd::Error("<path>: <cause>"): "file not found", "not a regular file"
// (checked before the open and again on the open descriptor, which is opened O_NONBLOCK so a FIFO
// swapped in between never blocks), "file too large (N bytes, at most M are read)", a read error,
// or a file shorter than its size said. Notes `path` in the input record once read. Thread safe.
std::vector<uint8_t> read_input_bytes(const std::string& path, size_t max_bytes);
inline std::vector<uint8_t> read_input_bytes(const std::string& path, InputKind kind) {
  return read_input_bytes(path, input_file_bound(kind));
}

// read_input_bytes of the first `head_bytes` only (the whole file when it is shorter), with the
// same checks and errors, the file's size in `*file_bytes` (may be null): a header read without
// reading a whole file (image_io.h's read_image_info; the pixels are read whole later). Thread safe.
std::vector<uint8_t> read_input_head(const std::string& path, size_t max_bytes, size_t head_bytes,
                                     uint64_t* file_bytes);

// Whether `path` exists (following symlinks), for readers deciding what to read: false when it is
// absent, ahd::Error("<path>: symbolic links loop …") for a symlink loop (std::filesystem::exists
// threw, which surfaced as an internal error), never blocks. Noted in the input record as an
// existence test (probe_input_file, files/input_record.h), not as a file read.
bool input_exists(const std::string& path);

// read_input_bytes as a string (text files).
std::string read_input_text(const std::string& path, InputKind kind);

}  // namespace ahd
