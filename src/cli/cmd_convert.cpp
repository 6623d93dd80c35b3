// ahdpack convert [IN.exr] [-o OUT.ktx2|OUT.dds]: SH lightmap → AHD planes + manifest + report.
#include <ahd/sample.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "api/options.h"
#include "cli/commands.h"
#include "cli/conversion_args.h"
#include "cli/output.h"
#include "cli/progress.h"
#include "core/error.h"
#include "io/ahd_intermediate.h"
#include "io/baker_layout.h"
#include "io/image_io.h"
#include "io/mesh_io.h"
#include "io/profile_file.h"
#include "io/sh_exr.h"
#include "pipeline/run.h"

namespace ahd::cli {
namespace fs = std::filesystem;

namespace {

struct ConvertArgs {
  std::string input;
  std::string output;
  std::string layout;   // baker layout preset (name or .json); input is then the base path
  std::string normals;  // lightmap-space normals for world-space layouts
  std::string mesh;     // or: the mesh, rasterised in its lightmap UVs (normals and coverage)
  int uv_set = -1;      // the mesh's lightmap UV set (−1 = the default rule of io/mesh_io.h)
  int sample_size = 256;
  int sample_order = 2;
  unsigned seed = 0;
  bool keep_intermediate = false;
  ConversionArgs conv;
};

// The baker's files through a layout preset, with normals/coverage from --normals or --mesh.
ShImage read_layout_input(const ConvertArgs& a, ReadStats* rs, std::string* source) {
  const LayoutPreset layout = load_layout(a.layout);
  std::string from_mesh;
  ShImage sh;
  if (!a.mesh.empty()) {
    if (layout.canonical)
      throw Error("layout " + layout.name + " is the tool's own EXR (coverage and normals inside): --mesh does not apply");
    // The mesh is rasterised at the lightmap's size, known from the first file's header.
    int w = 0, h = 0;
    layout_size(layout, a.input, &w, &h);
    MeshReadInfo mi;
    const MeshTriangles mesh = read_mesh_lightmap(a.mesh, a.uv_set, &mi);
    RasterisedNormals rn = rasterise_lightmap_normals(mesh, w, h);
    mesh_normals_to_layout_axes(layout, &rn.normals);  // glTF's axes → the baker's world
    size_t covered = 0;
    for (uint8_t c : rn.coverage) covered += c;
    if (covered == 0)
      throw file_error(a.mesh, "no triangle covers any texel of the " + std::to_string(w) + "x" + std::to_string(h) +
                                   " lightmap in UV set " + std::to_string(mi.uv_set) + " (wrong --uv-set?)");
    // Tangent-space layouts take the coverage only (read_layout uses normals for world space).
    const LayoutNormals ln{a.mesh, w, h, std::move(rn.normals), std::move(rn.coverage)};
    sh = read_layout(layout, a.input, &ln, rs);
    from_mesh = ", " + std::string(layout.world_space ? "normals and coverage" : "coverage") + " from " + a.mesh + " (" +
                std::to_string(mi.triangles) + " triangles, UV set " + std::to_string(mi.uv_set) + ", " +
                std::to_string(covered) + " texels covered)";
  } else {
    sh = read_layout(layout, a.input, a.normals, rs);
  }
  *source = a.input + " (layout " + layout.name + ", " + std::to_string(sh.width) + "x" + std::to_string(sh.height) +
            (sh.coeffs == 9 ? " L2" : " L1") + (sh.normals.empty() ? ", tangent space" : ", world space + normals") +
            from_mesh + ")";
  return sh;
}

// The SH to convert: the built-in sample, a baker's files (--layout) or the canonical EXR.
ShImage read_input(const ConvertArgs& a, ReadStats* rs, std::string* source) {
  if (a.input.empty()) {
    *source = "built-in sample (analytic scene, " + std::to_string(a.sample_size) + "x" + std::to_string(a.sample_size) +
              (a.sample_order == 2 ? " L2" : " L1") + ", seed " + std::to_string(a.seed) + ")";
    return bake_sample(a.sample_size, a.sample_order, a.seed, a.conv.options.threads);
  }
  if (!a.layout.empty()) return read_layout_input(a, rs, source);
  ShImage sh = read_canonical_sh(a.input, rs);
  *source = a.input + " (" + std::to_string(sh.width) + "x" + std::to_string(sh.height) + (sh.coeffs == 9 ? " L2" : " L1") +
            (sh.normals.empty() ? ", tangent space)" : ", world space + normals)");
  return sh;
}

void run_convert(const ConvertArgs& a) {
  std::string out_path = a.output;
  if (out_path.empty())
    out_path = "ahdpack-out/" + (a.input.empty() ? std::string("sample") : fs::path(a.input).stem().string()) + ".ktx2";
  const OutputPaths out = output_paths(out_path);
  ConversionOptions co = conversion_options(a.conv);
  co.container = out.kind;
  attach_terminal_progress(&co, a.conv.quiet);

  // Checked before anything is read or written: one clear line, no output.
  const ResolvedOptions ro = resolve_options(co, out.name, load_profile(a.conv.profile));
  if (!a.mesh.empty() && !a.normals.empty()) throw Error("--mesh and --normals both give the normals: use one");
  if (!a.mesh.empty() && a.layout.empty()) throw Error("--mesh needs --layout (a baker's files to pair it with)");
  if (a.uv_set >= 0 && a.mesh.empty()) throw Error("--uv-set needs --mesh");

  const auto t0 = std::chrono::steady_clock::now();
  ReadStats rs;
  std::string source;
  ShImage sh = read_input(a, &rs, &source);
  const double read_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  PackageOptions pkg = ro.package;
  pkg.world_frame = !sh.normals.empty();
  pkg.report_extra = {{"source", source},
                      {"read", {{"non_finite_texels", rs.non_finite_texels}, {"coverage_derived", rs.coverage_derived}}}};
  std::function<void(const std::vector<FittedLevel>&)> on_fitted;
  if (a.keep_intermediate)
    on_fitted = [&](const std::vector<FittedLevel>& levels) { write_intermediate(out.sibling(".ahd.exr"), levels, ro.convert.fit); };
  const ConversionRun run = run_conversion(std::move(sh), ro.profile, ro.convert, pkg,
                                           {{a.input.empty() ? "bake sample" : "read", read_seconds}}, on_fitted);
  publish_conversion(out, run.output.files);
  if (!a.conv.quiet) print_conversion(source, out, run, ro.convert.closed_loop, rs.non_finite_texels);
}

}  // namespace

void add_layouts_command(CLI::App& app) {
  CLI::App* c = app.add_subcommand("layouts", "List the baker layout presets (formats/bakers)");
  c->callback([]() {
    for (const std::string& n : list_layouts()) {
      const LayoutPreset p = load_layout(n);
      std::printf("%-18s %s\n", n.c_str(), p.description.c_str());
    }
  });
}

void add_convert_command(CLI::App& app) {
  auto a = std::make_shared<ConvertArgs>();
  CLI::App* c = app.add_subcommand("convert", "Convert an SH lightmap (or, with no input, the built-in sample) to AHD planes");
  c->add_option("input", a->input, "Canonical SH EXR (sh0.R … sh8.B); omit for the built-in sample");
  c->add_option("-o,--output", a->output, "OUT.ktx2 or OUT.dds: writes OUT.<plane>.<ext>, OUT.json, OUT.report.json");
  c->add_option("--layout", a->layout, "Baker layout preset (ahdpack layouts) or FILE.json; the input is then the base path");
  c->add_option("--normals", a->normals, "Lightmap-space normal EXR, for world-space layouts");
  c->add_option("--mesh", a->mesh,
                "Mesh (.gltf, .glb, .obj) rasterised in its lightmap UVs: the normals (world-space layouts) and the "
                "coverage (any layout); instead of --normals. Lightmap row 0 = glTF v=0 = OBJ v=1");
  c->add_option("--uv-set", a->uv_set,
                "The mesh's lightmap UV set (glTF TEXCOORD_n); default: the second set when the meshes have 2 or "
                "more, else the first")
      ->check(CLI::NonNegativeNumber);
  add_conversion_options(c, &a->conv, true);
  c->add_flag("--keep-intermediate", a->keep_intermediate, "Also write OUT.ahd.exr, the lossless fitted planes for transcode");
  c->add_option("--sample-size", a->sample_size, "Built-in sample: width and height")->check(CLI::Range(1, 8192));
  c->add_option("--sample-order", a->sample_order, "Built-in sample: SH order 1 (L1) or 2 (L2)")->check(CLI::IsMember({1, 2}));
  c->add_option("--seed", a->seed, "Built-in sample: scene seed (0 = canonical)");
  c->callback([a]() { run_convert(*a); });
}

}  // namespace ahd::cli
