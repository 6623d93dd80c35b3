// ahdpack decode NAME.json -o OUT.exr [--level L] [--layer P] [--normals N.exr]: irradiance from the planes.
#include <cmath>
#include <filesystem>
#include <string>

#include "files/manifest_file.h"
#include "cli/commands.h"
#include "files/container_file.h"
#include "core/error.h"
#include "fit/ahd_decode.h"
#include "image/image_io.h"
#include "pipeline/convert.h"
#include "pipeline/manifest.h"
#include "files/utf8_path.h"

namespace ahd::cli {
namespace fs = std::filesystem;

namespace {

struct DecodeArgs {
  std::string manifest;
  std::string output;
  std::string normals;
  int level = 0;
  int layer = 0;
};

void run_decode(const DecodeArgs& a) {
  const Manifest m = read_manifest_file(a.manifest);
  std::vector<Plane> planes;
  // Each plane's size and SHA-256 are checked against the manifest before it is decoded.
  for (const auto& mp : m.planes) {
    Texture t = read_manifest_plane(a.manifest, mp);
    if (t.layers != mp.layers)
      throw file_error(utf8_string(fs_path(a.manifest).parent_path() / fs_path(mp.file)),
                       "holds " + std::to_string(t.layers) + " layer(s), the manifest says " + std::to_string(mp.layers));
    planes.push_back({mp.name, std::move(t)});
  }
  if (a.layer < 0 || uint32_t(a.layer) >= m.layers)
    throw file_error(a.manifest, "has " + std::to_string(m.layers) + " layer(s) (atlas pages); --layer " +
                                     std::to_string(a.layer) + " does not exist");
  for (Plane& pl : planes) pl.texture = texture_layer(pl.texture, uint32_t(a.layer));
  if (a.level < 0 || uint32_t(a.level) >= m.levels)
    throw file_error(a.manifest, "has " + std::to_string(m.levels) + " mip level(s); --level " + std::to_string(a.level) +
                                     " does not exist");
  const DecodedPlanes p = decode_planes(planes, m.ratio_form == RatioForm::Rgb, a.level);

  ImageF normals;
  if (!a.normals.empty()) {
    normals = read_image(a.normals);
    if (normals.width != p.width || normals.height != p.height)
      throw file_error(a.normals, "normal map is " + std::to_string(normals.width) + "x" + std::to_string(normals.height) +
                                      ", level " + std::to_string(a.level) + " is " + std::to_string(p.width) + "x" +
                                      std::to_string(p.height));
    if (normals.channels < 3) throw file_error(a.normals, "normal map needs 3 channels (tangent-space X Y Z)");
  }
  ImageF out(p.width, p.height, 3);
  for (size_t i = 0; i < out.texels(); ++i) {
    double n[3] = {0, 0, 1};
    if (normals.channels) {
      for (int c = 0; c < 3; ++c) n[c] = normals.data[i * normals.channels + c];
      const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (!(len > 0)) throw file_error(a.normals, "zero-length normal at texel " + std::to_string(i));
      for (double& v : n) v /= len;
    }
    double e[3];
    decode_irradiance(&p.iz[i * 3], &p.d[i * 3], &p.ratio[i * 3], n, m.dz_min, e);
    for (int c = 0; c < 3; ++c) out.data[i * 3 + c] = float(e[c]);
  }
  write_image(a.output, out, false, {"R", "G", "B"});
  std::printf("ahdpack decode: level %d%s (%dx%d) -> %s\n", a.level,
              m.layers > 1 ? (", layer " + std::to_string(a.layer)).c_str() : "", p.width, p.height, a.output.c_str());
}

}  // namespace

void add_decode_command(CLI::App& app) {
  auto a = std::make_shared<DecodeArgs>();
  CLI::App* c = app.add_subcommand("decode", "Reconstruct irradiance (RGB float EXR) from a conversion's manifest");
  c->add_option("manifest", a->manifest, "NAME.json written by convert")->required();
  c->add_option("-o,--output", a->output, "Output EXR")->required();
  c->add_option("--level", a->level, "Mip level");
  c->add_option("--layer", a->layer, "Array layer (atlas page) of a multi-page conversion");
  c->add_option("--normals", a->normals, "Tangent-space normal map (EXR, XYZ in [-1,1]); default: the surface normal");
  c->callback([a]() { run_decode(*a); });
}

}  // namespace ahd::cli
