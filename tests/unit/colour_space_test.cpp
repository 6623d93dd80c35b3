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

namespace ahd {
namespace {
namespace fs = std::filesystem;

const std::vector<float> kAp1 = {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
const std::vector<float> kRec2020 = {0.708f, 0.292f, 0.170f, 0.797f, 0.131f, 0.046f, 0.3127f, 0.3290f};
const std::vector<float> kRec709 = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};

// A small L2 image with positive L0 and signed higher bands, every value distinct.
ShImage test_sh(int w = 5, int h = 4) {
  ShImage sh = make_sh_image(w, h, 9);
  for (size_t i = 0; i < sh.data.size(); ++i) {
    const size_t v = i % 27;
    sh.data[i] = v < 3 ? 0.5f + 0.07f * float(i % 11) + 0.3f * float(v)
                       : 0.4f * std::sin(0.37f * float(i)) - 0.05f * float(v % 3);
  }
  return sh;
}

// The canonical EXR (float) with optional chromaticities: what a baker working in ACEScg writes.
void write_sh_exr(const std::string& path, const ShImage& sh, const std::vector<float>& chroma) {
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
std::vector<double> numpy_matrix(const std::string& space) {
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
void expect_converted(const ShImage& in, const ShImage& out, const std::vector<double>& m) {
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

std::string tmp(const std::string& tag) { return ahd_test::temp_dir("colour_" + tag); }

}  // namespace

// OpenColorIO's matrix for every named space equals the numpy derivation (its builtin Bradford
// transforms for the ACES spaces, our chromaticity matrix for Rec.2020 and P3-D65).
TEST(ColourSpace, NumpyReferenceMatchesEverySpace) {
  for (const std::string space : {"acescg", "aces2065-1", "rec2020", "p3-d65"}) {
    const std::vector<double> ref = numpy_matrix(space);
    REQUIRE_NUMPY(ref);
    const Matrix3 m = working_space_matrix(parse_input_space(space), "test");
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(m[size_t(r)][size_t(c)], ref[size_t(r * 3 + c)], 1e-6) << space << " " << r << c;
  }
}

// The done-when line of issue 25: an EXR declaring ACEScg (AP1 chromaticities) converts, and every
// coefficient of every band equals the numpy matrix times the stored value, to 1e-5.
TEST(ColourSpace, NumpyAcesCgExrConvertsToTheReference) {
  const std::vector<double> ref = numpy_matrix("acescg");
  REQUIRE_NUMPY(ref);
  const std::string d = tmp("acescg");
  const ShImage sh = test_sh();
  write_sh_exr(d + "/acescg.exr", sh, kAp1);
  ReadStats rs;
  const ShImage got = read_canonical_sh(d + "/acescg.exr", &rs);
  expect_converted(sh, got, ref);
  EXPECT_NE(rs.input_space.find("ACEScg"), std::string::npos) << rs.input_space;
  // The same through a baker layout (the canonical preset reads the same file).
  expect_converted(sh, read_layout(load_layout("canonical"), d + "/acescg.exr", ""), ref);
}

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

// The command: the report records the space converted from, a non-convertible declaration is one
// error line and no output, and --input-space is part of the conversion's key.
TEST(ColourSpace, CliReportKeyAndRefusal) {
  const std::string d = tmp("cli");
  const ShImage sh = test_sh(8, 8);
  write_sh_exr(d + "/ap1.exr", sh, kAp1);
  write_sh_exr(d + "/none.exr", sh, {});
  write_sh_exr(d + "/flat.exr", sh, {0.3f, 0.3f, 0.4f, 0.4f, 0.5f, 0.5f, 0.3127f, 0.3290f});
  auto r = ahd_test::run_cli({"convert", d + "/ap1.exr", "-o", d + "/out/ap1.ktx2", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream rep(d + "/out/ap1.report.json");
  const std::string report((std::istreambuf_iterator<char>(rep)), std::istreambuf_iterator<char>());
  EXPECT_NE(report.find("\"input_space\": \"ACEScg"), std::string::npos) << report.substr(0, 400);

  r = ahd_test::run_cli({"convert", d + "/flat.exr", "-o", d + "/bad/flat.ktx2"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("flat.exr: declares degenerate chromaticities"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(fs::exists(d + "/bad") && !fs::is_empty(d + "/bad"));

  auto key = [&](std::vector<std::string> extra) {
    std::vector<std::string> a = {"convert", d + "/none.exr", "-o", d + "/k/none.ktx2", "--print-key"};
    a.insert(a.end(), extra.begin(), extra.end());
    const auto k = ahd_test::run_cli(a);
    EXPECT_EQ(k.exit_code, 0) << k.output;
    return k.output;
  };
  const std::string plain = key({}), acescg = key({"--input-space", "acescg"});
  EXPECT_NE(plain, acescg);
  EXPECT_NE(acescg, key({"--input-space", "rec2020"}));
  EXPECT_EQ(plain, key({}));
  r = ahd_test::run_cli({"convert", d + "/none.exr", "-o", d + "/k/none.ktx2", "--input-space", "logc"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("unknown space 'logc'"), std::string::npos) << r.output;
}

}  // namespace ahd
