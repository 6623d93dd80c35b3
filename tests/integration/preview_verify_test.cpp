// `ahdpack verify` (users' CI checks) and the SVG plots of `bench bc6h --plot` / `report profiles --plot`.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <tuple>

#include "cli_runner.h"
#include "file_bytes.h"

namespace fs = std::filesystem;
using ahd_test::run_cli;

namespace {

// The SVG parsed by python3's XML parser (independent of our writer); returns the number of
// elements whose class attribute is exactly `cls`, or -1 when the file is not well-formed XML.
int count_xml_class(const fs::path& svg, const std::string& cls) {
  const std::string cmd = "python3 -c \"import sys, xml.etree.ElementTree as E; r = E.parse(sys.argv[1]).getroot(); "
                          "print(sum(1 for e in r.iter() if e.get('class') == sys.argv[2]))\" '" +
                          svg.string() + "' '" + cls + "' 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  char buf[256];
  while (fgets(buf, sizeof buf, p)) out += buf;
  const int rc = pclose(p);
  if (rc != 0) {
    ADD_FAILURE() << svg << " is not well-formed XML: " << out;
    return -1;
  }
  return std::stoi(out);
}

// A converted sample: s.exr and three conversions of it: uncompressed (half-float I_z), and pc-bc
// with BC6H at quality high and fast.
struct Fixture {
  fs::path dir = ahd_test::temp_dir("verify");
  fs::path src = dir / "s.exr", exact = dir / "exact" / "s.json", high = dir / "high" / "s.json",
           fast = dir / "fast" / "s.json";
  explicit Fixture(bool all = true) {
    EXPECT_EQ(run_cli({"sample", "-o", src.string(), "--size", "64"}).exit_code, 0);
    for (auto [m, profile, q] : {std::tuple{high, "pc-bc", "high"}, std::tuple{exact, "uncompressed", "default"},
                                 std::tuple{fast, "pc-bc", "fast"}}) {
      if (!all && m != high) continue;
      const auto r = run_cli({"convert", src.string(), "-o", (m.parent_path() / "s.ktx2").string(), "--profile", profile,
                              "--quality", q});
      EXPECT_EQ(r.exit_code, 0) << r.output;
    }
  }
  // A copy of conversion `into` whose iz plane (file and manifest entry) is the one of `from`: a
  // consistent manifest (sizes and hashes match), so only the bounds can tell.
  fs::path swapped_iz(const fs::path& into, const fs::path& from, const std::string& tag) {
    const fs::path d = dir / tag;
    fs::create_directories(d);
    nlohmann::json mi = nlohmann::json::parse(ahd_test::read_text(into)), mf = nlohmann::json::parse(ahd_test::read_text(from));
    for (auto& p : mi["planes"]) {
      fs::path folder = into.parent_path();
      if (p["name"] == "iz") {
        for (const auto& q : mf["planes"])
          if (q["name"] == "iz") p = q;
        folder = from.parent_path();
      }
      fs::copy_file(folder / p["file"].get<std::string>(), d / p["file"].get<std::string>());
    }
    std::ofstream(d / "s.json") << mi.dump(2);
    return d / "s.json";
  }
};

double value_of(const std::string& out, const std::string& check) {
  std::smatch m;
  if (!std::regex_search(out, m, std::regex("(PASS|FAIL)  " + check + " +([0-9.e+-]+) <="))) return -1;
  return std::stod(m[2]);
}

}  // namespace

TEST(Verify, FreshConversionPassesAndASwappedPlaneFails) {
  Fixture f;
  // Against the source with the default bounds: every check passes, one line each.
  auto r = run_cli({"verify", f.high.string(), "--source", f.src.string()});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  for (const char* check : {"rel-p99", "log-rmse", "iz-rel-p99"})
    EXPECT_NE(r.output.find(std::string("PASS  ") + check), std::string::npos) << r.output;
  // Against itself as the golden: identical decode.
  r = run_cli({"verify", f.high.string(), "--golden", f.high.string()});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(value_of(r.output, "golden-diff-p99"), 0.0) << r.output;

  // pc-bc high with its iz plane replaced by the quality-fast one, against the golden high
  // conversion: the difference check fails, exit 1, naming the check, no error line.
  const fs::path fast_iz = f.swapped_iz(f.high, f.fast, "high_with_fast_iz");
  r = run_cli({"verify", fast_iz.string(), "--golden", f.high.string()});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("FAIL  golden-diff-p99"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("error"), std::string::npos) << r.output;

  // The uncompressed conversion (half-float I_z) with its iz plane replaced by the BC6H one,
  // against the source with the I_z bound such a conversion's CI would set (1 %): fails on iz.
  const fs::path bc6h_iz = f.swapped_iz(f.exact, f.high, "exact_with_bc6h_iz");
  r = run_cli({"verify", f.exact.string(), "--source", f.src.string(), "--max-iz-rel-p99", "0.01"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_LT(value_of(r.output, "iz-rel-p99"), 0.002) << r.output;
  r = run_cli({"verify", bc6h_iz.string(), "--source", f.src.string(), "--max-iz-rel-p99", "0.01"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("FAIL  iz-rel-p99"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("PASS  rel-p99"), std::string::npos) << r.output;
}

TEST(Verify, BadInputIsOneErrorLine) {
  Fixture f(false);  // pc-bc high only
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"verify", f.high.string()},  // neither --source nor --golden
        {"verify", (f.dir / "missing.json").string(), "--source", f.src.string()},
        {"verify", f.high.string(), "--source", (f.dir / "missing.exr").string()}}) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_EQ(r.output.rfind("ahdpack: error: ", 0), 0u) << r.output;
  }
  // A source of another size.
  const fs::path other = f.dir / "other.exr";
  ASSERT_EQ(run_cli({"sample", "-o", other.string(), "--size", "32"}).exit_code, 0);
  const auto r = run_cli({"verify", f.high.string(), "--source", other.string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("is 32x32, the conversion is 64x64"), std::string::npos) << r.output;
}

TEST(Plot, BenchBc6hHasOnePointPerImageAndQuality) {
  const fs::path d = ahd_test::temp_dir("plot_bench");
  fs::create_directories(d / "imgs");
  // Two small images (the sample's SH EXR: bench encodes its first three channels).
  // One named like a PEERS.md image, so its peers are drawn beside it.
  ASSERT_EQ(run_cli({"sample", "-o", (d / "imgs" / "lightmap_smooth.exr").string(), "--size", "32"}).exit_code, 0);
  ASSERT_EQ(run_cli({"sample", "-o", (d / "imgs" / "b.exr").string(), "--size", "32", "--seed", "3"}).exit_code, 0);
  const auto r = run_cli({"bench", "bc6h", (d / "imgs").string(), "--codecs", "bc6h", "--qualities", "fast", "default",
                          "--plot", (d / "bench.svg").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(count_xml_class(d / "bench.svg", "point ours"), 2 * 2);
  // The peers' figures for lightmap_smooth.exr (all 8 encoders of the table have one); none for b.exr.
  EXPECT_EQ(count_xml_class(d / "bench.svg", "point peer"), 8);
}

TEST(Plot, BenchBc6hByDefaultCoversTheSyntheticAndTheRealImages) {
  // No folder: the shared synthetic images (tests/data/bc6h) and the real-lightmap corpus
  // of bench/data/real, every image in the table; several folders are read in turn.
  const auto r = run_cli({"bench", "bc6h", "--codecs", "bc6h", "--qualities", "fast"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* real : {"godot42-vermilion_iz.exr", "godot-ragdoll-plain_iz_1024.exr"})
    EXPECT_NE(r.output.find(real), std::string::npos) << r.output;
  if (fs::exists(fs::path(AHD_TEST_DATA_DIR) / "bc6h" / "lightmap_smooth.exr"))
    for (const char* synthetic : {"lightmap_smooth.exr", "hdr_hard.exr", "lightmap_noisy.exr"})
      EXPECT_NE(r.output.find(synthetic), std::string::npos) << r.output;
  const fs::path d = ahd_test::temp_dir("bench_folders");
  fs::create_directories(d / "empty");
  const auto bad = run_cli({"bench", "bc6h", (fs::path(AHD_SOURCE_DIR) / "bench" / "data" / "real").string(),
                            (d / "empty").string(), "--codecs", "bc6h", "--qualities", "fast"});
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.output.find("no EXR images in this folder"), std::string::npos) << bad.output;
  fs::remove_all(d);
}

TEST(Plot, ReportProfilesHasOnePointPerProfileAndSet) {
  const fs::path d = ahd_test::temp_dir("plot_profiles");
  const auto r = run_cli({"report", "profiles", "--size", "16", "--plot", (d / "profiles.svg").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // One point per closed-loop row of the table (profile × set).
  size_t rows = 0;
  for (size_t at = 0; (at = r.output.find("| closed |", at)) != std::string::npos; ++at) ++rows;
  EXPECT_GE(rows, 8u);
  EXPECT_EQ(count_xml_class(d / "profiles.svg", "point ours"), int(rows));
}
