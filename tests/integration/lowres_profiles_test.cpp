// The built-in profiles below 2.5 B/texel (issue 43: pc-bc-half, pc-bc-quarter) through the command
// line: convert, the manifest's per-plane sizes, inspect, decode at every level, verify against the
// source, preview, and a transcode of the kept intermediate — nothing assumes the planes share I_z's size.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "file_bytes.h"
#include "files/container_file.h"
#include "pipeline/plane_scale.h"

namespace fs = std::filesystem;
using ahd_test::run_cli;

TEST(LowResProfiles, ConvertInspectDecodeVerifyPreviewTranscode) {
  const fs::path d = ahd_test::temp_dir("lowres_profiles");
  const fs::path src = d / "s.exr";
  ASSERT_EQ(run_cli({"sample", "-o", src.string(), "--size", "50"}).exit_code, 0);
  ASSERT_EQ(run_cli({"convert", src.string(), "-o", (d / "full" / "s.ktx2").string(), "--profile", "pc-bc", "-q"}).exit_code, 0);
  const ahd::Texture full_iz = ahd::read_container_file(ahd_test::plane_file((d / "full" / "s.json").string(), "iz"));
  for (const auto& [profile, s] : {std::pair<std::string, int>{"pc-bc-half", 2}, {"pc-bc-quarter", 4}}) {
    for (const char* ext : {"ktx2", "dds"}) {
      SCOPED_TRACE(profile + " " + ext);
      const fs::path out = d / (profile + "-" + ext);
      const fs::path man = out / "s.json";
      auto r = run_cli({"convert", src.string(), "-o", (out / (std::string("s.") + ext)).string(), "--profile", profile,
                        "--keep-intermediate", "-q"});
      ASSERT_EQ(r.exit_code, 0) << r.output;
      const nlohmann::json m = nlohmann::json::parse(ahd_test::read_text(man));
      const uint32_t sw = ahd::scaled_plane_size(50, s);
      for (const auto& p : m["planes"]) {
        const bool side = p["name"] != "iz";
        EXPECT_EQ(p["width"].get<uint32_t>(), side ? sw : 50u) << p["name"];
        EXPECT_EQ(p["height"].get<uint32_t>(), side ? sw : 50u) << p["name"];
        EXPECT_EQ(p["levels"].get<uint32_t>(), side ? ahd::full_mip_count(sw, sw) : ahd::full_mip_count(50, 50));
        const ahd::Texture t = ahd::read_container_file((out / p["file"].get<std::string>()).string());
        EXPECT_EQ(t.levels[0].width, side ? sw : 50u);
      }
      // I_z is pc-bc's, level by level.
      const ahd::Texture iz = ahd::read_container_file(ahd_test::plane_file(man.string(), "iz"));
      ASSERT_EQ(iz.levels.size(), full_iz.levels.size());
      for (size_t l = 0; l < iz.levels.size(); ++l) EXPECT_EQ(iz.levels[l].data, full_iz.levels[l].data) << l;
      r = run_cli({"inspect", man.string()});
      EXPECT_EQ(r.exit_code, 0) << r.output;
      for (const char* level : {"0", "5"}) {  // 5: past the side planes' chain at ¼ (13² has 4 levels)
        r = run_cli({"decode", man.string(), "--level", level, "-o", (out / (std::string("e") + level + ".exr")).string()});
        EXPECT_EQ(r.exit_code, 0) << r.output;
      }
      r = run_cli({"verify", man.string(), "--source", src.string(), "--max-rel-p99", "1"});
      EXPECT_NE(r.output.find("rel-p99"), std::string::npos) << r.output;
      r = run_cli({"preview", man.string(), "-o", (out / "page").string()});
      EXPECT_EQ(r.exit_code, 0) << r.output;
      // The intermediate transcodes to the same planes.
      r = run_cli({"transcode", (out / "s.ahd.exr").string(), "-o", (out / "t" / (std::string("s.") + ext)).string(),
                   "--profile", profile, "-q"});
      ASSERT_EQ(r.exit_code, 0) << r.output;
      for (const char* plane : {"iz", "dir", "ratio"}) {
        const ahd::Texture a = ahd::read_container_file(ahd_test::plane_file(man.string(), plane));
        const ahd::Texture b = ahd::read_container_file(ahd_test::plane_file((out / "t" / "s.json").string(), plane));
        ASSERT_EQ(a.levels.size(), b.levels.size()) << plane;
        for (size_t l = 0; l < a.levels.size(); ++l) EXPECT_EQ(a.levels[l].data, b.levels[l].data) << plane << " " << l;
      }
    }
  }
  fs::remove_all(d);
}
