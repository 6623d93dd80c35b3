// ahd_platform_bytes OUTDIR [--disable MASK] [--only CASE]: converts the built-in sample (and forms of it: L1, a
// plain map, world-space normals) with several profiles and options through the public C++ API
// and writes each case's planes and manifest into OUTDIR/<case>/ (not the report: it holds
// seconds). scripts/compare-platform-bytes.sh compares the folders of two builds byte for byte
// (docs/platforms.md). --disable MASK: ahd::cpu::disable_for_tests(MASK) first, to force a SIMD
// path on x86-64 (1 = the SSE2 loops, 31 = every extension: the plain path). --only CASE: that
// case alone (the emulators are slow: qemu-aarch64 runs the fit about 100 times slower).
#include <ahd/convert.h>
#include <ahd/sample.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "core/cpu.h"

namespace {

struct Case {
  const char* name;
  std::function<ahd::ShImage()> input;
  std::function<void(ahd::ConversionOptions&)> options;
};

ahd::ShImage sample() { return ahd::bake_sample(); }

// The sample's L0 band only: a plain lightmap (coeffs 1).
ahd::ShImage plain_map() {
  ahd::ShImage sh = ahd::bake_sample(128, 2, 5);
  ahd::ShImage out;
  out.width = sh.width;
  out.height = sh.height;
  out.coeffs = 1;
  out.coverage = sh.coverage;
  out.data.resize(sh.texels() * 3);
  for (size_t i = 0; i < sh.texels(); ++i)
    for (int c = 0; c < 3; ++c) out.data[i * 3 + c] = sh.texel(i)[c];
  return out;
}

// The L1 sample taken as world-space SH over a bowl of normals: the fit rotates every texel. The
// normals use only +, −, ×, ÷ and sqrt (correctly rounded everywhere), so the input is the same
// bytes on every platform.
ahd::ShImage world_space() {
  ahd::ShImage sh = ahd::bake_sample(64, 1, 9);
  sh.normals.resize(sh.texels() * 3);
  for (int y = 0; y < sh.height; ++y)
    for (int x = 0; x < sh.width; ++x) {
      const float nx = (float(x) + 0.5f) / float(sh.width) - 0.5f, ny = (float(y) + 0.5f) / float(sh.height) - 0.5f;
      const float len = std::sqrt(nx * nx + ny * ny + 1.0f);
      float* n = &sh.normals[(size_t(y) * sh.width + x) * 3];
      n[0] = nx / len;
      n[1] = ny / len;
      n[2] = 1.0f / len;
    }
  return sh;
}

const std::vector<Case>& cases() {
  using O = ahd::ConversionOptions;
  static const std::vector<Case> all = {
      {"sample-uncompressed", sample, [](O&) {}},
      {"sample-pc-bc", sample, [](O& o) { o.profile = "pc-bc"; }},
      {"sample-pc-bc-dds-1thread", sample,
       [](O& o) {
         o.profile = "pc-bc";
         o.container = ahd::ContainerKind::DDS;
         o.threads = 1;
       }},
      {"sample-pc-bc-high", sample,
       [](O& o) {
         o.profile = "pc-bc";
         o.bc6h_quality = ahd::Bc6hQuality::High;
       }},
      {"sample-pc-bc-fast-linear", sample,
       [](O& o) {
         o.profile = "pc-bc";
         o.bc6h_quality = ahd::Bc6hQuality::Fast;
         o.direction_fit = ahd::DirectionFit::Linear;
       }},
      {"sample-packed-float", sample, [](O& o) { o.profile = "packed-float"; }},
      {"sample-packed-rgb9e5", sample, [](O& o) { o.profile = "packed-rgb9e5"; }},
      {"sample-uncompressed-zstd-coverage", sample,
       [](O& o) {
         o.zstd = true;
         o.coverage_plane = true;
       }},
      {"sample-uncompressed-measure", sample, [](O& o) { o.measure = ahd::Measure::Estimate; }},
      {"sample-l1-uncompressed-rgb", [] { return ahd::bake_sample(96, 1, 3); },
       [](O& o) { o.profile = "uncompressed-rgb"; }},
      {"plain-map-pc-bc", plain_map, [](O& o) { o.profile = "pc-bc"; }},
      {"plain-map-uncompressed", plain_map, [](O&) {}},
      {"world-space-l1-pc-bc", world_space, [](O& o) { o.profile = "pc-bc"; }},
  };
  return all;
}

bool ends_with(const std::string& s, const char* tail) {
  const size_t n = std::strlen(tail);
  return s.size() >= n && s.compare(s.size() - n, n, tail) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc % 2 != 0) {
    std::fprintf(stderr, "usage: ahd_platform_bytes OUTDIR [--disable MASK] [--only CASE]\n");
    return 2;
  }
  std::string only;
  for (int i = 2; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--disable") == 0) ahd::cpu::disable_for_tests(unsigned(std::strtoul(argv[i + 1], nullptr, 0)));
    else if (std::strcmp(argv[i], "--only") == 0) only = argv[i + 1];
    else {
      std::fprintf(stderr, "ahd_platform_bytes: unknown option %s\n", argv[i]);
      return 2;
    }
  }
  const std::filesystem::path root = argv[1];
  try {
    for (const Case& c : cases()) {
      if (!only.empty() && only != c.name) continue;
      ahd::ConversionOptions opt;
      c.options(opt);
      const ahd::Conversion conv = ahd::convert(c.input(), "out", opt);
      const std::filesystem::path dir = root / c.name;
      std::filesystem::create_directories(dir);
      size_t written = 0;
      for (const ahd::OutputFile& f : conv.files) {
        if (ends_with(f.name, ".report.json")) continue;  // seconds, thread counts: not compared
        std::ofstream out(dir / f.name, std::ios::binary);
        out.write(reinterpret_cast<const char*>(f.bytes.data()), std::streamsize(f.bytes.size()));
        if (!out) {
          std::fprintf(stderr, "ahd_platform_bytes: %s: cannot write\n", (dir / f.name).string().c_str());
          return 1;
        }
        ++written;
      }
      std::printf("%s: %zu files\n", c.name, written);
      std::fflush(stdout);
    }
  } catch (const ahd::Error& e) {
    std::fprintf(stderr, "ahd_platform_bytes: %s\n", e.what());
    return 1;
  }
  return 0;
}
