// The option table (api/option_table.h) against everything it declares: the C struct, the key, the
// docs table, the ctypes mirror, the internal defaults.
#include <ahd/ahd.h>
#include <ahd/convert.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "api/option_table.h"
#include "api/options.h"
#include "cook/conversion_key.h"
#include "core/option_enums.h"

namespace {

using ahd::ConversionOptions;
using ahd::OptionRow;

std::string read_source(const std::string& rel) {
  std::ifstream f(std::string(AHD_SOURCE_DIR) + "/" + rel, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

std::string key_text(const ConversionOptions& o) { return ahd::conversion_options_text(ahd::BakeInput{}, o, "s"); }

// Rows by their C member's place in ahd_options.
std::vector<const OptionRow*> rows_in_c_order() {
  std::vector<const OptionRow*> rows;
  for (const OptionRow& r : ahd::option_table()) rows.push_back(&r);
  std::sort(rows.begin(), rows.end(), [](const OptionRow* a, const OptionRow* b) { return a->c_offset < b->c_offset; });
  return rows;
}

}  // namespace

// The key of today's default options, byte for byte as the table was introduced but for the format
// line (kKeyFormat 3: the same inputs give other bytes since the instances and plain scale (2) and
// the per-texel refined d (3)).
TEST(OptionTable, KeyTextOfTheDefaultsIsUnchanged) {
  const std::string want = std::string("ahdpack-conversion-key 3\nversion ") + AHD_VERSION_STRING +
                           "\nname s\ncontainer ktx2\nprofile uncompressed\n"
                           "profile_json e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855\n"
                           "ratio profile\ndirection_fit 1\nbc6h_quality 1\neps 0.050000000000000003\nclosed_loop 1\n"
                           "levels 0\ncoverage_plane 0\ndirection 0\nambient_threshold 0.01\nzstd 0\nplane_metadata 1\n"
                           "measure 0\ninput sample\nsample 256 2 0\nlayout \nnormals 0\nmesh 0 uv_set -1\nplacement 0\n"
                           "pages 0\n";
  EXPECT_EQ(key_text(ConversionOptions{}), want);
  // And with the values spelled by name or hash.
  ConversionOptions o;
  o.container = ahd::ContainerKind::DDS;
  o.ratio = ahd::RatioForm::Rgb;
  o.profile_json = "{}";
  o.measure = ahd::Measure::Estimate;
  const std::string t = key_text(o);
  EXPECT_NE(t.find("\ncontainer dds\n"), std::string::npos) << t;
  EXPECT_NE(t.find("\nratio rgb\n"), std::string::npos) << t;
  EXPECT_NE(t.find("\nprofile_json 44136fa355b3678a1146ad16f7e8649e94fb4fc21fe77e8310c060f61caaff8a\n"), std::string::npos) << t;
  EXPECT_NE(t.find("\nmeasure 1\n"), std::string::npos) << t;
}

// Every option in the key changes it when changed; the others (threads) do not. Each row changes
// its own member only (no two rows share a member).
TEST(OptionTable, EveryKeyedOptionChangesTheKey) {
  const ConversionOptions d;
  const std::string base = key_text(d);
  for (const OptionRow& r : ahd::option_table()) {
    ConversionOptions o = d;
    r.change(o);
    EXPECT_NE(r.text(o), r.text(d)) << r.name;
    if (r.spec.key == ahd::KeyForm::None) {
      EXPECT_EQ(key_text(o), base) << r.name;
    } else {
      EXPECT_NE(key_text(o), base) << r.name << " is not in the key";
    }
    for (const OptionRow& other : ahd::option_table())
      if (&other != &r) EXPECT_EQ(other.text(o), other.text(d)) << r.name << " changes " << other.name;
  }
}

// The rows' C members are every member of ahd_options after struct_size, each once, in place.
TEST(OptionTable, RowsCoverEveryCMemberOnce) {
  size_t end = sizeof(size_t);  // struct_size
  EXPECT_EQ(offsetof(ahd_options, struct_size), 0u);
  for (const OptionRow* r : rows_in_c_order()) {
    const size_t aligned = (end + r->c_size - 1) / r->c_size * r->c_size;
    EXPECT_EQ(r->c_offset, aligned) << r->name << ": a C member before it has no row, or two rows share one";
    end = r->c_offset + r->c_size;
  }
  EXPECT_EQ((end + alignof(ahd_options) - 1) / alignof(ahd_options) * alignof(ahd_options), sizeof(ahd_options))
      << "a C member at the end has no row";
}

// ahd_options_init gives the C++ defaults through every row.
TEST(OptionTable, CInitIsTheCppDefaults) {
  ahd_options c;
  ahd_options_init(&c);
  EXPECT_EQ(c.struct_size, sizeof(ahd_options));
  ConversionOptions from_c;
  from_c.eps = 0.5, from_c.zstd = true, from_c.profile = "other";  // overwritten by every row
  for (const OptionRow& r : ahd::option_table()) r.from_c(c, from_c);
  for (const OptionRow& r : ahd::option_table()) EXPECT_EQ(r.text(from_c), r.text(ConversionOptions{})) << r.name;
  EXPECT_STREQ(c.profile, "uncompressed");
  EXPECT_EQ(c.profile_json, nullptr);
  EXPECT_EQ(c.ratio, -1);
  EXPECT_EQ(c.direction_fit, 1);
  EXPECT_EQ(c.measure, 0);
  EXPECT_EQ(c.plane_metadata, 1);
}

// An enumeration's C range is its strategy table's size.
TEST(OptionTable, CEnumRangesComeFromTheStrategyTables) {
  const OptionRow& fit = ahd::option_row("direction_fit");
  ASSERT_EQ(fit.values.size(), ahd::kDirectionFits.size());
  ahd_options c;
  ahd_options_init(&c);
  ConversionOptions o;
  c.direction_fit = int(ahd::kDirectionFits.size()) - 1;
  fit.from_c(c, o);
  EXPECT_EQ(o.direction_fit, ahd::kDirectionFits.back().value);
  c.direction_fit = int(ahd::kDirectionFits.size());
  EXPECT_THROW(fit.from_c(c, o), ahd::Error);
  c.bc6h_quality = int(ahd::kBc6hQualities.size());
  EXPECT_THROW(ahd::option_row("bc6h_quality").from_c(c, o), ahd::Error);
  c.ratio = -2;
  EXPECT_THROW(ahd::option_row("ratio").from_c(c, o), ahd::Error);
  // The parsers take exactly the names.
  for (const auto& e : ahd::kMeasures) {
    ahd::option_row("measure").parse(o, e.name);
    EXPECT_EQ(o.measure, e.value);
  }
  EXPECT_THROW(ahd::option_row("measure").parse(o, "Full"), ahd::Error);
}

TEST(OptionTable, DocsTableMatchesTheTable) {
  const std::string doc = read_source(std::string("docs/") + "library.md");
  const std::string begin = "<!-- option table: generated from src/api/option_table.cpp -->\n", end = "<!-- end of option table -->";
  const size_t b = doc.find(begin), e = doc.find(end);
  ASSERT_NE(b, std::string::npos) << "docs/library.md lost its option table markers";
  ASSERT_NE(e, std::string::npos);
  EXPECT_EQ(doc.substr(b + begin.size(), e - b - begin.size()), ahd::options_docs_table())
      << "docs/library.md's option table differs from the table: replace it with the text above";
}

TEST(OptionTable, CtypesMirrorHasEveryCMemberInOrder) {
  const std::string py = read_source("tests/python/convert_with_ctypes.py");
  const size_t at = py.find("class Options(ctypes.Structure):");
  ASSERT_NE(at, std::string::npos);
  const std::string fields = py.substr(at, py.find("]\n", at) - at);
  std::vector<std::string> got;
  const std::regex field(R"re(\("([a-z_0-9]+)", ctypes\.)re");
  for (auto it = std::sregex_iterator(fields.begin(), fields.end(), field); it != std::sregex_iterator(); ++it)
    got.push_back((*it)[1]);
  std::vector<std::string> want = {"struct_size"};
  for (const OptionRow* r : rows_in_c_order()) want.push_back(r->name);
  EXPECT_EQ(got, want);
}

// The stage structs' defaults are the public ones: a conversion below the API (the report commands,
// the tests) runs what ahd::convert runs.
TEST(OptionTable, InternalDefaultsAreThePublicOnes) {
  const ahd::ResolvedOptions r = ahd::resolve_options(ConversionOptions{}, "s");
  const ahd::PipelineOptions p;
  EXPECT_EQ(p.fit.direction_fit, r.convert.fit.direction_fit);
  EXPECT_EQ(p.fit.dz_min, r.convert.fit.dz_min);
  EXPECT_EQ(p.fit.ratio_form, r.convert.fit.ratio_form);
  EXPECT_EQ(p.closed_loop, r.convert.closed_loop);
  EXPECT_EQ(p.measure, r.convert.measure);
  EXPECT_EQ(p.codec.bc6h_quality, r.convert.codec.bc6h_quality);
  EXPECT_EQ(p.threads, r.convert.threads);
  EXPECT_EQ(p.max_levels, r.convert.max_levels);
  EXPECT_EQ(p.coverage_plane, r.convert.coverage_plane);
  EXPECT_EQ(p.direction, r.convert.direction);
  EXPECT_EQ(p.ambient_threshold, r.convert.ambient_threshold);
  const ahd::PackageOptions k;
  EXPECT_EQ(k.container, r.package.container);
  EXPECT_EQ(k.zstd, r.package.zstd);
  EXPECT_EQ(k.plane_metadata, r.package.plane_metadata);
  EXPECT_EQ(k.iz_scale, r.package.iz_scale);
}
