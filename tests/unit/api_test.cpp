// The public API (<ahd/convert.h>, <ahd/ahd.h>) in process: what a cook step sees.
#include <ahd/ahd.h>
#include <ahd/convert.h>
#include <ahd/sample.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "containers/container.h"
#include "pipeline/plane_codec.h"

namespace {

const ahd::ShImage& sample32() {
  static const ahd::ShImage sh = ahd::bake_sample(32, 2, 0, 1);
  return sh;
}

const ahd::OutputFile* find(const ahd::Conversion& c, const std::string& name) {
  for (const auto& f : c.files)
    if (f.name == name) return &f;
  return nullptr;
}

nlohmann::json json_of(const ahd::OutputFile& f) { return nlohmann::json::parse(f.bytes.begin(), f.bytes.end()); }

}  // namespace

TEST(Api, ConvertReturnsPlanesThenManifestThenReport) {
  ahd::ConversionOptions opt;
  opt.profile = "pc-bc";
  const ahd::Conversion c = ahd::convert(sample32(), "room", opt);
  ASSERT_EQ(c.files.size(), 5u);
  EXPECT_EQ(c.files[0].name.rfind("room.iz.", 0), 0u);  // room.iz.<12 hex of its SHA-256>.ktx2
  EXPECT_EQ(c.files[0].name.size(), std::string("room.iz.123456789abc.ktx2").size());
  EXPECT_EQ(c.files[3].name, "room.report.json");
  EXPECT_EQ(c.files[4].name, "room.json");  // last: publishing it commits the set
  EXPECT_TRUE(c.directional);
  const nlohmann::json m = json_of(c.files[4]);
  ASSERT_EQ(m.at("planes").size(), 3u);
  for (const auto& p : m.at("planes")) {
    const ahd::OutputFile* f = find(c, p.at("file").get<std::string>());
    ASSERT_NE(f, nullptr) << p.dump();
    EXPECT_EQ(p.at("bytes").get<size_t>(), f->bytes.size());
    EXPECT_EQ(p.at("sha256").get<std::string>().substr(0, 12), f->name.substr(f->name.size() - 17, 12));
    const ahd::Texture t = ahd::decode_container(ahd::ContainerKind::KTX2, f->bytes.data(), f->bytes.size(), f->name);
    EXPECT_EQ(t.levels.size(), 6u);  // 32 → 1
  }
}

TEST(Api, SameBytesWhateverTheThreadCount) {
  ahd::ConversionOptions a, b;
  a.profile = b.profile = "pc-bc";
  a.threads = 1;
  b.threads = 2;
  const ahd::Conversion x = ahd::convert(sample32(), "s", a), y = ahd::convert(sample32(), "s", b);
  ASSERT_EQ(x.files.size(), y.files.size());
  for (size_t i = 0; i < x.files.size(); ++i)
    if (x.files[i].name != "s.report.json") EXPECT_EQ(x.files[i].bytes, y.files[i].bytes) << x.files[i].name;
}

TEST(Api, DiagnosticsAreOffByDefaultAndFullOnRequest) {
  ahd::ConversionOptions opt;
  const nlohmann::json off = json_of(*find(ahd::convert(sample32(), "s", opt), "s.report.json"));
  EXPECT_EQ(off.at("error").at("quantised_closed_loop").at("texels").get<size_t>(), 0u);
  EXPECT_TRUE(off.at("levels").empty());
  opt.measure = ahd::Measure::Full;
  const nlohmann::json full = json_of(*find(ahd::convert(sample32(), "s", opt), "s.report.json"));
  size_t covered = 0;
  for (uint8_t c : sample32().coverage) covered += c;
  EXPECT_EQ(full.at("error").at("quantised_closed_loop").at("texels").get<size_t>(), covered);
  EXPECT_GT(full.at("error").at("unconstrained_ls").at("texels").get<size_t>(), 0u);
  EXPECT_EQ(full.at("levels").size(), 6u);
}

TEST(Api, ProgressIsReportedInOrderAndCancelStopsTheConversion) {
  ahd::ConversionOptions opt;
  std::vector<std::pair<std::string, double>> seen;
  opt.progress = [&](const char* stage, double f) { seen.emplace_back(stage, f); };
  ahd::convert(sample32(), "s", opt);
  ASSERT_GE(seen.size(), 6u);
  EXPECT_EQ(seen.front(), std::make_pair(std::string("fit"), 0.0));
  EXPECT_EQ(seen.back(), std::make_pair(std::string("write"), 1.0));
  for (size_t i = 1; i < seen.size(); ++i)
    if (seen[i].first == seen[i - 1].first) EXPECT_GE(seen[i].second, seen[i - 1].second) << seen[i].first;

  std::atomic<bool> cancel{false};
  opt.cancel = &cancel;
  opt.progress = [&](const char* stage, double) {
    if (std::string(stage) == "encode") cancel = true;
  };
  EXPECT_THROW(ahd::convert(sample32(), "s", opt), ahd::Cancelled);
}

TEST(Api, InvalidOptionsAndInputsAreOneClearError) {
  auto message = [](const ahd::ShImage& sh, const ahd::ConversionOptions& o, const std::string& name = "s") {
    try {
      ahd::convert(sh, name, o);
    } catch (const ahd::Error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  ahd::ConversionOptions o;
  o.eps = 1.5;
  EXPECT_NE(message(sample32(), o).find("eps"), std::string::npos);
  o = {};
  o.profile = "no-such-profile";
  EXPECT_NE(message(sample32(), o).find("unknown profile 'no-such-profile'"), std::string::npos);
  o = {};
  o.profile_json = "{\"name\": \"x\", \"planes\": {\"iz\": \"r8\", \"dir\": \"rg8\", \"ratio\": \"r8\"}}";
  EXPECT_NE(message(sample32(), o).find("iz plane needs an HDR RGB format"), std::string::npos);
  o = {};
  EXPECT_NE(message(sample32(), o, "a/b").find("without folders"), std::string::npos);
  ahd::ShImage bad = sample32();
  bad.data.pop_back();
  EXPECT_NE(message(bad, o).find("SH data holds"), std::string::npos);
  bad = sample32();
  bad.coeffs = 5;
  EXPECT_NE(message(bad, o).find("4 (L1) or 9 (L2)"), std::string::npos);
}

TEST(Api, PlaneMetadataCanBeLeftOutForStrictValidators) {
  ahd::ConversionOptions opt;
  const ahd::Conversion with = ahd::convert(sample32(), "s", opt);
  opt.plane_metadata = false;
  const ahd::Conversion without = ahd::convert(sample32(), "s", opt);
  auto keys = [](const ahd::OutputFile& f) {
    size_t n = 0;
    for (const auto& kv : ahd::decode_container(ahd::ContainerKind::KTX2, f.bytes.data(), f.bytes.size(), f.name).metadata)
      n += kv.first.rfind("ahd.", 0) == 0;
    return n;
  };
  EXPECT_GT(keys(with.files[0]), 5u);
  EXPECT_EQ(keys(without.files[0]), 0u);
  // The manifest says the same either way (sizes aside).
  nlohmann::json a = json_of(with.files.back()), b = json_of(without.files.back());
  for (auto* m : {&a, &b})
    for (auto& p : (*m)["planes"]) p.erase("bytes"), p.erase("sha256"), p.erase("file");
  EXPECT_EQ(a, b);
}

TEST(Api, CApiConvertsAndReportsErrors) {
  const ahd::ShImage& sh = sample32();
  ahd_sh_input in = {sh.width, sh.height, sh.coeffs, sh.data.data(), sh.coverage.data(), nullptr};
  ahd_options opt;
  ahd_options_init(&opt);
  ahd_result* r = nullptr;
  char err[128] = "";
  ASSERT_EQ(ahd_convert(&in, "s", &opt, &r, err, sizeof err), 0) << err;
  const ahd::Conversion cpp = ahd::convert(sh, "s", {});
  ASSERT_EQ(ahd_result_file_count(r), cpp.files.size());
  for (size_t i = 0; i < cpp.files.size(); ++i) {
    if (cpp.files[i].name == "s.report.json") continue;  // its seconds differ
    size_t n = 0;
    const unsigned char* d = ahd_result_file_data(r, i, &n);
    EXPECT_EQ(std::string(ahd_result_file_name(r, i)), cpp.files[i].name);
    EXPECT_EQ(std::vector<uint8_t>(d, d + n), cpp.files[i].bytes);
  }
  EXPECT_EQ(ahd_result_file_name(r, 99), nullptr);
  ahd_result_free(r);

  opt.eps = 0;
  EXPECT_NE(ahd_convert(&in, "s", &opt, &r, err, sizeof err), 0);
  EXPECT_EQ(r, nullptr);
  EXPECT_NE(std::string(err).find("eps"), std::string::npos);
  EXPECT_NE(ahd_convert(nullptr, "s", &opt, &r, err, 8), 0);
  EXPECT_EQ(std::string(err).size(), 7u);  // truncated to the buffer, NUL-terminated
}

// ahd_options is versioned by its leading struct_size: a caller compiled with an older, smaller
// struct gets the defaults for the members it lacks; a size no version has is refused.
TEST(Api, CApiOptionsStructSize) {
  const ahd::ShImage& sh = sample32();
  ahd_sh_input in = {sh.width, sh.height, sh.coeffs, sh.data.data(), sh.coverage.data(), nullptr};
  char err[256] = "";
  ahd_result* r = nullptr;
  // An older struct ending before `measure` (aligned as the struct): measure takes its default,
  // whatever lies beyond the caller's size.
  const size_t older = offsetof(ahd_options, measure) / alignof(ahd_options) * alignof(ahd_options);
  ahd_options opt;
  std::memset(&opt, 0xAB, sizeof opt);
  ahd_options_init_size(&opt, older);
  EXPECT_EQ(opt.struct_size, older);
  EXPECT_EQ(opt.measure, int(0xABABABAB)) << "init wrote past the caller's size";
  EXPECT_EQ(opt.direction_fit, 1);
  ASSERT_EQ(ahd_convert(&in, "s", &opt, &r, err, sizeof err), 0) << err;
  ahd_result_free(r);
  opt.struct_size = sizeof(ahd_options);  // now measure = 0xABABABAB is read, and refused
  EXPECT_NE(ahd_convert(&in, "s", &opt, &r, err, sizeof err), 0);
  EXPECT_NE(std::string(err).find("measure"), std::string::npos) << err;
  // Zero, unaligned, larger than this library's: refused with the cause, no result.
  for (size_t bad : {size_t(0), older + 1, sizeof(ahd_options) + alignof(ahd_options), size_t(0xABABABABABABABABull)}) {
    opt.struct_size = bad;
    r = nullptr;
    EXPECT_NE(ahd_convert(&in, "s", &opt, &r, err, sizeof err), 0) << bad;
    EXPECT_EQ(r, nullptr);
    EXPECT_NE(std::string(err).find("struct_size"), std::string::npos) << err;
  }
  // NULL options: the defaults.
  ASSERT_EQ(ahd_convert(&in, "s", nullptr, &r, err, sizeof err), 0) << err;
  ahd_result_free(r);
}

// The library's iz_scale (issue 39; the command's --iz-scale): stored I_z = iz_scale × E. The SH
// is scaled before the fit, so the I_z plane is the default's times the factor (float rounding),
// the manifest and the planes record it, and a caller of an older header (no member) gets 1.
TEST(Api, IzScaleScalesTheIzPlaneAndIsRecorded) {
  const auto iz_and_manifest = [](double iz_scale) {
    ahd::ConversionOptions opt;
    opt.iz_scale = iz_scale;
    const ahd::Conversion c = ahd::convert(sample32(), "s", opt);
    const nlohmann::json m = json_of(c.files.back());
    const ahd::OutputFile* f = find(c, m.at("planes").at(0).at("file").get<std::string>());
    EXPECT_EQ(m.at("planes").at(0).at("name").get<std::string>(), "iz");
    const ahd::Texture t = ahd::decode_container(ahd::ContainerKind::KTX2, f->bytes.data(), f->bytes.size(), f->name);
    return std::make_pair(ahd::decode_plane(t.format, t.levels.at(0)), m);
  };
  const auto [e, me] = iz_and_manifest(1.0);
  const double k = 1.0 / 3.14159265358979323846;
  const auto [q, mq] = iz_and_manifest(k);
  EXPECT_EQ(me.at("decode").at("iz_scale").get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(mq.at("decode").at("iz_scale").get<double>(), k);
  ASSERT_EQ(e.data.size(), q.data.size());
  size_t lit = 0;
  for (size_t i = 0; i < e.data.size(); ++i) {
    if (i % size_t(e.channels) == 3) continue;  // RGBA16F: alpha is 1
    const float a = e.data[i], b = q.data[i];
    EXPECT_NEAR(b, a * k, 2e-3 * std::abs(a * k) + 1e-6) << i;  // half floats: 11 bits
    lit += a > 0;
  }
  EXPECT_GT(lit, 100u);
  ahd::ConversionOptions bad;
  for (double v : {0.0, -1.0, std::nan("")}) {
    bad.iz_scale = v;
    EXPECT_THROW(ahd::convert(sample32(), "s", bad), ahd::Error) << v;
  }
  // C: a caller whose struct ends before iz_scale converts at 1, one whose struct has it at 1/π.
  const ahd::ShImage& sh = sample32();
  ahd_sh_input in = {sh.width, sh.height, sh.coeffs, sh.data.data(), sh.coverage.data(), nullptr};
  char err[256] = "";
  for (const bool member : {false, true}) {
    ahd_options opt;
    std::memset(&opt, 0xAB, sizeof opt);
    ahd_options_init_size(&opt, member ? sizeof opt : offsetof(ahd_options, iz_scale));
    EXPECT_EQ(opt.iz_scale == 1.0, member) << "init wrote past the caller's size, or not its default";
    if (member) opt.iz_scale = k;
    ahd_result* r = nullptr;
    ASSERT_EQ(ahd_convert(&in, "s", &opt, &r, err, sizeof err), 0) << err;
    size_t n = 0;
    const unsigned char* d = ahd_result_file_data(r, ahd_result_file_count(r) - 1, &n);
    EXPECT_DOUBLE_EQ(nlohmann::json::parse(d, d + n).at("decode").at("iz_scale").get<double>(), member ? k : 1.0);
    ahd_result_free(r);
  }
}

// Issue 44: the C API accepted stems `.room`, `a:b`, `..`, newlines, 300 characters and NaN
// normals (an all-black map, exit 0). Refused now with the CLI's rule (pipeline/manifest.h
// set_name_problem), one message, no result.
TEST(Api, CApiRefusesStemsAndNormalsTheCliRefuses) {
  const ahd::ShImage& sh = sample32();
  ahd_sh_input in = {sh.width, sh.height, sh.coeffs, sh.data.data(), sh.coverage.data(), nullptr};
  ahd_options opt;
  ahd_options_init(&opt);
  char err[256] = "";
  for (const std::string& bad : {std::string(".room"), std::string("a:b"), std::string(".."), std::string("a\nb"),
                                std::string("a\tb"), std::string(300, 'r'), std::string(""), std::string("room.report"),
                                std::string("a/b")}) {
    ahd_result* r = nullptr;
    EXPECT_NE(ahd_convert(&in, bad.c_str(), &opt, &r, err, sizeof err), 0) << bad;
    EXPECT_EQ(r, nullptr);
    EXPECT_NE(std::string(err).find("output name"), std::string::npos) << err;
    EXPECT_THROW(ahd::convert(sh, bad, {}), ahd::Error) << bad;
  }
  ahd_result* r = nullptr;
  ASSERT_EQ(ahd_convert(&in, std::string(200, 'r').c_str(), &opt, &r, err, sizeof err), 0) << err;
  ahd_result_free(r);
  // Normals: one NaN, one infinite, one zero-length on a covered texel.
  std::vector<float> normals(sh.texels() * 3, 0.0f);
  for (size_t i = 0; i < sh.texels(); ++i) normals[i * 3 + 2] = 1.0f;
  in.normals = normals.data();
  r = nullptr;
  ASSERT_EQ(ahd_convert(&in, "s", &opt, &r, err, sizeof err), 0) << err;
  ahd_result_free(r);
  size_t covered = 0;
  while (!sh.coverage[covered]) ++covered;
  for (const float v : {std::nanf(""), INFINITY, 0.0f}) {
    std::vector<float> bad = normals;
    bad[covered * 3 + 2] = v;
    in.normals = bad.data();
    r = nullptr;
    EXPECT_NE(ahd_convert(&in, "s", &opt, &r, err, sizeof err), 0) << v;
    EXPECT_EQ(r, nullptr);
    EXPECT_NE(std::string(err).find("normal at texel (" + std::to_string(covered % size_t(sh.width))), std::string::npos)
        << err;
  }
}
