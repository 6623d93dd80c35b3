#include "cli/conversion_view.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/parallel.h"
#include "io/manifest_file.h"
#include "io/sh_exr.h"

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
  for (uint32_t l = 0; l < m.levels; ++l) v.levels.push_back(decode_planes(planes, m.ratio_form == RatioForm::Rgb, int(l)));
  return v;
}

ShImage read_source_for(const std::string& source, const ConversionView& v) {
  ShImage sh = read_canonical_sh(source);
  if (v.manifest.layers != 1)
    throw file_error(source, "the conversion has " + std::to_string(v.manifest.layers) +
                                 " atlas pages; checking against a source handles single-page conversions only");
  if (uint32_t(sh.width) != v.manifest.width || uint32_t(sh.height) != v.manifest.height)
    throw file_error(source, "is " + std::to_string(sh.width) + "x" + std::to_string(sh.height) + ", the conversion is " +
                                 std::to_string(v.manifest.width) + "x" + std::to_string(v.manifest.height));
  return sh;
}

TexelErrorMaps texel_error_maps(const ShImage& sh, const DecodedPlanes& p, double dz_min) {
  const double luma[3] = {0.2126, 0.7152, 0.0722};  // as fit/hemisphere_error.cpp
  const int nd = 64;
  const std::vector<double> dirs = hemisphere_directions(nd);
  const std::vector<AhdLobe> lobes = lobes_from_planes(p, dz_min);
  TexelErrorMaps out;
  const size_t n = sh.texels();
  out.hemisphere.assign(n, std::numeric_limits<float>::quiet_NaN());
  out.normal = out.hemisphere;
  parallel_for(size_t(sh.height), 0, 1, [&](size_t y) {
    for (size_t i = size_t(y) * sh.width; i < size_t(y + 1) * sh.width; ++i) {
      if (!sh.coverage[i]) continue;
      IrradiancePoly poly[3];
      local_polys(sh, i, poly);
      const AhdLobe& l = lobes[i];
      double se = 0, lum = 0;
      for (int k = 0; k < nd; ++k) {
        const double* w = &dirs[size_t(k) * 3];
        const double cosine = std::max(0.0, w[0] * l.d[0] + w[1] * l.d[1] + w[2] * l.d[2]);
        for (int c = 0; c < 3; ++c) {
          const double ref = eval_irradiance(poly[c], w), got = l.ca[c] + cosine * l.cd[c];
          se += (got - ref) * (got - ref);
          lum += luma[c] * ref;
        }
      }
      lum /= nd;
      out.hemisphere[i] = lum > 0 ? float(std::sqrt(se / (3.0 * nd)) / lum) : 0.0f;
      const double z[3] = {0, 0, 1};
      double zl = 0, ze = 0;
      for (int c = 0; c < 3; ++c) {
        const double ref = std::max(0.0, eval_irradiance(poly[c], z));
        const double got = l.ca[c] + std::max(0.0, l.d[2]) * l.cd[c];
        zl += luma[c] * ref;
        ze = std::max(ze, std::fabs(got - ref));
      }
      out.normal[i] = zl > 0 ? float(ze / zl) : 0.0f;
    }
  });
  return out;
}

ErrorReport measure_conversion(const ShImage& sh, const DecodedPlanes& level0, double dz_min) {
  return measure_error(sh, lobes_from_planes(level0, dz_min), 0);
}

}  // namespace ahd::cli
