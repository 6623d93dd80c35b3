// Colour spaces through OpenColorIO (image/colour_space.h, docs/colour.md): an input declaring another
// linear working space is converted to linear Rec.709 per SH coefficient; --input-space replaces a
// wrong or missing declaration; what cannot be converted is refused with one line; sRGB-encoded
// colour planes are decoded with the sRGB EOTF. The reference matrices come from
// tests/colour_reference.py (numpy, primaries' xy and Bradford), independent of OpenColorIO.
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
#include "colour_space_fixture.h"

namespace ahd {
using namespace ahd_fixture::colour_space_fixture;


// Rec.709 declared, nothing declared, or --input-space linear-rec709: the values exactly as stored
// (no matrix at all), and the report names no conversion.
TEST(ColourSpace, WorkingSpaceIsReadUntouched) {
  const std::string d = tmp("working");
  const ShImage sh = test_sh();
  write_sh_exr(d + "/rec709.exr", sh, kRec709);
  write_sh_exr(d + "/none.exr", sh, {});
  for (const std::string f : {"rec709.exr", "none.exr"}) {
    ReadStats rs;
    EXPECT_EQ(read_canonical_sh(d + "/" + f, &rs).data, sh.data) << f;
    EXPECT_EQ(rs.input_space, "") << f;
    EXPECT_EQ(read_canonical_sh(d + "/" + f, nullptr, "linear-rec709").data, sh.data) << f;
  }
}

// --input-space replaces a wrong declaration (Rec.2020 declared, ACEScg meant) and gives a missing
// one: both read exactly as the file that declares ACEScg.
TEST(ColourSpace, InputSpaceOverridesAWrongOrMissingDeclaration) {
  const std::string d = tmp("override");
  const ShImage sh = test_sh();
  write_sh_exr(d + "/ap1.exr", sh, kAp1);
  write_sh_exr(d + "/wrong.exr", sh, kRec2020);
  write_sh_exr(d + "/none.exr", sh, {});
  const ShImage want = read_canonical_sh(d + "/ap1.exr");
  EXPECT_NE(want.data, sh.data);
  EXPECT_NE(read_canonical_sh(d + "/wrong.exr").data, want.data);  // as declared: Rec.2020
  EXPECT_EQ(read_canonical_sh(d + "/wrong.exr", nullptr, "acescg").data, want.data);
  EXPECT_EQ(read_canonical_sh(d + "/none.exr", nullptr, "acescg").data, want.data);
  // A baker layout takes it through LayoutPreset::input_space (what --input-space sets).
  LayoutPreset canonical = load_layout("canonical");
  canonical.input_space = "acescg";
  EXPECT_EQ(read_layout(canonical, d + "/wrong.exr", "").data, want.data);
  // An override to the working space reads the wrong file's values untouched.
  EXPECT_EQ(read_canonical_sh(d + "/wrong.exr", nullptr, "linear-rec709").data, sh.data);
}

// Declarations no matrix converts: one line naming the file and the way out; nothing else.
TEST(ColourSpace, NonConvertibleDeclarationsAreRefused) {
  const std::string d = tmp("refused");
  const ShImage sh = test_sh();
  const std::vector<float> collinear = {0.3f, 0.3f, 0.4f, 0.4f, 0.5f, 0.5f, 0.3127f, 0.3290f};
  write_sh_exr(d + "/flat.exr", sh, collinear);
  try {
    read_canonical_sh(d + "/flat.exr");
    ADD_FAILURE() << "degenerate chromaticities were read";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(d + "/flat.exr: declares degenerate chromaticities"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
  // An unknown name.
  ImageFileInfo info;
  info.is_float = true;
  info.color_space = "ARRI LogC";
  try {
    declared_space(info, "x.exr");
    ADD_FAILURE() << "an unknown colour space was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("x.exr: declares colour space 'ARRI LogC'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--input-space"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_input_space("acescc"), Error);
  // SH is signed: an sRGB encoding cannot hold it.
  write_sh_exr(d + "/plain.exr", sh, {});
  EXPECT_THROW(read_canonical_sh(d + "/plain.exr", nullptr, "srgb"), Error);
}

// An 8-bit colour plane of a preset that declares "encoding": "srgb" is decoded with the sRGB EOTF
// (IEC 61966-2-1); the same preset's ratio (direction) channel stays raw. Without the
// declaration the stored values are read as they are, and --input-space srgb decodes them.
TEST(ColourSpace, SrgbEncodedColourPlaneDecodesToLinear) {
  const std::string d = tmp("srgb");
  const int w = 16, h = 16;
  std::vector<uint8_t> px(size_t(w) * h * 4);
  for (size_t i = 0; i < size_t(w) * h; ++i)
    for (size_t c = 0; c < 4; ++c) px[i * 4 + c] = uint8_t((i + 85 * c) % 256);
  {
    OIIO::ImageSpec spec(w, h, 4, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:UnassociatedAlpha", 1);  // the numbers as given (PNG's alpha is not premultiplied)
    auto out = OIIO::ImageOutput::create(d + "/lm.png");
    ASSERT_TRUE(out && out->open(d + "/lm.png", spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
    out->close();
  }
  auto preset = [&](const std::string& name, const std::string& encoding) {
    std::ofstream(d + "/" + name + ".json")
        << "{\"name\": \"" << name << "\", \"coeffs\": 4, \"space\": \"tangent\", \"form\": \"radiance\", \"files\": "
        << "[{\"pattern\": \"{base}.png\"" << encoding << "}], \"coefficients\": [{\"file\": 0}, "
        << "{\"file\": 0, \"channels\": [\"A\", \"A\", \"A\"], \"decode\": \"ratio\", \"k\": 2}]}";
    return load_layout(d + "/" + name + ".json");
  };
  auto eotf = [](double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); };
  auto check = [&](const ShImage& sh, bool decoded) {
    double worst = 0, worst_ratio = 0;
    for (size_t i = 0; i < sh.texels(); ++i)
      for (int c = 0; c < 3; ++c) {
        const double stored = px[i * 4 + size_t(c)] / 255.0, a = px[i * 4 + 3] / 255.0;
        const double l0 = decoded ? eotf(stored) : stored;
        worst = std::max(worst, std::fabs(sh.texel(i)[c] - l0));
        worst_ratio = std::max(worst_ratio, std::fabs(sh.texel(i)[3 + c] - (a - 0.5) * 2 * l0));  // A stays raw
      }
    EXPECT_LE(worst, 2e-6);
    EXPECT_LE(worst_ratio, 4e-6);
  };
  ReadStats rs;
  check(read_layout(preset("enc", ", \"encoding\": \"srgb\""), d + "/lm", "", &rs), true);
  EXPECT_NE(rs.input_space.find("sRGB"), std::string::npos) << rs.input_space;
  LayoutPreset raw = preset("raw", "");
  check(read_layout(raw, d + "/lm", ""), false);
  raw.input_space = "srgb";
  check(read_layout(raw, d + "/lm", ""), true);
  EXPECT_THROW(preset("bad", ", \"encoding\": \"gamma\""), Error);
}

}  // namespace ahd
