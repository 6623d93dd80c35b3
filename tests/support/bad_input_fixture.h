// What the first bad-input round's tests share (tests/unit and tests/integration bad_input_test.cpp).
#pragma once
#include <gtest/gtest.h>
#include <zstd.h>
#include <sys/wait.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include "files/manifest_file.h"
#include "files/container_file.h"
#include "files/profile_file.h"
#include "cli_runner.h"
#include "file_bytes.h"
#include "sanitized.h"
#include "containers/container.h"
#include "containers/dds.h"
#include "containers/ktx2.h"
#include "containers/limits.h"
#include "containers/sha256.h"
#include "core/error.h"
#include "image/ahd_intermediate.h"
#include "bakers/baker_layout.h"
#include "image/image_io.h"
#include "scene/mesh_io.h"
#include "files/output_set.h"
#include "image/sh_exr.h"
#include "pipeline/convert.h"
#include "pipeline/manifest.h"
#include "sample/analytic_baker.h"

namespace ahd_fixture::bad_input_fixture {

namespace fs = std::filesystem;
using namespace ::ahd;

using ahd_test::slurp;
using ahd_test::spit;
using ahd_test::wr32;
using ahd_test::wr64;


inline Texture plain_texture(PixelFormat f, uint32_t w, uint32_t h, size_t levels = 1) {
  Texture t;
  t.format = f;
  for (size_t l = 0; l < levels; ++l) {
    TextureLevel lv;
    lv.width = std::max(1u, w >> l);
    lv.height = std::max(1u, h >> l);
    lv.data.assign(level_size_bytes(f, lv.width, lv.height), uint8_t(0x3C + l));
    t.levels.push_back(std::move(lv));
  }
  return t;
}

// Every file under `d` with its bytes: "no new file, previous outputs untouched" compares these.
inline std::map<std::string, std::vector<uint8_t>> snapshot_tree(const fs::path& d) {
  std::map<std::string, std::vector<uint8_t>> m;
  for (auto it = fs::recursive_directory_iterator(d); it != fs::recursive_directory_iterator(); ++it)
    if (it->is_regular_file()) m[it->path().string()] = slurp(it->path());
  return m;
}

// A valid uncompressed conversion of a 8x8 sample written to d/prev.* through the same library
// calls as `ahdpack convert`: the "previous outputs" every case must leave untouched.
inline Manifest write_previous_set(const fs::path& d, const std::string& name = "prev", const std::string& ext = "ktx2") {
  BakerOptions bo;
  bo.width = bo.height = 8;
  PipelineResult r = run_conversion(bake_analytic_scene(bo), load_profile("uncompressed"), {});
  Manifest m;
  m.profile = "uncompressed";
  m.container = ext;
  m.width = m.height = 8;
  m.levels = uint32_t(r.planes[0].texture.levels.size());
  std::vector<FileToPublish> files;
  for (Plane& p : r.planes) {
    p.texture.metadata = plane_metadata(m, p.name);
    std::vector<uint8_t> bytes = encode_container(ext == "dds" ? ContainerKind::DDS : ContainerKind::KTX2, p.texture);
    ManifestPlane mp{p.name, plane_file_name(name, p.name, ext, bytes), p.texture.format, 8, 8, m.levels,
                     bytes.size(), sha256_hex(bytes.data(), bytes.size())};
    m.planes.push_back(mp);
    files.push_back({(d / mp.file).string(), std::move(bytes)});
  }
  const std::string text = manifest_to_json(m);
  files.push_back({(d / (name + ".json")).string(), std::vector<uint8_t>(text.begin(), text.end())});
  publish_output_set(files);
  return m;
}

// Reads a manifest and decodes its planes as `ahdpack decode` does.
inline DecodedPlanes decode_manifest(const std::string& path, int level = 0) {
  const Manifest m = read_manifest_file(path);
  std::vector<Plane> planes;
  for (const auto& mp : m.planes) planes.push_back({mp.name, read_manifest_plane(path, mp)});
  return decode_planes(planes, m.ratio_form == RatioForm::Rgb, level);
}

struct Case {
  std::string name;
  // Makes the bad input in `d` and returns the call that must fail, and the file it must name.
  std::function<std::pair<std::function<void()>, std::string>(const fs::path& d)> make;
  std::string cause;  // a piece of the cause
};


// A canonical L1 SH EXR of w×h texels, every coefficient `value`.
inline void write_sh(const fs::path& p, int w, int h, float value) {
  ShImage sh = make_sh_image(w, h, 4);
  for (size_t i = 0; i < sh.texels(); ++i)
    for (int j = 0; j < 12; ++j) sh.texel(i)[j] = value;
  write_canonical_sh(p.string(), sh);
}

}  // namespace ahd_fixture::bad_input_fixture
