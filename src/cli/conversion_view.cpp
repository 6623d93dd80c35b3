#include "cli/conversion_view.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "core/error.h"
#include "core/parallel.h"
#include "files/manifest_file.h"
#include "image/sh_exr.h"

namespace ahd::cli {

ConversionView read_conversion(const std::string& manifest_path, int layer) {
  ConversionView v;
  v.manifest = read_manifest_file(manifest_path);
  const Manifest& m = v.manifest;
  if (layer < 0 || uint32_t(layer) >= m.layers)
    throw file_error(manifest_path, "has " + std::to_string(m.layers) + " layer(s); layer " + std::to_string(layer) +
                                        " does not exist");
  std::vector<Plane> planes;
  for (const ManifestPlane& mp : m.planes) {
    Texture t = read_manifest_plane(manifest_path, mp);
    if (t.layers != mp.layers)
      throw file_error(manifest_path, "plane " + mp.name + " holds " + std::to_string(t.layers) + " layer(s), the manifest says " +
                                          std::to_string(mp.layers));
    planes.push_back({mp.name, texture_layer(t, uint32_t(layer))});
  }
  for (uint32_t l = 0; l < m.levels; ++l) {
    v.levels.push_back(decode_planes(planes, m.ratio_form == RatioForm::Rgb, int(l)));
    // The SH was scaled by iz_scale before the fit, so I_z and both colours of the lobe are
    // iz_scale × E; d and the ratio are unchanged. Back to E, what the source SH gives.
    if (m.iz_scale != 1.0)
      for (float& x : v.levels.back().iz) x = float(double(x) / m.iz_scale);
  }
  return v;
}

std::vector<ShImage> read_source_for(BakeInput source, const Manifest& m, std::string* described, BakeInput* read_as) {
  const std::string given = source.input;
  ReadStats rs;
  std::vector<ShImage> pages = read_bake_input(&source, 0, &rs, described);
  if (pages.size() != m.layers)
    throw file_error(
        given, "holds " + std::to_string(pages.size()) + " atlas page(s), the conversion " + std::to_string(m.layers));
  for (const ShImage& sh : pages)
    if (uint32_t(sh.width) != m.width || uint32_t(sh.height) != m.height)
      throw file_error(given, "is " + std::to_string(sh.width) + "x" + std::to_string(sh.height) +
                                  ", the conversion is " + std::to_string(m.width) + "x" + std::to_string(m.height));
  if (read_as) *read_as = std::move(source);
  return pages;
}

TexelErrorMaps texel_error_maps(const ShImage& sh, const DecodedPlanes& p, double dz_min) {
  const int nd = 64;
  const std::vector<double> dirs = hemisphere_directions(nd);
  const std::vector<AhdLobe> lobes = lobes_from_planes(p, dz_min);
  TexelErrorMaps out;
  const size_t n = sh.texels();
  out.hemisphere.assign(n, std::numeric_limits<float>::quiet_NaN());
  out.normal = out.hemisphere;
  parallel_for(n, 0, 1024, [&](size_t i) {
    if (!sh.coverage[i]) return;
    const TexelError e = texel_error(sh, i, lobes[i], dirs.data(), nd);  // the reports' own figures
    out.hemisphere[i] = float(e.rel);
    out.normal[i] = float(e.nrel);
  });
  return out;
}

ErrorReport measure_conversion(const ShImage& sh, const DecodedPlanes& level0, double dz_min) {
  return measure_error(sh, lobes_from_planes(level0, dz_min), 0);
}

}  // namespace ahd::cli
