#include "lab/truth_file.h"

#include <Imath/half.h>

#include <algorithm>
#include <cstring>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <zstd.h>

#include "core/error.h"
#include "sh/sh.h"

namespace ahd {

namespace {

constexpr int kMaxSize = 4096;
constexpr size_t kMaxNormals = 1024;

std::string read_small_file(const std::string& path, size_t max_bytes) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw file_error(path, "cannot read (" + ec.message() + ")");
  if (size > max_bytes) throw file_error(path, "larger than " + std::to_string(max_bytes) + " bytes");
  std::ifstream f(path, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  if (!f) throw file_error(path, "cannot read");
  return s.str();
}

// One plane of the .bin: width*height*3 halves from `at`.
std::vector<float> plane(const std::vector<Imath::half>& bin, size_t at, size_t count) {
  std::vector<float> out(count);
  for (size_t i = 0; i < count; ++i) out[i] = float(bin[at + i]);
  return out;
}

}  // namespace

TruthSet load_truth_set(const std::string& dir) {
  const std::string jpath = dir + "/truth.json", bpath = dir + "/truth.bin";
  TruthSet t;
  size_t count = 0;
  try {
    const auto j = nlohmann::json::parse(read_small_file(jpath, 1 << 20));
    if (j.at("format") != "ahdpack-truth" || j.at("version") != 1) throw file_error(jpath, "not an ahdpack-truth file, version 1");
    t.name = j.at("scene").get<std::string>();
    t.width = j.at("width").get<int>(), t.height = j.at("height").get<int>();
    if (t.width < 1 || t.height < 1 || t.width > kMaxSize || t.height > kMaxSize) throw file_error(jpath, "size out of range");
    const auto& n = j.at("normals");
    if (n.size() < 4 || n.size() > kMaxNormals) throw file_error(jpath, "normal count out of range");
    for (const auto& v : n) {
      std::array<double, 3> a = {v.at(0).get<double>(), v.at(1).get<double>(), v.at(2).get<double>()};
      const double len = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
      if (!(std::fabs(len - 1.0) < 1e-3) || a[2] <= 0) throw file_error(jpath, "a normal is not a unit upper-hemisphere vector");
      t.normals.push_back(a);
    }
    t.held_out.assign(t.normals.size(), 0);
    for (const auto& k : j.at("held_out")) {
      const size_t i = k.get<size_t>();
      if (i >= t.normals.size()) throw file_error(jpath, "held_out index out of range");
      t.held_out[i] = 1;
    }
    count = t.normals.size();
  } catch (const nlohmann::json::exception& e) {
    throw file_error(jpath, std::string("malformed: ") + e.what());
  }
  const size_t n3 = t.texels() * 3, planes = count + 3;
  // truth.bin, or truth.bin.zst (zstd: the larger bakes are committed compressed).
  std::string raw;
  std::error_code ec;
  if (!std::filesystem::exists(bpath, ec) && std::filesystem::exists(bpath + ".zst", ec)) {
    const std::string zpath = bpath + ".zst";
    const std::string z = read_small_file(zpath, planes * n3 * 2 + (1 << 20));
    raw.resize(planes * n3 * 2);
    const size_t got = ZSTD_decompress(raw.data(), raw.size(), z.data(), z.size());
    if (ZSTD_isError(got)) throw file_error(zpath, std::string("not a zstd frame of truth.bin (") + ZSTD_getErrorName(got) + ")");
    if (got != raw.size()) throw file_error(zpath, "size does not match truth.json");
  } else {
    raw = read_small_file(bpath, planes * n3 * 2);
  }
  if (raw.size() != planes * n3 * 2) throw file_error(bpath, "size does not match truth.json");
  std::vector<Imath::half> bin(planes * n3);
  std::memcpy(bin.data(), raw.data(), raw.size());  // little-endian halves (the script writes <f2)
  for (size_t k = 0; k < count; ++k) {
    t.e.push_back(plane(bin, k * n3, n3));
    for (float& v : t.e.back()) v *= float(kPi);  // the bake is E/π
  }
  t.bumped_e = plane(bin, count * n3, n3);
  for (float& v : t.bumped_e) v *= float(kPi);
  t.bumped_n = plane(bin, (count + 1) * n3, n3);
  const std::vector<float> cov = plane(bin, (count + 2) * n3, n3);
  t.coverage.resize(t.texels());
  for (size_t i = 0; i < t.texels(); ++i) {
    t.coverage[i] = cov[i * 3] > 0.5f;
    float* nb = &t.bumped_n[i * 3];
    const float len = std::sqrt(nb[0] * nb[0] + nb[1] * nb[1] + nb[2] * nb[2]);
    if (t.coverage[i] && !(len > 0.5f)) t.coverage[i] = 0;  // no usable normal: not a chart texel
    for (int c = 0; c < 3; ++c) nb[c] = len > 0 ? nb[c] / len : (c == 2);
  }
  return t;
}

}  // namespace ahd
