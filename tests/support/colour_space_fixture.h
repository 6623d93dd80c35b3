// What the colour-space tests share (tests/unit and tests/integration colour_space_test.cpp).
#pragma once
#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include "cli_runner.h"
#include "bakers/baker_layout.h"
#include "image/colour_space.h"
#include "image/sh_exr.h"

namespace ahd_fixture::colour_space_fixture {

using namespace ::ahd;

namespace fs = std::filesystem;

const std::vector<float> kAp1 = {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
const std::vector<float> kRec2020 = {0.708f, 0.292f, 0.170f, 0.797f, 0.131f, 0.046f, 0.3127f, 0.3290f};
const std::vector<float> kRec709 = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};

// A small L2 image with positive L0 and signed higher bands, every value distinct.
inline ShImage test_sh(int w = 5, int h = 4) {
  ShImage sh = make_sh_image(w, h, 9);
  for (size_t i = 0; i < sh.data.size(); ++i) {
    const size_t v = i % 27;
    sh.data[i] = v < 3 ? 0.5f + 0.07f * float(i % 11) + 0.3f * float(v)
                       : 0.4f * std::sin(0.37f * float(i)) - 0.05f * float(v % 3);
  }
  return sh;
}

// The canonical EXR (float) with optional chromaticities: what a baker working in ACEScg writes.
inline void write_sh_exr(const std::string& path, const ShImage& sh, const std::vector<float>& chroma) {
  OIIO::ImageSpec spec(sh.width, sh.height, sh.coeffs * 3, OIIO::TypeDesc::FLOAT);
  spec.channelnames.clear();
  const char* rgb[3] = {"R", "G", "B"};
  for (int k = 0; k < sh.coeffs; ++k)
    for (int c = 0; c < 3; ++c) spec.channelnames.push_back("sh" + std::to_string(k) + "." + rgb[c]);
  if (!chroma.empty()) spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), chroma.data());
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out && out->open(path, spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, sh.data.data()));
  out->close();
}

// The numpy reference of `space` → linear Rec.709 (tests/colour_reference.py), or empty when no
// python3 with numpy is installed (scripts/setup.sh installs python3-numpy).
inline std::vector<double> numpy_matrix(const std::string& space) {
  const std::string script = std::string(AHD_SOURCE_DIR) + "/tests/colour_reference.py";
  for (const char* py : {"python3", "/usr/bin/python3"}) {
    const std::string out = ahd_test::run_shell(std::string(py) + " '" + script + "' " + space + " 2>/dev/null");
    std::istringstream in(out);
    std::vector<double> m;
    double v;
    while (in >> v) m.push_back(v);
    if (m.size() == 9) return m;
  }
  return {};
}

#define REQUIRE_NUMPY(m) \
  if ((m).empty()) GTEST_SKIP() << "python3 with numpy missing (apt-get install python3-numpy): no reference matrix"

// Every coefficient's RGB of `out` is m · the same coefficient of `in`, to 1e-5 (relative above 1).
inline void expect_converted(const ShImage& in, const ShImage& out, const std::vector<double>& m) {
  ASSERT_EQ(in.data.size(), out.data.size());
  double worst = 0;
  for (size_t t = 0; t < in.texels(); ++t)
    for (int k = 0; k < in.coeffs; ++k) {
      const float* a = in.texel(t) + k * 3;
      const float* b = out.texel(t) + k * 3;
      for (int r = 0; r < 3; ++r) {
        const double want = m[size_t(r * 3)] * a[0] + m[size_t(r * 3 + 1)] * a[1] + m[size_t(r * 3 + 2)] * a[2];
        worst = std::max(worst, std::fabs(double(b[r]) - want) / std::max(1.0, std::fabs(want)));
      }
    }
  EXPECT_LE(worst, 1e-5);
}

inline std::string tmp(const std::string& tag) { return ahd_test::temp_dir("colour_" + tag); }

}  // namespace ahd_fixture::colour_space_fixture
