#include "cli/conversion_key.h"

#include <cstdio>

#include "containers/sha256.h"
#include "io/image_io.h"

#ifndef AHD_VERSION_STRING
#error "AHD_VERSION_STRING must be defined (CMakeLists.txt)"
#endif

namespace ahd::cli {

namespace {

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

}  // namespace

std::string conversion_key_text(const InputArgs& in, const ConversionOptions& o, const std::string& out_name,
                                const InputRecord& record) {
  std::string t = "ahdpack-conversion-key " + std::to_string(kKeyFormat) + "\n";
  t += "version " AHD_VERSION_STRING "\n";
  // Output naming.
  t += "name " + out_name + "\n";
  t += std::string("container ") + (o.container == ContainerKind::DDS ? "dds" : "ktx2") + "\n";
  // ConversionOptions: every field that reaches the bytes (threads, progress and cancel do not).
  t += "profile " + o.profile + "\n";
  t += "profile_json " + sha256_hex(reinterpret_cast<const uint8_t*>(o.profile_json.data()), o.profile_json.size()) + "\n";
  t += "ratio " + std::string(!o.ratio ? "profile" : *o.ratio == RatioForm::Rgb ? "rgb" : "luminance") + "\n";
  t += "direction_fit " + std::to_string(int(o.direction_fit)) + "\n";
  t += "bc6h_quality " + std::to_string(int(o.bc6h_quality)) + "\n";
  t += "eps " + num(o.eps) + "\n";
  t += "closed_loop " + std::to_string(int(o.closed_loop)) + "\n";
  t += "levels " + std::to_string(o.levels) + "\n";
  t += "coverage_plane " + std::to_string(int(o.coverage_plane)) + "\n";
  t += "direction " + std::to_string(int(o.direction)) + "\n";
  t += "ambient_threshold " + num(o.ambient_threshold) + "\n";
  t += "zstd " + std::to_string(int(o.zstd)) + "\n";
  t += "plane_metadata " + std::to_string(int(o.plane_metadata)) + "\n";
  t += "measure " + std::to_string(int(o.measure)) + "\n";
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
  for (const std::string& f : record.files) {
    const std::vector<uint8_t> bytes = read_file_bytes(f);
    t += "read " + std::to_string(bytes.size()) + " " + sha256_hex(bytes.data(), bytes.size()) + "\n";
  }
  return t;
}

std::string conversion_key(const std::string& key_text) {
  return sha256_hex(reinterpret_cast<const uint8_t*>(key_text.data()), key_text.size());
}

}  // namespace ahd::cli
