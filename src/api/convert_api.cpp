// ahd::convert (<ahd/convert.h>): the public entry point over the pipeline stages.
#include <ahd/convert.h>

#include "api/options.h"
#include "pipeline/run.h"

namespace ahd {

Conversion convert(const ShImage& sh, const std::string& name, const ConversionOptions& options) {
  check_sh_image(sh);
  return convert(ShImage(sh), name, options);
}

Conversion convert(ShImage&& sh, const std::string& name, const ConversionOptions& options) {
  check_sh_image(sh);
  ResolvedOptions o = resolve_options(options, name);
  o.package.world_frame = !sh.normals.empty();
  ConversionRun run = run_conversion(std::move(sh), o.profile, o.convert, o.package);
  Conversion c;
  c.files = std::move(run.output.files);
  c.directional = run.result.directional;
  return c;
}

}  // namespace ahd
