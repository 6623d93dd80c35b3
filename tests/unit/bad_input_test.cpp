// The bad-input catalogue (issue 15): every named bad input must give one ahd::Error of one line
// "<file>: <cause>", write no file, and leave the previous outputs untouched. In-process (the
// library calls the CLI makes); bad_input_cli_test.cpp runs a representative handful through the
// command line. docs/robustness.md "The catalogue of bad input" lists it; keep both in step.
#include <gtest/gtest.h>
#include <zstd.h>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>

#include "files/manifest_file.h"
#include "files/container_file.h"
#include "files/profile_file.h"
#include "cli_runner.h"
#include "file_bytes.h"
#include "sanitized.h"
#include "containers/container.h"
#include "containers/dds.h"
#include "containers/ktx2.h"
#include "containers/limits.h"
#include "containers/sha256.h"
#include "core/error.h"
#include "image/ahd_intermediate.h"
#include "bakers/baker_layout.h"
#include "image/image_io.h"
#include "scene/mesh_io.h"
#include "files/output_set.h"
#include "image/sh_exr.h"
#include "pipeline/convert.h"
#include "pipeline/manifest.h"
#include "sample/analytic_baker.h"
#include "bad_input_fixture.h"

namespace fs = std::filesystem;
using namespace ahd;
using namespace ahd_fixture::bad_input_fixture;

namespace {
std::vector<Case> catalogue();  // below, after the test that runs it
}  // namespace

TEST(BadInput, CatalogueEachGivesOneLineNamingTheFileAndWritesNothing) {
  const std::vector<Case> cases = catalogue();
  EXPECT_GE(cases.size(), 40u);
  const fs::path root = ahd_test::temp_dir("bad_input");
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path d = root / c.name;
    fs::create_directories(d);
    write_previous_set(d);
    auto [call, file] = c.make(d);
    const auto before = snapshot_tree(d);
    try {
      call();
      ADD_FAILURE() << c.name << ": accepted";
    } catch (const Error& e) {
      const std::string m = e.what();
      if (std::getenv("AHD_PRINT_CATALOGUE")) std::printf("| %s | `%s` |\n", c.name.c_str(), m.substr(d.string().size() + 1).c_str());
      EXPECT_EQ(m.rfind(file + ": ", 0), 0u) << c.name << ": does not start with the file: " << m;
      EXPECT_NE(m.find(c.cause), std::string::npos) << c.name << ": expected '" << c.cause << "' in: " << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    } catch (const std::exception& e) {
      ADD_FAILURE() << c.name << ": not an ahd::Error: " << e.what();
    }
    EXPECT_EQ(snapshot_tree(d), before) << c.name << ": files were added, changed or removed";
    // The previous set still decodes.
    EXPECT_NO_THROW(decode_manifest((d / "prev.json").string())) << c.name;
  }
  fs::remove_all(root);
}

namespace {

// Cases reading a container file: the bytes of a valid file, edited.
Case container_case(const std::string& name, const char* ext, std::function<void(std::vector<uint8_t>&)> edit,
                    const std::string& cause, PixelFormat f = PixelFormat::RGBA16_SFLOAT, bool zstd = false) {
  return {name,
          [=](const fs::path& d) {
            const fs::path p = d / (std::string("in.") + ext);
            const Texture t = plain_texture(f, 16, 8, 3);
            std::vector<uint8_t> b = std::string(ext) == "dds" ? write_dds(t) : write_ktx2(t, {zstd, 3});
            edit(b);
            spit(p, b);
            return std::pair{std::function<void()>([p] { read_container_file(p.string()); }), p.string()};
          },
          cause};
}

// A manifest written beside the previous set, edited as JSON text.
Case manifest_case(const std::string& name, std::function<void(std::string&)> edit, const std::string& cause,
                   bool cause_names_plane = false) {
  return {name,
          [=](const fs::path& d) {
            std::string text(reinterpret_cast<const char*>(slurp(d / "prev.json").data()), slurp(d / "prev.json").size());
            edit(text);
            spit(d / "bad.json", text);
            const std::string p = (d / "bad.json").string();
            std::string named = p;
            if (cause_names_plane) {  // the error names the plane file that fails its check
              const Manifest m = manifest_from_json(text, p);
              named = (d / m.planes[0].file).string();
            }
            return std::pair{std::function<void()>([p] { decode_manifest(p); }), named};
          },
          cause};
}

void replace(std::string& s, const std::string& from, const std::string& to, bool last = false) {
  const size_t at = last ? s.rfind(from) : s.find(from);
  if (at == std::string::npos) throw std::runtime_error("test edit: '" + from + "' not in the manifest");
  s.replace(at, from.size(), to);
}

// An EXR with the canonical channels; `edit` changes the image before it is written.
Case sh_exr_case(const std::string& name, std::function<void(const fs::path&)> write, const std::string& cause) {
  return {name,
          [=](const fs::path& d) {
            const fs::path p = d / "in.exr";
            write(p);
            return std::pair{std::function<void()>([p] { read_canonical_sh(p.string()); }), p.string()};
          },
          cause};
}

// The bytes of an EXR header attribute's value ("dataWindow" box2i: xmin ymin xmax ymax).
size_t exr_attribute(const std::vector<uint8_t>& b, const std::string& name) {
  const std::string key = name + std::string(1, '\0');
  for (size_t i = 8; i + key.size() < b.size(); ++i)
    if (std::equal(key.begin(), key.end(), b.begin() + std::ptrdiff_t(i))) {
      size_t at = i + key.size();
      while (b[at] != 0) ++at;  // type name
      return at + 1 + 4;        // NUL, then the 4-byte size
    }
  throw std::runtime_error("no EXR attribute " + name);
}

// A tiny zstd frame that claims `content` bytes and holds 16 (the allocation bomb of issue 15).
std::vector<uint8_t> lying_zstd_frame(uint64_t content) {
  std::vector<uint8_t> f = {0x28, 0xB5, 0x2F, 0xFD, 0xC0, 0x50};  // magic; 8-byte content size; 1 MiB window
  for (int i = 0; i < 8; ++i) f.push_back(uint8_t(content >> (8 * i)));
  const uint32_t block = 1u | (16u << 3);  // last block, raw, 16 bytes
  f.push_back(uint8_t(block)), f.push_back(uint8_t(block >> 8)), f.push_back(uint8_t(block >> 16));
  for (int i = 0; i < 16; ++i) f.push_back(uint8_t(i));
  return f;
}

// A KTX2 that claims w x h RGBA16F with zstd, whose one level is a lying frame.
std::vector<uint8_t> zstd_bomb_ktx2(uint32_t w, uint32_t h) {
  Texture t = plain_texture(PixelFormat::RGBA16_SFLOAT, 1, 1, 1);
  std::vector<uint8_t> b = write_ktx2(t, {true, 3});
  const uint64_t level_at = b.size() - 0;  // level data appended at the end
  const uint64_t claim = uint64_t(w) * h * 8;
  const std::vector<uint8_t> frame = lying_zstd_frame(claim);
  // Replace the level: header size, then the level index entry 0 (offset, length, uncompressed).
  const uint64_t old_off = b[80] | uint64_t(b[81]) << 8 | uint64_t(b[82]) << 16 | uint64_t(b[83]) << 24;
  b.resize(old_off);
  (void)level_at;
  b.insert(b.end(), frame.begin(), frame.end());
  wr32(b, 20, w);
  wr32(b, 24, h);
  wr64(b, 80, old_off);
  wr64(b, 88, frame.size());
  wr64(b, 96, claim);
  return b;
}

std::vector<Case> catalogue() {
  std::vector<Case> c;
  using B = std::vector<uint8_t>;
  // --- KTX2 ---
  c.push_back(container_case("ktx2-truncated-header", "ktx2", [](B& b) { b.resize(40); }, "not a KTX2 file"));
  c.push_back(container_case("ktx2-truncated-level", "ktx2", [](B& b) { b.resize(b.size() - 7); }, "truncated"));
  c.push_back(container_case("ktx2-bitflip-identifier", "ktx2", [](B& b) { b[5] ^= 0x10; }, "bad identifier"));
  c.push_back(container_case("ktx2-unknown-vkformat", "ktx2", [](B& b) { wr32(b, 12, 12345); }, "unsupported vkFormat"));
  c.push_back(container_case("ktx2-zero-width", "ktx2", [](B& b) { wr32(b, 20, 0); }, "unsupported size"));
  c.push_back(container_case("ktx2-over-size-limit", "ktx2", [](B& b) { wr32(b, 20, 32768), wr32(b, 24, 32768); },
                             "over the size limit of 16384x16384"));
  c.push_back(container_case("ktx2-100000x1", "ktx2", [](B& b) { wr32(b, 20, 100000), wr32(b, 24, 1); }, "unsupported size"));
  c.push_back(container_case("ktx2-too-many-levels", "ktx2", [](B& b) { wr32(b, 40, 9); }, "invalid level count"));
  c.push_back(container_case("ktx2-level-offset-out-of-file", "ktx2", [](B& b) { wr64(b, 80, 1u << 30); }, "out-of-bounds level data"));
  c.push_back(container_case("ktx2-level-size-lies", "ktx2", [](B& b) { wr64(b, 96, 999); }, "expected"));
  c.push_back(container_case("ktx2-dfd-mismatch", "ktx2", [](B& b) { wr32(b, 12, 37); wr32(b, 16, 1); }, "Data Format Descriptor"));
  c.push_back(container_case("ktx2-kvd-length-lies", "ktx2",
                             [](B& b) { const uint32_t at = uint32_t(b[56] | b[57] << 8 | b[58] << 16); wr32(b, at, 0x7FFFFFF0); },
                             "malformed key/value"));
  c.push_back(container_case("ktx2-zstd-frame-cut-short", "ktx2", [](B& b) { wr64(b, 88, uint64_t(b[88] | b[89] << 8) - 3); }, "zstd",
                             PixelFormat::RGBA16_SFLOAT, true));
  c.push_back(container_case("ktx2-zstd-bad-magic", "ktx2", [](B& b) { b[b[80] | b[81] << 8] ^= 0xFF; }, "zstd",
                             PixelFormat::RGBA16_SFLOAT, true));
  c.push_back({"ktx2-zstd-allocation-bomb-16384", [](const fs::path& d) {
                 const fs::path p = d / "bomb.ktx2";
                 spit(p, zstd_bomb_ktx2(16384, 16384));
                 return std::pair{std::function<void()>([p] { read_container_file(p.string()); }), p.string()};
               },
               "level 0"});
  c.push_back({"ktx2-zstd-allocation-bomb-32768", [](const fs::path& d) {
                 const fs::path p = d / "bomb.ktx2";
                 spit(p, zstd_bomb_ktx2(32768, 32768));
                 return std::pair{std::function<void()>([p] { read_container_file(p.string()); }), p.string()};
               },
               "over the size limit"});
  c.push_back({"ktx2-unsupported-supercompression", [](const fs::path& d) {
                 const fs::path p = d / "in.ktx2";
                 B b = write_ktx2(plain_texture(PixelFormat::R8_UNORM, 4, 4), {});
                 wr32(b, 44, 1);  // BasisLZ
                 spit(p, b);
                 return std::pair{std::function<void()>([p] { read_container_file(p.string()); }), p.string()};
               },
               "supercompression"});
  // --- DDS ---
  c.push_back(container_case("dds-truncated-header", "dds", [](B& b) { b.resize(60); }, "not a DDS file"));
  c.push_back(container_case("dds-truncated-level", "dds", [](B& b) { b.resize(b.size() - 1); }, "truncated"));
  c.push_back(container_case("dds-bad-header-size", "dds", [](B& b) { wr32(b, 4, 100); }, "invalid DDS header size"));
  c.push_back(container_case("dds-unknown-dxgi", "dds", [](B& b) { wr32(b, 128, 999); }, "unsupported DXGI format"));
  c.push_back(container_case("dds-over-size-limit", "dds", [](B& b) { wr32(b, 12, 20000), wr32(b, 16, 20000); }, "over the size limit"));
  c.push_back(container_case("dds-zero-height", "dds", [](B& b) { wr32(b, 12, 0); }, "unsupported size"));
  c.push_back(container_case("dds-too-many-mips", "dds", [](B& b) { wr32(b, 28, 30); }, "invalid mip count"));
  c.push_back(container_case("dds-cube-map", "dds", [](B& b) { wr32(b, 136, 4); }, "cube maps"));
  // Arrays are read (atlas pages); one that claims more layers than its data holds is refused.
  c.push_back(container_case("dds-array", "dds", [](B& b) { wr32(b, 140, 6); }, "truncated"));
  // --- manifests ---
  c.push_back(manifest_case("manifest-truncated", [](std::string& s) { s.resize(s.size() / 2); }, "not a JSON manifest"));
  c.push_back(manifest_case("manifest-not-ours", [](std::string& s) { replace(s, "ahdpack-manifest", "other"); }, "not an ahdpack manifest"));
  c.push_back(manifest_case("manifest-version-9", [](std::string& s) { replace(s, "\"version\": 1", "\"version\": 9"); }, "version 9"));
  c.push_back(manifest_case("manifest-iz-one-channel-r8", [](std::string& s) { replace(s, "\"rgba16f\"", "\"r8\""); },
                            "plane iz cannot be r8"));
  c.push_back(manifest_case("manifest-dir-one-channel-r8", [](std::string& s) { replace(s, "\"rg8\"", "\"r8\""); },
                            "plane dir cannot be r8"));
  c.push_back(manifest_case("manifest-dir-as-hdr", [](std::string& s) { replace(s, "\"rg8\"", "\"rgba16f\""); }, "needs a UNORM"));
  c.push_back(manifest_case("manifest-plane-path-escapes", [](std::string& s) { replace(s, "\"file\": \"prev.iz", "\"file\": \"../prev.iz"); },
                            "plain name"));
  c.push_back(manifest_case("manifest-unknown-plane", [](std::string& s) { replace(s, "\"name\": \"ratio\"", "\"name\": \"alpha\""); },
                            "unknown plane alpha"));
  c.push_back(manifest_case("manifest-plane-twice", [](std::string& s) { replace(s, "\"name\": \"ratio\"", "\"name\": \"dir\""); },
                            "listed twice"));
  c.push_back(manifest_case("manifest-huge-size", [](std::string& s) { replace(s, "\"width\": 8", "\"width\": 4000000000", true); },
                            "over the size limit"));
  c.push_back(manifest_case("manifest-zero-levels", [](std::string& s) { replace(s, "\"levels\": 4", "\"levels\": 0"); },
                            "invalid level count"));
  c.push_back(manifest_case("manifest-plane-size-disagrees", [](std::string& s) {
    const size_t at = s.find("\"width\": 8", s.find("\"planes\""));
    s.replace(at, 10, "\"width\": 4");
  }, "the manifest says"));
  c.push_back(manifest_case("manifest-nan-dz-min", [](std::string& s) { replace(s, "\"dz_min\": 0.05", "\"dz_min\": NaN"); },
                            "not a JSON manifest"));
  c.push_back(manifest_case("manifest-negative-dz-min", [](std::string& s) { replace(s, "\"dz_min\": 0.05", "\"dz_min\": -1"); },
                            "dz_min"));
  c.push_back(manifest_case("manifest-missing-hash", [](std::string& s) {
    const size_t at = s.find("\"sha256\"");
    s.erase(at, s.find('\n', at) - at);
  }, "malformed manifest"));
  c.push_back(manifest_case("manifest-plane-bytes-lie", [](std::string& s) {
    const size_t at = s.find("\"bytes\": ");
    if (at != std::string::npos) s.insert(s.begin() + std::ptrdiff_t(at + 9), '1');  // (else the check fails)
  }, "does not match the manifest", true));
  c.push_back(manifest_case("manifest-plane-hash-differs (a set mixed by a crash)", [](std::string& s) {
    const size_t at = s.find("\"sha256\": \"") + 11;
    s[at] = s[at] == '0' ? '1' : '0';
  }, "content hash differs", true));
  c.push_back({"manifest-plane-file-missing", [](const fs::path& d) {
                 const Manifest m = read_manifest_file((d / "prev.json").string());
                 fs::copy_file(d / "prev.json", d / "copy.json");
                 fs::create_directories(d / "sub");
                 fs::rename(d / "copy.json", d / "sub" / "copy.json");
                 const std::string p = (d / "sub" / "copy.json").string();
                 return std::pair{std::function<void()>([p] { decode_manifest(p); }), (d / "sub" / m.planes[0].file).string()};
               },
               "missing plane file"});
  c.push_back({"manifest-plane-replaced-by-another-run", [](const fs::path& d) {
                 // Another conversion's iz file put in place of this set's iz: same format and
                 // size, other content.
                 const Manifest m = read_manifest_file((d / "prev.json").string());
                 const fs::path other = d / "other";
                 fs::create_directories(other);
                 BakerOptions bo;
                 bo.width = bo.height = 8;
                 bo.seed = 7;
                 PipelineResult r = run_conversion(bake_analytic_scene(bo), load_profile("uncompressed"), {});
                 fs::create_directories(d / "mixed");
                 for (const auto& p : m.planes) fs::copy_file(d / p.file, d / "mixed" / p.file);
                 fs::copy_file(d / "prev.json", d / "mixed" / "prev.json");
                 Texture t = r.planes[0].texture;
                 t.metadata = plane_metadata(m, "iz");
                 spit(d / "mixed" / m.planes[0].file, write_ktx2(t));
                 const std::string p = (d / "mixed" / "prev.json").string();
                 return std::pair{std::function<void()>([p] { decode_manifest(p); }), (d / "mixed" / m.planes[0].file).string()};
               },
               "does not match the manifest"});
  // --- input images ---
  c.push_back(sh_exr_case("exr-truncated", [](const fs::path& p) {
    write_sh(p, 8, 8, 0.5f);
    fs::resize_file(p, fs::file_size(p) / 2);
  }, "cannot read"));
  c.push_back(sh_exr_case("exr-bitflip-magic", [](const fs::path& p) {
    write_sh(p, 8, 8, 0.5f);
    B b = slurp(p);
    b[0] ^= 0x01;
    spit(p, b);
  }, "cannot read image"));
  c.push_back(sh_exr_case("exr-100000x1 (refused at read, before fitting)", [](const fs::path& p) { write_sh(p, 100000, 1, 0.5f); },
                          "100000x1 is over the size limit of 16384x16384"));
  c.push_back(sh_exr_case("exr-huge-data-window", [](const fs::path& p) {
    write_sh(p, 4, 4, 0.5f);
    B b = slurp(p);
    const size_t at = exr_attribute(b, "dataWindow");
    wr32(b, at + 8, 0x3FFFFFFF);  // xmax
    spit(p, b);
  }, ""));
  c.push_back(sh_exr_case("exr-inverted-data-window", [](const fs::path& p) {
    write_sh(p, 4, 4, 0.5f);
    B b = slurp(p);
    const size_t at = exr_attribute(b, "dataWindow");
    wr32(b, at + 0, 10);  // xmin > xmax
    spit(p, b);
  }, ""));
  c.push_back(sh_exr_case("exr-8-bit-channels (PNG given as SH)", [](const fs::path& p) {
    const fs::path png = p.parent_path() / "in.png";
    ImageF img(4, 4, 3);
    write_image(png.string(), img);
    fs::rename(png, p);
  }, ""));
  c.push_back(sh_exr_case("exr-missing-sh-channels", [](const fs::path& p) {
    ImageF img(4, 4, 3);
    write_image(p.string(), img);
  }, ""));
  c.push_back(sh_exr_case("exr-nan-flood", [](const fs::path& p) { write_sh(p, 8, 8, std::numeric_limits<float>::quiet_NaN()); },
                          "no finite texel"));
  c.push_back(sh_exr_case("exr-inf-flood", [](const fs::path& p) { write_sh(p, 8, 8, std::numeric_limits<float>::infinity()); },
                          "no finite texel"));
  c.push_back(sh_exr_case("exr-is-a-folder", [](const fs::path& p) { fs::create_directories(p); }, ""));
  c.push_back(sh_exr_case("exr-empty-file", [](const fs::path& p) { spit(p, B{}); }, ""));
  // --- intermediate, layouts, meshes ---
  c.push_back({"intermediate-is-a-plain-exr", [](const fs::path& d) {
                 const fs::path p = d / "x.ahd.exr";
                 write_sh(p, 4, 4, 1.0f);
                 return std::pair{std::function<void()>([p] { read_intermediate(p.string(), nullptr); }), p.string()};
               },
               "not an ahdpack intermediate"});
  c.push_back({"layout-json-truncated", [](const fs::path& d) {
                 const fs::path p = d / "layout.json";
                 spit(p, std::string("{\"name\": \"x\", \"images\": ["));
                 return std::pair{std::function<void()>([p] { load_layout(p.string()); }), p.string()};
               },
               ""});
  c.push_back({"layout-json-wrong-types", [](const fs::path& d) {
                 const fs::path p = d / "layout.json";
                 spit(p, std::string("{\"name\": 5, \"images\": 7, \"coefficients\": \"x\"}"));
                 return std::pair{std::function<void()>([p] { load_layout(p.string()); }), p.string()};
               },
               ""});
  c.push_back({"mesh-truncated-glb", [](const fs::path& d) {
                 const fs::path p = d / "m.glb";
                 spit(p, std::string("glTF\x02\0\0\0", 8));
                 return std::pair{std::function<void()>([p] { read_mesh_lightmap(p.string(), -1); }), p.string()};
               },
               ""});
  c.push_back({"mesh-obj-bad-indices", [](const fs::path& d) {
                 const fs::path p = d / "m.obj";
                 spit(p, std::string("v 0 0 0\nv 1 0 0\nvt 0 0\nf 1/1 2/1 99/1\n"));
                 return std::pair{std::function<void()>([p] { read_mesh_lightmap(p.string(), -1); }), p.string()};
               },
               ""});
  c.push_back({"mesh-without-uvs", [](const fs::path& d) {
                 const fs::path p = d / "m.obj";
                 spit(p, std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
                 return std::pair{std::function<void()>([p] { read_mesh_lightmap(p.string(), -1); }), p.string()};
               },
               ""});
  // --- outputs ---
  c.push_back({"output-manifest-path-is-a-folder", [](const fs::path& d) {
                 fs::create_directories(d / "prev2.json");
                 const std::string p = (d / "prev2.json").string();
                 return std::pair{std::function<void()>([d, p] {
                                    publish_output_set({{(d / "prev2.iz.ktx2").string(), {1, 2, 3}}, {p, {4}}});
                                  }),
                                  p};
               },
               "is a folder"});
  c.push_back({"output-folder-is-a-file", [](const fs::path& d) {
                 spit(d / "notafolder", std::string("x"));
                 const std::string p = (d / "notafolder" / "out.json").string();
                 return std::pair{std::function<void()>([p] { publish_output_set({{p, {1}}}); }), p};
               },
               "cannot create folder"});
  for (const char* fault : {"ENOSPC", "EROFS", "EACCES"}) {
    c.push_back({std::string("output-") + fault + "-on-second-plane (simulated)", [fault](const fs::path& d) {
                   // Overwrites the previous set's own names: the failure must leave it intact.
                   const Manifest m = read_manifest_file((d / "prev.json").string());
                   std::vector<FileToPublish> files;
                   for (const auto& p : m.planes) files.push_back({(d / (p.file + ".new")).string(), std::vector<uint8_t>(100, 7)});
                   files.push_back({(d / "prev.json").string(), {'{', '}'}});
                   const std::string named = files[1].path;
                   return std::pair{std::function<void()>([files, fault] {
                                      ::setenv("AHDPACK_TEST_WRITE_FAULT", (std::string("1:") + fault).c_str(), 1);
                                      try {
                                        publish_output_set(files);
                                      } catch (...) {
                                        ::unsetenv("AHDPACK_TEST_WRITE_FAULT");
                                        throw;
                                      }
                                      ::unsetenv("AHDPACK_TEST_WRITE_FAULT");
                                    }),
                                    named};
                 },
                 fault == std::string("ENOSPC") ? "No space left" : fault == std::string("EROFS") ? "Read-only" : "Permission denied"});
  }
  return c;
}

}  // namespace

// Issue 15, case 1: a manifest naming a one-channel plane for iz (or dir) used to be decoded past
// the end of the plane. decode_planes now refuses it before decoding, whoever calls it.
TEST(BadInput, DecodePlanesRefusesPlanesThatDoNotFitTheirRole) {
  auto planes = [](PixelFormat iz, PixelFormat dir, PixelFormat ratio) {
    return std::vector<Plane>{{"iz", plain_texture(iz, 8, 8)}, {"dir", plain_texture(dir, 8, 8)},
                              {"ratio", plain_texture(ratio, 8, 8)}};
  };
  using P = PixelFormat;
  EXPECT_NO_THROW(decode_planes(planes(P::RGBA16_SFLOAT, P::RG8_UNORM, P::R8_UNORM), false));
  EXPECT_THROW(decode_planes(planes(P::R8_UNORM, P::RG8_UNORM, P::R8_UNORM), false), Error);
  EXPECT_THROW(decode_planes(planes(P::RGBA16_SFLOAT, P::R8_UNORM, P::R8_UNORM), false), Error);
  EXPECT_THROW(decode_planes(planes(P::RGBA16_SFLOAT, P::BC4_UNORM, P::R8_UNORM), false), Error);
  EXPECT_THROW(decode_planes(planes(P::RGBA16_SFLOAT, P::RG8_UNORM, P::R8_UNORM), true), Error);  // RGB ratio in R8
  auto mixed = planes(P::RGBA16_SFLOAT, P::RG8_UNORM, P::R8_UNORM);
  mixed[1].texture = plain_texture(P::RG8_UNORM, 4, 4);
  EXPECT_THROW(decode_planes(mixed, false), Error);
  auto levels = planes(P::RGBA16_SFLOAT, P::RG8_UNORM, P::R8_UNORM);
  levels[2].texture = plain_texture(P::R8_UNORM, 8, 8, 2);
  EXPECT_THROW(decode_planes(levels, false), Error);
  // A level whose bytes do not match its size is refused (not read past its end).
  auto shortlv = planes(P::RGBA16_SFLOAT, P::RG8_UNORM, P::R8_UNORM);
  shortlv[0].texture.levels[0].data.resize(10);
  EXPECT_THROW(decode_planes(shortlv, false), Error);
}

// Issue 15, case 2: the zstd allocation bomb. Fails on what the frame holds, without allocating the
// claimed 2 GiB (checked through the CLI under a 1 GiB address-space limit where no sanitizer
// reserves shadow memory).
TEST(BadInput, ZstdBombIsRefusedWithoutAllocatingTheClaim) {
  const fs::path d = ahd_test::temp_dir("zstd_bomb");
  spit(d / "bomb.ktx2", zstd_bomb_ktx2(16384, 16384));
  spit(d / "bomb32k.ktx2", zstd_bomb_ktx2(32768, 32768));
  EXPECT_THROW(read_container_file((d / "bomb.ktx2").string()), Error);
  const bool limit_memory = !ahd_test::kSanitized;
  for (const char* f : {"bomb.ktx2", "bomb32k.ktx2"}) {
    const std::string cmd = std::string(limit_memory ? "ulimit -v 1048576; " : "") + "'" AHD_CLI_PATH "' inspect '" +
                            (d / f).string() + "' 2>&1";
    FILE* p = popen(cmd.c_str(), "r");
    ASSERT_NE(p, nullptr);
    std::string out;
    char buf[512];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
    const int st = pclose(p);
    EXPECT_EQ(WEXITSTATUS(st), 1) << out;
    EXPECT_EQ(out.rfind("ahdpack: error: " + (d / f).string() + ": ", 0), 0u) << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  }
  fs::remove_all(d);
}

// The limit is documented and overridable; an image over it is refused when read.
TEST(BadInput, SizeLimitIsOverridable) {
  EXPECT_EQ(max_image_size(), kDefaultMaxImageSize);
  const fs::path d = ahd_test::temp_dir("size_limit");
  write_sh(d / "a.exr", 40, 2, 0.25f);
  set_max_image_size(32);
  try {
    read_canonical_sh((d / "a.exr").string());
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("40x2 is over the size limit of 32x32"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_container_file((d / "x").string()), Error);
  set_max_image_size(64);
  EXPECT_NO_THROW(read_canonical_sh((d / "a.exr").string()));
  set_max_image_size(0);
  fs::remove_all(d);
}

// SHA-256 against the FIPS 180-4 examples.
TEST(BadInput, Sha256MatchesTheStandardsExamples) {
  auto h = [](const std::string& s) { return sha256_hex(reinterpret_cast<const uint8_t*>(s.data()), s.size()); };
  EXPECT_EQ(h("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(h(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(h("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(h(std::string(1000000, 'a')), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

// Found by fuzz_manifest under UBSan: a number such as 1.9e113 where a whole number belongs was
// converted with undefined behaviour. Every whole-number field now takes integer tokens in range.
TEST(BadInput, ManifestNumbersMustBeWholeAndInRange) {
  std::ifstream f(std::string(AHD_SOURCE_DIR) + "/golden/expected/scene16_uncompressed_ktx2.json");
  ASSERT_TRUE(f);
  const nlohmann::json good = nlohmann::json::parse(f);
  EXPECT_NO_THROW(manifest_from_json(good.dump(), "m.json"));
  const std::vector<std::pair<std::string, nlohmann::json>> bad = {
      {"/planes/0/bytes", 1.94856e+113}, {"/width", -3}, {"/levels", 2.5}, {"/version", 1e30}, {"/planes/0/height", "16"}};
  for (const auto& [pointer, value] : bad) {
    nlohmann::json m = good;
    m[nlohmann::json::json_pointer(pointer)] = value;
    try {
      manifest_from_json(m.dump(), "m.json");
      ADD_FAILURE() << pointer << " = " << value.dump() << " was accepted";
    } catch (const ahd::Error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("m.json: ", 0), 0u) << e.what();
    }
  }
}
