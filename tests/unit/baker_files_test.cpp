// The files users have (issue 16): every preset reads its set when given any file of the set
// ("World.exr", "Lightmap-0_comp_light.exr", "Scene_LM0_L0.hdr", "Scene_LM0_L1x.tga") exactly as
// when given the base name — one test per preset, each file of the set tried in turn.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>

#include <OpenImageIO/imageio.h>

#include "containers/container.h"
#include "image/colour_space.h"
#include "pipeline/plane_codec.h"
#include "image/sh_exr.h"
#include "layout_test_scene.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace layout_test;

namespace {

ShImage l2_scene() {
  BakerOptions bo;
  bo.width = bo.height = N;
  bo.coeffs = 9;
  return bake_analytic_scene(bo);
}

// Writes the preset's set for b.base() in the preset's layout (values need only be readable).
void write_set(const std::string& preset, const WorldBake& b) {
  const std::string base = b.base();
  if (preset == "godot4-packed" || preset == "godot4-unpacked") return write_godot_packed(b.w, base + ".exr");
  if (preset == "bakery-sh") return write_bakery_sh(b.w, base);
  if (preset == "bakery-monosh") return write_bakery_monosh(b.w, base);
  if (preset == "unity-directional") return write_unity_directional(b.w, base);
  if (preset == "three-rgba") return write_three_rgba(b.w, base);
  if (preset == "exr-layers-l1") return write_exr_layers(base + ".exr", b.w.tangent);
  if (preset == "exr-layers-l2") return write_exr_layers(base + ".exr", l2_scene());
  if (preset == "exr-parts-l1") return write_exr_parts(base + ".exr", b.w.tangent);
  if (preset == "exr-parts-l2") return write_exr_parts(base + ".exr", l2_scene());
  if (preset == "per-coefficient") {
    const ShImage s = l2_scene();
    for (int k = 0; k < 9; ++k) write_image(base + "_sh" + std::to_string(k) + ".exr", coefficient_image(s, k));
    return;
  }
  if (preset == "plain") return write_image(base + ".exr", coefficient_image(b.w.tangent, 0));
  if (preset == "plain-ktx2") {  // Bevy's form: B10G11R11, zstd-supercompressed
    Texture tex;
    tex.format = PixelFormat::B10G11R11_UFLOAT;
    tex.levels.push_back(encode_plane(tex.format, coefficient_image(b.w.tangent, 0), {}));
    const std::vector<uint8_t> bytes = encode_container(ContainerKind::KTX2, tex, /*zstd=*/true);
    std::ofstream(base + ".ktx2", std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    return;
  }
  if (preset == "plain-rgbm") {
    ImageF img(N, N, 4);
    for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = float((i * 7) % 256) / 255.0f;
    return write_image(base + ".png", img);
  }
  ADD_FAILURE() << "no writer for preset " << preset;
}

// Reads the set through every one of its files and through the base: all identical.
void check_every_file_reads_the_set(const std::string& preset, const std::string& stem) {
  const WorldBake b("files_" + preset);
  const LayoutPreset layout = load_layout(preset);
  write_set(preset, b);
  const std::string base = (b.dir / stem).string();
  // The set is written for base(); rename to the user-facing stem of the test.
  for (const auto& e : fs::directory_iterator(b.dir)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("lm", 0) == 0) fs::rename(e.path(), b.dir / (stem + name.substr(2)));
  }
  const std::string normals = layout.world_space ? b.normals : "";
  const ShImage want = read_layout(layout, base, normals);
  ASSERT_GT(want.texels(), 0u);
  for (const LayoutFile& lf : layout.files) {
    const std::string file = base + lf.pattern.substr(6);  // every pattern is "{base}SUFFIX"
    ASSERT_TRUE(fs::exists(file)) << file;
    const ShImage got = read_layout(layout, file, normals);
    EXPECT_EQ(got.data, want.data) << preset << " via " << file;
    EXPECT_EQ(got.coverage, want.coverage) << preset << " via " << file;
    int w = 0, h = 0;
    layout_size(layout, file, &w, &h);
    EXPECT_EQ(w, want.width);
    EXPECT_EQ(h, want.height);
  }
}

}  // namespace

TEST(BakerFiles, GodotPackedWorldExr) { check_every_file_reads_the_set("godot4-packed", "World"); }
TEST(BakerFiles, GodotUnpackedWorldExr) { check_every_file_reads_the_set("godot4-unpacked", "World"); }
TEST(BakerFiles, BakeryShSceneL0HdrAndL1xTga) { check_every_file_reads_the_set("bakery-sh", "Scene_LM0"); }
TEST(BakerFiles, BakeryMonoShSceneL0Hdr) { check_every_file_reads_the_set("bakery-monosh", "Scene_LMA1"); }
TEST(BakerFiles, UnityCompLightExr) { check_every_file_reads_the_set("unity-directional", "Lightmap-0"); }
TEST(BakerFiles, ThreeRgba) { check_every_file_reads_the_set("three-rgba", "room"); }
TEST(BakerFiles, ExrLayersL1) { check_every_file_reads_the_set("exr-layers-l1", "room"); }
TEST(BakerFiles, ExrLayersL2) { check_every_file_reads_the_set("exr-layers-l2", "room"); }
TEST(BakerFiles, ExrPartsL1) { check_every_file_reads_the_set("exr-parts-l1", "room"); }
TEST(BakerFiles, ExrPartsL2) { check_every_file_reads_the_set("exr-parts-l2", "room"); }
TEST(BakerFiles, PerCoefficient) { check_every_file_reads_the_set("per-coefficient", "room"); }
TEST(BakerFiles, PlainCompLightExr) { check_every_file_reads_the_set("plain", "Lightmap-0_comp_light"); }
TEST(BakerFiles, PlainKtx2) { check_every_file_reads_the_set("plain-ktx2", "CornellBox-Box.zstd"); }
TEST(BakerFiles, PlainRgbm) { check_every_file_reads_the_set("plain-rgbm", "room"); }

TEST(BakerFiles, CanonicalIsTheFileItself) {
  const WorldBake b("files_canonical");
  const std::string file = (b.dir / "room.exr").string();
  write_canonical_sh(file, b.w.tangent);
  const LayoutPreset layout = load_layout("canonical");
  EXPECT_EQ(layout_base(layout, file), file);
  EXPECT_EQ(read_layout(layout, file, "").data, read_canonical_sh(file).data);
}

// Every preset has a test above: a new preset must add one.
TEST(BakerFiles, EveryPresetIsCovered) {
  const std::vector<std::string> tested = {"bakery-monosh", "bakery-sh", "canonical", "exr-layers-l1", "exr-layers-l2",
                                           "exr-parts-l1", "exr-parts-l2", "godot4-packed", "godot4-unpacked",
                                           "per-coefficient", "plain", "plain-ktx2", "plain-rgbm", "three-rgba", "unity-directional"};
  EXPECT_EQ(list_layouts(), tested);
}

TEST(BakerFiles, BaseNameStillWinsAndMissingFilesAreNamed) {
  const WorldBake b("files_base");
  write_godot_packed(b.w, b.file(".exr"));
  const LayoutPreset godot = load_layout("godot4-packed");
  EXPECT_EQ(layout_base(godot, b.base()), b.base());
  EXPECT_EQ(layout_base(godot, b.file(".exr")), b.base());
  // A missing file is reported under the name the set needs, not "World.exr.exr".
  expect_error([&] { read_layout(load_layout("bakery-sh"), b.file("_L0.hdr"), b.normals); }, "lm_L0.hdr: file not found");
}

// Colour spaces as the files declare them: linear Rec.709 is read, other linear primaries are
// converted to it (tests/unit/colour_space_test.cpp checks the numbers), and a declaration nothing
// can convert is refused with one line naming it.
TEST(BakerFiles, DeclaredColourSpacesAreConvertedOrRefused) {
  const WorldBake b("files_colour");
  const ImageF img = coefficient_image(b.w.tangent, 0);
  auto write = [&](const std::string& name, const std::vector<float>& chroma, const std::string& space) {
    OIIO::ImageSpec spec(img.width, img.height, 3, OIIO::TypeDesc::HALF);
    if (!chroma.empty()) spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), chroma.data());
    if (!space.empty()) spec.attribute("oiio:ColorSpace", space);
    auto out = OIIO::ImageOutput::create(name);
    ASSERT_TRUE(out && out->open(name, spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, img.data.data()));
    out->close();
  };
  const LayoutPreset plain = load_layout("plain");
  const std::string dir = b.dir.string();
  write(dir + "/rec709.exr", {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f}, "");
  ReadStats rs;
  EXPECT_EQ(read_layout(plain, dir + "/rec709.exr", "", &rs).width, N);
  EXPECT_EQ(rs.input_space, "");
  write(dir + "/p3.exr", {0.68f, 0.32f, 0.265f, 0.69f, 0.15f, 0.06f, 0.3127f, 0.3290f}, "");
  EXPECT_EQ(read_layout(plain, dir + "/p3.exr", "", &rs).width, N);
  EXPECT_EQ(rs.input_space, "linear P3-D65");
  // A name no conversion is known for (OpenEXR files always read back as "Linear", so in memory).
  ImageFileInfo info;
  info.is_float = true;
  info.color_space = "ARRI LogC";
  expect_error([&] { declared_space(info, "x.tif"); }, "x.tif: declares colour space 'ARRI LogC'");
  info.color_space = "Linear";
  EXPECT_TRUE(declared_space(info, "x.tif").working_primaries());
}
