// ahd::convert (<ahd/convert.h>): the public entry point over the pipeline stages.
#include <ahd/convert.h>

#include "api/options.h"
#include "core/error.h"
#include "pipeline/manifest.h"
#include "pipeline/run.h"

namespace ahd {

Conversion convert(const ShImage& sh, const std::string& name, const ConversionOptions& options) {
  check_sh_image(sh);
  return convert(ShImage(sh), name, options);
}

namespace {

Conversion convert_with(ShImage&& sh, const std::string& name, const ConversionOptions& options,
                        const std::vector<LightmapInstance>& instances) {
  check_sh_image(sh);
  ResolvedOptions o = resolve_options(options, name);
  o.package.world_frame = !sh.normals.empty();
  for (const LightmapInstance& i : instances) {
    if (i.page != 0) throw Error("instance " + i.node + ": page " + std::to_string(i.page) + " of a one-page conversion");
    ManifestInstance m;
    m.node = i.node;
    m.page = i.page;
    for (int k = 0; k < 2; ++k) m.scale[k] = i.uv_scale[k], m.offset[k] = i.uv_offset[k];
    o.package.instances.push_back(std::move(m));
  }
  ConversionRun run = run_conversion(std::move(sh), o.profile, o.convert, o.package);
  Conversion c;
  c.files = std::move(run.output.files);
  c.directional = run.result.directional;
  return c;
}

}  // namespace

Conversion convert(ShImage&& sh, const std::string& name, const ConversionOptions& options) {
  return convert_with(std::move(sh), name, options, {});
}

Conversion convert(const ShImage& sh, const std::string& name, const ConversionOptions& options,
                   const std::vector<LightmapInstance>& instances) {
  check_sh_image(sh);
  return convert_with(ShImage(sh), name, options, instances);
}

}  // namespace ahd
