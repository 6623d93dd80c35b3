#include "cli/conversion_input.h"

#include <ahd/sample.h>

#include "core/error.h"
#include "io/baker_layout.h"
#include "io/layout_detect.h"
#include "io/layout_pages.h"
#include "io/mesh_io.h"
#include "io/placement_io.h"
#include "mesh/lightmap_raster.h"
#include "sh/sh.h"

namespace ahd::cli {

void add_input_options(CLI::App* c, InputArgs* a) {
  c->add_option("--layout", a->layout,
                "Baker layout preset (ahdpack layouts), FILE.json, or auto (the default for an input that is not the "
                "canonical EXR): the input is then any file of the baker's set, or its base path");
  c->add_option("--pages", a->pages,
                "Atlas pages of a stacked layout (Godot: slices/vertical / 4), when NAME.exr.import is not beside it")
      ->check(CLI::PositiveNumber);
  c->add_option("--normals", a->normals, "Lightmap-space normal EXR, for world-space layouts");
  c->add_option("--mesh", a->mesh,
                "Mesh (.gltf, .glb, .obj) rasterised in its lightmap UVs: the normals (world-space layouts) and the "
                "coverage (any layout); instead of --normals. Lightmap row 0 = glTF v=0 = OBJ v=1");
  c->add_option("--uv-set", a->uv_set,
                "The mesh's lightmap UV set (glTF TEXCOORD_n); default: the second set when the meshes have 2 or "
                "more, else the first")
      ->check(CLI::NonNegativeNumber);
  c->add_option("--placement", a->placement,
                "Atlas placement of the mesh's instances (node name -> page, scale, offset): ahdpack's JSON or a Unity "
                "scene (.unity: m_LightmapIndex, m_LightmapTilingOffset); each instance's UVs become uv*scale+offset");
}

void resolve_auto_layout(InputArgs* a) {
  if (a->input.empty() || (!a->layout.empty() && a->layout != "auto")) return;
  if (a->layout.empty() && is_canonical_sh_file(a->input)) return;
  std::optional<LayoutDetection> d;
  if (a->layout == "auto") d = detect_layout(a->input);
  else d = try_detect_layout(a->input);
  if (!d) return;
  a->layout = d->preset == "canonical" ? "" : d->preset;
  a->input = d->base;
  a->notes += "layout auto: " + d->preset + " (base " + d->base + ")\n";
  for (const std::string& r : d->reasons) a->notes += "  because " + r + "\n";
  for (const std::string& n : d->notes) a->notes += "  note: " + n + "\n";
}

void check_input_args(const InputArgs& a) {
  if (!a.mesh.empty() && !a.normals.empty()) throw Error("--mesh and --normals both give the normals: use one");
  if (!a.mesh.empty() && a.layout.empty()) throw Error("--mesh needs --layout (a baker's files to pair it with)");
  if (a.uv_set >= 0 && a.mesh.empty()) throw Error("--uv-set needs --mesh");
  if (!a.placement.empty() && a.mesh.empty()) throw Error("--placement needs --mesh (the instances it places)");
}

namespace {

// The baker's files through a layout preset, with normals/coverage from --normals or --mesh.
// The mesh's triangles for atlas page `page`: as stored, or each instance moved into its atlas
// rectangle by --placement (overlaps printed; *note says what was placed).
MeshTriangles page_mesh(const InputArgs& a, int page, MeshReadInfo* mi, std::string* note) {
  if (a.placement.empty()) return read_mesh_lightmap(a.mesh, a.uv_set, mi);
  const MeshInstances scene = read_mesh_instances(a.mesh, a.uv_set, mi);
  PlacedMesh pm = place_instances(scene, read_placements(a.placement), page, a.placement);
  *note = ", " + std::to_string(pm.placed.size()) + " instance(s) placed by " + a.placement +
          (pm.unplaced.empty() ? "" : " (" + std::to_string(pm.unplaced.size()) + " without placement left out)");
  for (const std::string& o : pm.overlaps) {
    *note += ", overlap: " + o;
    a.notes += "placement: page " + std::to_string(page) + ": instances " + o + " overlap in the atlas\n";
  }
  return std::move(pm.mesh);
}

ShImage read_layout_input(const InputArgs& a, const LayoutPreset& layout, ReadStats* rs, std::string* source,
                          int page = 0) {
  std::string from_mesh;
  ShImage sh;
  if (!a.mesh.empty()) {
    if (layout.canonical)
      throw Error("layout " + layout.name + " is the tool's own EXR (coverage and normals inside): --mesh does not apply");
    // The mesh is rasterised at the lightmap's size, known from the first file's header.
    int w = 0, h = 0;
    layout_size(layout, a.input, &w, &h);
    MeshReadInfo mi;
    std::string placed;
    const MeshTriangles mesh = page_mesh(a, page, &mi, &placed);
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
                std::to_string(covered) + " texels covered" + placed + ")";
  } else {
    sh = read_layout(layout, a.input, a.normals, rs);
  }
  *source = a.input + " (layout " + layout.name + ", " + std::to_string(sh.width) + "x" + std::to_string(sh.height) +
            " " + std::string(sh_order_name(sh.coeffs)) + (sh.normals.empty() ? ", tangent space" : ", world space + normals") +
            from_mesh + ")";
  return sh;
}

// The SH to convert: the built-in sample, a baker's files (--layout) or the canonical EXR.
ShImage read_input(const InputArgs& a, int threads, ReadStats* rs, std::string* source) {
  if (a.input.empty()) {
    *source = "built-in sample (analytic scene, " + std::to_string(a.sample_size) + "x" + std::to_string(a.sample_size) +
              (a.sample_order == 2 ? " L2" : " L1") + ", seed " + std::to_string(a.seed) + ")";
    return bake_sample(a.sample_size, a.sample_order, a.seed, threads);
  }
  if (!a.layout.empty()) return read_layout_input(a, load_layout(a.layout), rs, source);
  ShImage sh = read_canonical_sh(a.input, rs);
  *source = a.input + " (" + std::to_string(sh.width) + "x" + std::to_string(sh.height) + " " + std::string(sh_order_name(sh.coeffs)) +
            (sh.normals.empty() ? ", tangent space)" : ", world space + normals)");
  return sh;
}

}  // namespace

std::vector<ShImage> read_input_pages(const InputArgs& a, int threads, ReadStats* rs, std::string* source) {
  if (a.layout.empty() || a.input.empty()) {
    if (a.pages > 1) throw Error("--pages needs a paged layout (Godot's stacked atlas)");
    return {read_input(a, threads, rs, source)};
  }
  const LayoutPreset layout = load_layout(a.layout);
  const LayoutPages lp = layout_pages(layout, a.input, a.pages);
  if (!lp.why.empty()) a.notes += "atlas: " + lp.why + "\n";
  std::vector<ShImage> pages;
  for (int p = 0; p < lp.pages; ++p) pages.push_back(read_layout_input(a, layout_page(layout, p, lp.pages), rs, source, p));
  if (lp.pages > 1) *source += ", " + std::to_string(lp.pages) + " atlas pages -> array layers";
  return pages;
}

}  // namespace ahd::cli
