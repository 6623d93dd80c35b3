// ahdpack scene IN [input options] -o OUT.glb: the placed scene of a conversion's input as glTF
// (bakers/scene_export.h) — what three.js, the preview and engine tests load beside the planes.
#include <cstdio>

#include "bakers/scene_export.h"
#include "cli/commands.h"
#include "cli/conversion_args.h"
#include "core/error.h"
#include "files/output_set.h"

namespace ahd::cli {

void add_scene_command(CLI::App& app) {
  auto in = std::make_shared<BakeInput>();
  auto out = std::make_shared<std::string>();
  CLI::App* c = app.add_subcommand(
      "scene", "Write the placed scene of a lightmap's input (a project whose scene places it, or --mesh with --placement) as glTF: "
               "world-space meshes, lightmap UVs in atlas space (TEXCOORD_1), each instance's page");
  c->add_option("input", in->input, "The lightmap as convert reads it (any file of a baker's set)")->required();
  add_input_options(c, in.get());
  c->add_option("-o,--output", *out, "Output .glb")->required();
  c->callback([in, out]() {
    ReadStats rs;
    std::string source;
    read_bake_input(in.get(), 0, &rs, &source);  // as convert reads it: same scene, same checks
    const SceneGltf g = bake_scene_gltf(*in);
    write_file_atomic(*out, g.glb);
    std::printf("ahdpack scene: %zu instance(s), %zu triangles, %d page(s) -> %s\n", g.instances, g.triangles, g.pages,
                out->c_str());
  });
}

}  // namespace ahd::cli
