// EngineGuide.*: docs/engine-integration.md shows the files the tests run. Every code block marked
// `<!-- example: PATH -->` must appear verbatim in PATH, and the guide must show the three.js
// module, the page ThreeRender.* loads and the GLSL decode; those files must be what the render
// tests use (render_check.html imports ahd_three.js and fetches ahd_decode.glsl).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include "file_bytes.h"
#include "test_data.h"

namespace fs = std::filesystem;

namespace {
}  // namespace

TEST(EngineGuide, ExamplesAreTheTestedFiles) {
  const std::string guide = ahd_test::read_text(ahd_test::kSourceDir / "docs" / "engine-integration.md");
  ASSERT_FALSE(guide.empty());
  const std::string marker = "<!-- example: ";
  std::set<std::string> shown;
  for (size_t k = guide.find(marker); k != std::string::npos; k = guide.find(marker, k + 1)) {
    const size_t pe = guide.find(" -->", k);
    const std::string path = guide.substr(k + marker.size(), pe - (k + marker.size()));
    const size_t open = guide.find("```", pe), body = guide.find('\n', open) + 1, close = guide.find("\n```", body);
    ASSERT_NE(close, std::string::npos) << path;
    const std::string code = guide.substr(body, close - body);
    const std::string file = ahd_test::read_text(ahd_test::kSourceDir / path);
    ASSERT_FALSE(file.empty()) << path;
    EXPECT_NE(file.find(code), std::string::npos) << "the guide's block is not in " << path << ":\n" << code;
    shown.insert(path);
  }
  for (const char* p : {"formats/engine/three/ahd_three.js", "docs/examples/three/render_check.html",
                        "formats/shaders/ahd_decode.glsl", "addons/ahdpack/ahd_lightmap.gd",
                        "addons/ahdpack/ahd_lightmap.gdshader", "docs/examples/godot/render_check/main.gd"})
    EXPECT_TRUE(shown.count(p)) << "the guide shows nothing of " << p;
  const std::string page = ahd_test::read_text(ahd_test::kSourceDir / "docs" / "examples" / "three" / "render_check.html");
  EXPECT_NE(page.find("from '../ahd/formats/engine/three/ahd_three.js'"), std::string::npos);
  EXPECT_NE(page.find("fetch('../ahd/formats/shaders/ahd_decode.glsl')"), std::string::npos);
  EXPECT_NE(ahd_test::read_text(ahd_test::kSourceDir / "tests" / "judges" / "three_render_test.cpp").find("/page/render_check.html"),
            std::string::npos);
  // The Godot test (GodotAddon.*) runs the project the guide shows, with the add-on it shows,
  // through the shared runner (tests/support/godot_run.h: docs/examples/godot/<project>, addons/ahdpack).
  const std::string godot_test = ahd_test::read_text(ahd_test::kSourceDir / "tests" / "judges" / "godot_addon_test.cpp");
  EXPECT_NE(godot_test.find("run_godot(\"render_check\""), std::string::npos);
  EXPECT_NE(godot_test.find("files.add_addon()"), std::string::npos);
  const std::string runner = ahd_test::read_text(ahd_test::kSourceDir / "tests" / "support" / "godot_run.h");
  EXPECT_NE(runner.find("\"docs\" / \"examples\" / \"godot\" / project"), std::string::npos);
  EXPECT_NE(runner.find("\"addons\" / \"ahdpack\""), std::string::npos);
}

// The add-on's Godot include carries the GLSL decode's functions verbatim (the Godot test renders
// the include; the GL and three.js tests the GLSL file).
TEST(EngineGuide, GodotIncludeIsTheGlslDecode) {
  const std::string glsl = ahd_test::read_text(ahd_test::kSourceDir / "formats" / "shaders" / "ahd_decode.glsl");
  const std::string inc = ahd_test::read_text(ahd_test::kSourceDir / "addons" / "ahdpack" / "ahd_decode.gdshaderinc");
  const size_t k = glsl.find("vec3 ahd_hemi_oct_decode");
  ASSERT_NE(k, std::string::npos);
  EXPECT_NE(inc.find(glsl.substr(k)), std::string::npos)
      << "addons/ahdpack/ahd_decode.gdshaderinc differs from formats/shaders/ahd_decode.glsl";
  EXPECT_NE(ahd_test::read_text(ahd_test::kSourceDir / "addons" / "ahdpack" / "ahd_lightmap.gdshader")
                .find("#include \"res://addons/ahdpack/ahd_decode.gdshaderinc\""),
            std::string::npos);
}
