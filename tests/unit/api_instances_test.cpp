// ApiInstances.*: ahd::convert with the scene's lightmapped instances (<ahd/convert.h>, the
// overload taking a std::vector<LightmapInstance>; <ahd/bakers.h> BakeRead::instances) writes the
// manifest "instances" the command writes (docs/container-format.md "Instances"); without them the
// manifest is byte for byte the one of before. The installed-package comparison with the CLI on a
// real Godot project is Consumer.InstalledBakersMatchCli (tests/consumer/bakers.sh).
#include <ahd/convert.h>
#include <ahd/sample.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace {

const ahd::ShImage& sample16() {
  static const ahd::ShImage sh = ahd::bake_sample(16, 2, 0, 1);
  return sh;
}

std::string manifest_of(const ahd::Conversion& c) {
  const ahd::OutputFile& m = c.files.back();
  EXPECT_EQ(m.name, "s.json");
  return std::string(m.bytes.begin(), m.bytes.end());
}

}  // namespace

TEST(ApiInstances, ConvertWritesTheInstancesIntoTheManifest) {
  ahd::LightmapInstance a, b;
  a.node = "../Level/Wall";
  a.uv_scale[0] = 0.25, a.uv_scale[1] = 0.5, a.uv_offset[0] = 0.5, a.uv_offset[1] = 0.125;
  b.node = "Floor";
  const ahd::Conversion with = ahd::convert(sample16(), "s", {}, {a, b});
  const nlohmann::json m = nlohmann::json::parse(manifest_of(with));
  ASSERT_TRUE(m.contains("instances")) << m.dump(1);
  ASSERT_EQ(m["instances"].size(), 2u);
  EXPECT_EQ(m["instances"][0]["node"], "../Level/Wall");
  EXPECT_EQ(m["instances"][0]["page"], 0);
  EXPECT_EQ(m["instances"][0]["uv_scale"], nlohmann::json({0.25, 0.5}));
  EXPECT_EQ(m["instances"][0]["uv_offset"], nlohmann::json({0.5, 0.125}));
  EXPECT_EQ(m["instances"][0]["direction_frame"], m["decode"]["direction_frame"]);
  EXPECT_EQ(m["instances"][1]["node"], "Floor");
  EXPECT_TRUE(m.contains("instance_uv"));
  // The planes do not depend on the instances; without any, the manifest of before.
  const ahd::Conversion plain = ahd::convert(sample16(), "s", {});
  const ahd::Conversion none = ahd::convert(sample16(), "s", {}, {});
  ASSERT_EQ(plain.files.size(), with.files.size());
  for (size_t i = 0; i + 2 < plain.files.size(); ++i) EXPECT_EQ(plain.files[i].bytes, with.files[i].bytes);
  EXPECT_EQ(manifest_of(none), manifest_of(plain));
  EXPECT_EQ(manifest_of(plain).find("instances"), std::string::npos);
}

TEST(ApiInstances, AnInstanceOnAPageTheConversionHasNotIsRefused) {
  ahd::LightmapInstance a;
  a.node = "Wall";
  a.page = 1;
  try {
    ahd::convert(sample16(), "s", {}, {a});
    FAIL() << "no error";
  } catch (const ahd::Error& e) {
    EXPECT_EQ(std::string(e.what()), "instance Wall: page 1 of a one-page conversion");
  }
}
