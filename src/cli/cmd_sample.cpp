// ahdpack sample -o OUT.exr: writes the built-in analytic scene as a canonical SH EXR.
#include <cstdio>

#include "cli/commands.h"
#include "image/sh_exr.h"
#include "sample/analytic_baker.h"

namespace ahd::cli {

void add_sample_command(CLI::App& app) {
  auto bo = std::make_shared<BakerOptions>();
  auto out = std::make_shared<std::string>();
  auto order = std::make_shared<int>(2);
  CLI::App* c = app.add_subcommand("sample", "Write the built-in analytic scene as a canonical SH EXR");
  c->add_option("-o,--output", *out, "Output EXR")->required();
  c->add_option("--size", bo->width, "Width and height")->check(CLI::Range(1, 16384));
  c->add_option("--order", *order, "SH order: 1 (L1) or 2 (L2)")->check(CLI::IsMember({1, 2}));
  c->add_option("--seed", bo->seed, "Scene seed (0 = canonical)");
  c->callback([bo, out, order]() {
    BakerOptions o = *bo;
    o.height = o.width;
    o.coeffs = *order == 1 ? 4 : 9;
    write_canonical_sh(*out, bake_analytic_scene(o));
    std::printf("ahdpack sample: %dx%d %s -> %s\n", o.width, o.height, o.coeffs == 9 ? "L2" : "L1", out->c_str());
  });

}

}  // namespace ahd::cli
