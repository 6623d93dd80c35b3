#include "api/options.h"

#include <cmath>

#include "core/error.h"
#include "pipeline/set_name.h"
#include "sh/sh.h"

namespace ahd {

ResolvedOptions resolve_options(const ConversionOptions& o, const std::string& name) {
  return resolve_options(o, name,
                         o.profile_json.empty() ? builtin_profile(o.profile) : profile_from_json(o.profile_json, "profile_json"));
}

ResolvedOptions resolve_options(const ConversionOptions& o, const std::string& name, const Profile& profile) {
  if (!(o.eps > 0 && o.eps < 1)) throw Error("eps (--eps) must be in (0, 1)");
  if (o.levels < 0) throw Error("levels must be ≥ 0");
  if (!(o.ambient_threshold >= 0)) throw Error("the ambient threshold must be ≥ 0");
  if (!(o.iz_scale > 0) || !std::isfinite(o.iz_scale))
    throw Error("iz_scale must be a finite positive factor (stored I_z = iz_scale × E), not " + std::to_string(o.iz_scale));
  if (name.empty() || name.find_first_of("/\\") != std::string::npos)
    throw Error("the output name must be a file stem without folders (got '" + name + "')");
  const std::string problem = set_name_problem(name);  // the CLI's rule (cook/publish.h output_paths)
  if (!problem.empty()) throw Error("the output name '" + name + "' " + problem);
  ResolvedOptions r;
  r.profile = profile;
  PipelineOptions& c = r.convert;
  c.fit.dz_min = o.eps;
  c.fit.ratio_form = o.ratio ? *o.ratio : profile.ratio_rgb ? RatioForm::Rgb : RatioForm::Luminance;
  c.fit.direction_fit = o.direction_fit;
  c.closed_loop = o.closed_loop;
  c.measure = o.measure;
  c.codec.bc6h_quality = o.bc6h_quality;
  c.threads = o.threads;
  c.max_levels = o.levels;
  c.coverage_plane = o.coverage_plane;
  c.direction = o.direction;
  c.ambient_threshold = o.ambient_threshold;
  c.progress = o.progress;
  c.cancel = o.cancel;
  check_profile(r.profile, c);
  PackageOptions& p = r.package;
  p.name = name;
  p.container = o.container;
  p.zstd = o.zstd;
  p.plane_metadata = o.plane_metadata;
  p.iz_scale = o.iz_scale;
  p.stable_names = o.stable_names;
  return r;
}

void check_sh_image(const ShImage& sh) {
  if (sh.width <= 0 || sh.height <= 0) throw Error("the SH image has no texels");
  if (!valid_sh_coeffs(sh.coeffs)) throw Error("the SH image must hold 1 (L0), 4 (L1) or 9 (L2) coefficients");
  const size_t n = sh.texels();
  if (sh.data.size() != n * size_t(sh.coeffs) * 3)
    throw Error("the SH data holds " + std::to_string(sh.data.size()) + " floats, not width*height*coeffs*3 = " +
                std::to_string(n * size_t(sh.coeffs) * 3));
  if (sh.coverage.size() != n) throw Error("the coverage must hold width*height entries");
  if (!sh.normals.empty() && sh.normals.size() != n * 3) throw Error("the normals must be empty or width*height*3 floats");
  // A NaN or infinite normal made an all-black map without a word (issue 44): refused as the CLI's
  // readers refuse it (bakers/baker_layout.cpp check_normals).
  for (size_t i = 0; i < sh.normals.size(); ++i)
    if (!std::isfinite(sh.normals[i]))
      throw Error("non-finite normal at texel (" + std::to_string(i / 3 % size_t(sh.width)) + ", " +
                  std::to_string(i / 3 / size_t(sh.width)) + ")");
}

}  // namespace ahd
