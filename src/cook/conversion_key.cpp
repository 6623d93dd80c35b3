#include "cook/conversion_key.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <vector>

#include "api/option_table.h"
#include "containers/sha256.h"
#include "core/error.h"
#include "files/file_io.h"
#include "files/regular_file.h"
#include "files/paths.h"
#include "files/utf8_path.h"

#ifndef AHD_VERSION_STRING
#error "AHD_VERSION_STRING must be defined (CMakeLists.txt)"
#endif

namespace ahd {

std::string conversion_options_text(const BakeInput& in, const ConversionOptions& o, const std::string& out_name) {
  std::string t = "ahdpack-conversion-key " + std::to_string(kKeyFormat) + "\n";
  t += "version " AHD_VERSION_STRING "\n";
  // Output naming.
  t += "name " + out_name + "\n";
  // ConversionOptions: every option the table puts in the key (api/option_table.h; not threads,
  // progress, cancel), the container first; an option added later (iz_scale) only when set.
  for (const OptionRow& r : option_table())
    if (option_in_key(r, o)) t += std::string(r.name) + " " + r.key_text(o) + "\n";
  // The input's options (which role each file plays; the files themselves follow).
  t += "input " + std::string(in.input.empty() ? "sample" : "files") + "\n";
  if (in.input.empty())
    t += "sample " + std::to_string(in.sample_size) + " " + std::to_string(in.sample_order) + " " + std::to_string(in.seed) + "\n";
  // A preset given as a .json file: its bytes are in the record, its path is not part of the key.
  const bool layout_file = in.layout.size() > 5 && in.layout.compare(in.layout.size() - 5, 5, ".json") == 0;
  t += "layout " + (layout_file ? std::string("(file)") : in.layout) + "\n";
  t += "normals " + std::to_string(int(!in.normals.empty())) + "\n";
  t += "mesh " + std::to_string(int(!in.mesh.empty())) + " uv_set " + std::to_string(in.uv_set) + "\n";
  t += "placement " + std::to_string(int(!in.placement.empty())) + "\n";
  t += "pages " + std::to_string(in.pages) + "\n";
  // Godot's path and the mismatch gate change what is read and whether it converts; added only
  // when used so that other keys stay as they were.
  if (!in.scene.empty()) t += "godot_scene 1\n";
  if (in.allow_mismatch) t += "allow_mismatch 1\n";
  if (in.allow_unplaced) t += "allow_unplaced 1\n";
  if (!in.node.empty()) t += "node " + in.node + "\n";
  if (in.page >= 0) t += "page " + std::to_string(in.page) + "\n";
  if (!in.input_space.empty())
    t += "input_space " + in.input_space + "\n";  // the files' declarations are in their bytes
  return t;
}

// A file's content hash: SHA-256 of its 4 MiB chunks' SHA-256 digests (with the size beside it, as
// collision-resistant as SHA-256 of the whole), read through one reused buffer: a cache hit on a
// large EXR hashes it without holding it in memory. Only a regular file of at most
// kMaxHashedInputBytes is read (files/regular_file.h RegularFile: opened without blocking, checked by
// fstat): a record naming /dev/zero, a FIFO or a huge sparse file is an error (for a stored inputs
// record: a miss that reads the input again), never a read without end.
constexpr uint64_t kMaxHashedInputBytes = uint64_t(1) << 34;  // read_file_bytes' bound (files/file_io.h)

static std::string file_digest(const std::string& path, uint64_t* size) {
  RegularFile f(path, kMaxHashedInputBytes);
  std::vector<uint8_t> buf(size_t(std::min<uint64_t>(f.size(), uint64_t(4) << 20)));
  std::string digests;
  *size = 0;
  for (uint64_t left = f.size(); left > 0;) {
    const size_t n = size_t(std::min<uint64_t>(left, buf.size()));
    f.read(buf.data(), n);
    digests += sha256_hex(buf.data(), n);
    *size += n, left -= n;
  }
  return sha256_hex(reinterpret_cast<const uint8_t*>(digests.data()), digests.size());
}

std::string input_files_text(const std::vector<std::string>& files) {
  std::string t;
  for (const std::string& f : files) {
    uint64_t size = 0;
    const std::string digest = file_digest(f, &size);
    t += "read " + std::to_string(size) + " " + digest + "\n";
  }
  return t;
}

std::string conversion_key_text(const BakeInput& in, const ConversionOptions& o, const std::string& out_name,
                                const InputRecord& record) {
  return conversion_options_text(in, o, out_name) + input_files_text(record.files);
}

std::string command_key(const BakeInput& given, const ConversionOptions& o, const std::string& out_name,
                        const std::string& profile_arg) {
  std::error_code ec;
  std::string t = "ahdpack-command-key " + std::to_string(kKeyFormat) + "\n" + conversion_options_text(given, o, out_name);
  t += "input_path " + given.input + "\nlayout_arg " + given.layout + "\nnormals_path " + given.normals + "\nmesh_path " +
       given.mesh + "\nplacement_path " + given.placement +
       "\ngodot_scene_path " + given.scene + "\nprofile_arg " + profile_arg + "\ncwd " +
       utf8_string(std::filesystem::current_path(ec)) + "\nformats " + formats_dir() + "\n";
  return conversion_key(t);
}

std::string conversion_key(const std::string& key_text) {
  return sha256_hex(reinterpret_cast<const uint8_t*>(key_text.data()), key_text.size());
}

}  // namespace ahd
