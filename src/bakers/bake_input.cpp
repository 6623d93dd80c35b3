#include "bakers/bake_input.h"

#include <ahd/sample.h>

#include "core/error.h"
#include "image/colour_space.h"
#include "bakers/baker_layout.h"
#include "bakers/godot/godot_import.h"
#include "bakers/godot/godot_scene.h"
#include "bakers/godot/godot_unplaced.h"
#include "bakers/layout_detect.h"
#include "bakers/layout_pages.h"
#include "bakers/unity/lightmap_page.h"
#include "scene/mesh_io.h"
#include "scene/placement_io.h"
#include "scene/coverage_check.h"
#include "scene/lightmap_raster.h"
#include "sh/sh.h"
#include "files/utf8_path.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace ahd {

const std::vector<BakeInputOption>& bake_input_options() {
  static const std::vector<BakeInputOption> options = [] {
    std::string names;
    for (const std::string& n : input_space_names()) names += (names.empty() ? "" : ", ") + n;
    return std::vector<BakeInputOption>{
        {"--layout", &BakeInput::layout,
         "Baker layout preset (ahdpack layouts), FILE.json, or auto (the default for an input that is not the "
         "canonical EXR): the input is then any file of the baker's set, or its base path"},
        {"--pages", &BakeInput::pages,
         "Atlas pages of a stacked layout (Godot: slices/vertical / 4), when NAME.exr.import is not beside it", 1},
        {"--normals", &BakeInput::normals, "Lightmap-space normal EXR, for world-space layouts"},
        {"--mesh", &BakeInput::mesh,
         "Mesh (.gltf, .glb, .obj) rasterised in its lightmap UVs: the normals (world-space layouts) and the "
         "coverage (any layout); instead of --normals. Lightmap row 0 = glTF v=0 = OBJ v=1"},
        {"--node", &BakeInput::node,
         "Per-object lightmaps (Bevy): the one node of --mesh the lightmap belongs to, by its glTF node name or "
         "mesh name (e.g. Bevy's GltfMeshName); the other nodes are left out"},
        {"--uv-set", &BakeInput::uv_set,
         "The mesh's lightmap UV set (glTF TEXCOORD_n); default: the second set when the meshes have 2 or "
         "more, else the first"},
        {"--placement", &BakeInput::placement,
         "Atlas placement of the mesh's instances (node name -> page, scale, offset): ahdpack's JSON or a Unity "
         "scene (.unity: m_LightmapIndex, m_LightmapTilingOffset); each instance's UVs become uv*scale+offset"},
        {"--page", &BakeInput::page,
         "The atlas page of a one-page lightmap file, for --placement (default: from the file name, Unity "
         "Lightmap-N_comp_light.exr or Bakery _LMN; else 0)"},
        {"--godot-scene", &BakeInput::scene,
         "A Godot project's scene (.tscn) holding the LightmapGI that baked the input: every lightmap user's "
         "mesh (.glb + its .unwrap_cache UV2, or TEXCOORD_1), transform and atlas rectangle (.lmbake); "
         "found by itself in the EXR's project (the .tscn whose LightmapGI's light_data is NAME.lmbake). "
         "Or the scene exported from Godot's editor as "
         "glTF (.glb/.gltf with UV2 as TEXCOORD_1), placed by the NAME.lmbake beside the EXR"},
        {"--input-space", &BakeInput::input_space,
         "The input's colour space, replacing what its files declare (or a missing declaration): " + names +
             "; converted to linear Rec.709 through OpenColorIO (docs/colour.md)"},
        {"--allow-mismatch", &BakeInput::allow_mismatch,
         "Convert even when the mesh's coverage disagrees with the lightmap (lit texels outside it, covered "
         "texels black, overlapping instances without placement)"},
        {"--allow-unplaced", &BakeInput::allow_unplaced,
         "Godot: convert even when some lightmap users cannot be placed from the project (a cache entry Godot "
         "dropped, a TextMesh, a GridMap cell, a missing file): the others are converted from their meshes, the "
         "unplaced users' lit texels with normals taken from the SH itself, counted in the summary and report "
         "(docs/godot.md \"Users that cannot be placed\")"},
    };
  }();
  return options;
}

namespace {

// `--layout plain` reads one image as one lightmap. Godot's atlases are one image of stacked
// layers (its importer's 2d_array_texture, slices/vertical = pages × 4 for directional SH: L0, L1y,
// L1z, L1x per page), which plain would convert as one tall map mixing L0 with L1: refused, naming
// what the set is and the remedy (docs/godot.md "Damaged or unsuitable SH").
void refuse_plain_on_a_stack(const BakeInput& a) {
  if (a.layout != "plain" || a.input.empty()) return;
  const std::string exr = layout_base(load_layout("plain"), a.input) + ".exr";
  const GodotImport gi = read_godot_import(exr);
  if (!gi.found || gi.importer != "2d_array_texture" || gi.slices_vertical <= 1) return;
  std::string detected;
  try {
    if (std::optional<LayoutDetection> d = try_detect_layout(exr)) detected = d->preset;
  } catch (const Error&) {  // ambiguous or unsupported: --layout auto says why
  }
  const int s = gi.slices_vertical;
  const std::string what = s % 4 == 0 ? "a Godot directional SH atlas, " + std::to_string(s / 4) +
                                            " page(s) x (L0 + three L1 layers)"
                                      : "a Godot atlas of " + std::to_string(s) + " layers";
  throw file_error(exr, "is " + what + " stacked vertically (" + utf8_string(fs_path(exr).filename()) +
                            ".import: slices/vertical=" + std::to_string(s) + (detected.empty() ? "" : "; detected: " + detected) +
                            "): --layout plain would convert the whole stack as one lightmap; use --layout auto" +
                            (detected.empty() ? "" : " or --layout " + detected) +
                            " (add --direction drop for the I_z plane alone)");
}

}  // namespace

void resolve_auto_layout(BakeInput* a) {
  refuse_plain_on_a_stack(*a);
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

void find_scene_for_input(BakeInput* a) {
  if (a->layout.empty() || a->input.empty() || !a->normals.empty() || !a->mesh.empty() || !a->scene.empty()) return;
  const LayoutPreset layout = load_layout(a->layout);
  if (!layout.world_space || layout.name.rfind("godot", 0) != 0) return;
  const std::string exr = layout_base(layout, a->input) + ".exr";
  const std::string scene = find_godot_scene(exr);
  if (scene.empty()) return;
  a->scene = scene;
  a->notes += "godot scene: " + scene + " (its LightmapGI baked " + utf8_string(fs_path(exr).filename()) +
              "): meshes, normals and atlas placement from the project\n";
}

void check_bake_input(const BakeInput& a) {
  if (!a.input_space.empty()) {
    if (a.input.empty()) throw Error("--input-space needs an input (the built-in sample is in the working space)");
    parse_input_space(a.input_space);  // an unknown name, before anything is read
  }
  if (!a.mesh.empty() && !a.normals.empty()) throw Error("--mesh and --normals both give the normals: use one");
  if (!a.scene.empty() && (!a.mesh.empty() || !a.normals.empty() || !a.placement.empty()))
    throw Error("--godot-scene gives the meshes, normals and placement: not with --mesh, --normals or --placement");
  if (!a.mesh.empty() && a.layout.empty()) throw Error("--mesh needs --layout (a baker's files to pair it with)");
  if (a.uv_set >= 0 && a.mesh.empty()) throw Error("--uv-set needs --mesh");
  if (!a.placement.empty() && a.mesh.empty()) throw Error("--placement needs --mesh (the instances it places)");
  if (!a.node.empty() && a.mesh.empty()) throw Error("--node needs --mesh (the file holding the node)");
  if (!a.node.empty() && !a.placement.empty())
    throw Error("--node takes one object at its own UVs; --placement places every instance in an atlas: use one");
  if (a.page >= 0 && a.placement.empty()) throw Error("--page selects the instances --placement puts on that page: give --placement");
}

double input_iz_scale(const BakeInput& a, std::string* why) {
  if (a.layout.empty() || a.input.empty()) return 1.0;
  const LayoutPreset layout = load_layout(a.layout);
  if (layout.coeffs != 1 || layout.form != LayoutForm::LinearOverPi) return 1.0;
  if (why)
    *why = "iz scale: E/pi, the input's own numbers (" + layout.name +
           " holds E/pi; --iz-scale E stores irradiance, pi times more)";
  return 1.0 / kPi;
}

namespace {

// The baker's files through a layout preset, with normals/coverage from --normals or --mesh.
// The mesh's triangles for atlas page `page`: as stored, or each instance moved into its atlas
// rectangle by --placement (overlaps printed; *note says what was placed).
// What gives the normals and coverage: the mesh file or the Godot scene.
const std::string& mesh_source(const BakeInput& a) { return a.scene.empty() ? a.mesh : a.scene; }

// A .tscn of the project, or the editor's glTF export of the scene placed by the bake's .lmbake
// (NAME.lmbake beside NAME.exr, as Godot writes them).
GodotSceneMeshes load_godot_meshes(const BakeInput& a) {
  std::string ext = utf8_string(fs_path(a.scene).extension());
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".glb" && ext != ".gltf") return load_godot_scene(a.scene);
  const std::string lmbake = layout_base(load_layout(a.layout), a.input) + ".lmbake";
  if (!std::filesystem::exists(fs_path(lmbake)))
    throw file_error(a.scene, "a glTF export is placed by the bake's .lmbake, expected beside the lightmap: " + lmbake +
                                        " not found");
  return load_godot_export(a.scene, lmbake);
}

// What a page's meshes gave, for the summary line: read_bake_pages sums it over an atlas's pages
// (one page's counts alone would say "9 of 39 users placed" when the 4 pages placed 32).
struct PageMesh {
  MeshReadInfo mi;
  size_t covered = 0;      // texels the page's triangles cover
  size_t placed = 0;       // instances placed on the page (--godot-scene, --placement)
  std::string placed_of;   // after the count: " of N lightmap users placed by X", " instance(s) placed by P"
  size_t unplaced = 0;     // --placement: instances no placement names (the same on every page)
  std::string overlaps;    // ", overlap: A and B" for --placement
  size_t unplaced_users = 0, unplaced_kept = 0;  // --allow-unplaced: Godot users left out, their lit texels kept
  std::string unplaced_where;                    // " on page P", " on pages 0-N"
};

std::string placed_text(const PageMesh& pm) {
  if (pm.placed_of.empty()) return "";
  return ", " + std::to_string(pm.placed) + pm.placed_of +
         (pm.unplaced ? " (" + std::to_string(pm.unplaced) + " without placement left out)" : "") + pm.overlaps;
}

// ", normals and coverage from SRC (T triangles, UV set U, C texels covered, P … placed by X)".
std::string mesh_text(const BakeInput& a, const LayoutPreset& layout, const PageMesh& pm, const std::string& pages) {
  return ", " + std::string(layout.world_space ? "normals and coverage" : "coverage") + " from " + mesh_source(a) +
         " (" + std::to_string(pm.mi.triangles) + " triangles, UV set " + std::to_string(pm.mi.uv_set) + ", " +
         std::to_string(pm.covered) + " texels covered" + pages + placed_text(pm) + ")" +
         (a.godot && !a.godot->unplaced.empty()
              ? ", " + std::to_string(pm.unplaced_users) + " unplaced user(s)" + pm.unplaced_where + ": " +
                    std::to_string(pm.unplaced_kept) + " lit texels kept with normals from the SH (--allow-unplaced)"
              : "");
}

MeshTriangles godot_page_mesh(const BakeInput& a, int page, MeshReadInfo* mi, PageMesh* note) {
  if (!a.godot) {
    auto g = std::make_shared<const GodotSceneMeshes>(load_godot_meshes(a));
    if (!g->unplaced.empty() && !a.allow_unplaced) throw file_error(g->lmbake, godot_unplaced_refusal(*g));
    a.godot = g;
    for (const std::string& n : a.godot->notes) a.notes += "godot scene: " + n + "\n";
    for (const GodotUnplacedUser& u : a.godot->unplaced) {  // those the reader's notes do not name already
      const std::string named = "lightmap user " + u.node + " left out: ";
      if (std::none_of(a.godot->notes.begin(), a.godot->notes.end(),
                       [&](const std::string& n) { return n.rfind(named, 0) == 0; }))
        a.notes += "godot scene: unplaced (--allow-unplaced): " + u.node + ": " + u.why + "\n";
    }
  }
  const GodotSceneMeshes& g = *a.godot;
  PlacedMesh pm = place_instances(g.scene, g.placements, page, g.lmbake);
  *mi = {2, 2, int(pm.placed.size()), pm.mesh.indices.size() / 3};
  note->placed = pm.placed.size();
  note->placed_of = " of " + std::to_string(g.users) + " lightmap users placed by " + g.lmbake;
  for (const std::string& o : pm.overlaps) a.notes += "placement: page " + std::to_string(page) + ": instances " + o + " overlap in the atlas\n";
  if (pm.overlap_count > pm.overlaps.size())
    a.notes += "placement: page " + std::to_string(page) + ": … and " + std::to_string(pm.overlap_count - pm.overlaps.size()) +
               " more overlapping pair(s)\n";
  return std::move(pm.mesh);
}

// --node: the instances of the mesh file whose node or mesh name is `a.node`, at their own UVs.
MeshTriangles node_mesh(const BakeInput& a, int page, MeshReadInfo* mi, PageMesh* note) {
  const MeshInstances scene = read_mesh_instances(a.mesh, a.uv_set, mi);
  std::vector<Placement> chosen;
  std::string names;
  for (const Placement& p : identity_placements(scene, page)) {
    const MeshInstance& inst = *std::find_if(scene.instances.begin(), scene.instances.end(),
                                             [&](const MeshInstance& i) { return i.node == p.node; });
    // Assimp names the meshes of a glTF mesh of several primitives NAME-0, NAME-1, …: each is NAME.
    const auto is_mesh = [&](const std::string& m) {
      if (m == a.node) return true;
      if (m.size() <= a.node.size() + 1 || m.compare(0, a.node.size() + 1, a.node + "-") != 0) return false;
      return std::all_of(m.begin() + std::ptrdiff_t(a.node.size() + 1), m.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
    };
    const bool match = inst.node == a.node || std::any_of(inst.meshes.begin(), inst.meshes.end(), is_mesh);
    if (match && std::none_of(chosen.begin(), chosen.end(), [&](const Placement& c) { return c.node == p.node; }))
      chosen.push_back(p);
    names += (names.empty() ? "" : ", ") + inst.node + (inst.meshes.empty() ? "" : " (mesh " + inst.meshes[0] + ")");
  }
  if (chosen.empty())
    throw file_error(a.mesh, "no node or mesh named '" + a.node + "' (nodes: " + names + ")");
  PlacedMesh pm = place_instances(scene, chosen, page, a.mesh);
  note->placed = pm.placed.size();
  note->placed_of = " node(s) named " + a.node;
  mi->triangles = pm.mesh.indices.size() / 3;
  return std::move(pm.mesh);
}

MeshTriangles page_mesh(const BakeInput& a, int page, MeshReadInfo* mi, PageMesh* note) {
  if (!a.scene.empty()) return godot_page_mesh(a, page, mi, note);
  if (!a.node.empty()) return node_mesh(a, page, mi, note);
  if (a.placement.empty()) {
    // Several instances whose lightmap UVs overlap need their atlas placement: merged, they
    // would be rasterised on top of each other.
    const MeshInstances scene = read_mesh_instances(a.mesh, a.uv_set, mi);
    if (!a.allow_mismatch) {
      const PlacedMesh all = place_instances(scene, identity_placements(scene, page), page, a.mesh);
      if (!all.overlaps.empty())
        throw file_error(a.mesh, std::to_string(all.overlap_count) + " pair(s) of instances overlap in UV set " +
                                     std::to_string(mi->uv_set) + " (first: " + all.overlaps.front() +
                                     ") and no placement was given: give --placement (JSON or the Unity scene), "
                                     "--godot-scene for a Godot project, or --allow-mismatch");
    }
    return read_mesh_lightmap(a.mesh, a.uv_set, mi);
  }
  const MeshInstances scene = read_mesh_instances(a.mesh, a.uv_set, mi);
  if (a.page_count_of_input == 1) page = a.placement_page;  // a one-page file: the page it is (read_bake_pages)
  PlacedMesh pm = place_instances(scene, read_placements(a.placement), page, a.placement);
  note->placed = pm.placed.size();
  note->placed_of = " instance(s) placed by " + a.placement;
  note->unplaced = pm.unplaced.size();
  for (const std::string& o : pm.overlaps) {
    note->overlaps += ", overlap: " + o;
    a.notes += "placement: page " + std::to_string(page) + ": instances " + o + " overlap in the atlas\n";
  }
  if (pm.overlap_count > pm.overlaps.size()) {
    const std::string more = std::to_string(pm.overlap_count - pm.overlaps.size()) + " more";
    note->overlaps += ", overlap: … and " + more;
    a.notes += "placement: page " + std::to_string(page) + ": … and " + more + " overlapping pair(s)\n";
  }
  return std::move(pm.mesh);
}

ShImage read_layout_input(const BakeInput& a, const LayoutPreset& layout, ReadStats* rs, std::string* source,
                          int page = 0, PageMesh* page_mesh_out = nullptr) {
  std::string from_mesh;
  ShImage sh;
  if (!a.mesh.empty() || !a.scene.empty()) {
    const std::string& src = mesh_source(a);
    if (layout.canonical)
      throw Error("layout " + layout.name + " is the tool's own EXR (coverage and normals inside): --mesh does not apply");
    // The mesh is rasterised at the lightmap's size, known from the first file's header.
    int w = 0, h = 0;
    layout_size(layout, a.input, &w, &h);
    PageMesh placed;
    MeshReadInfo& mi = placed.mi;
    const MeshTriangles mesh = page_mesh(a, page, &mi, &placed);
    RasterisedNormals rn = rasterise_lightmap_normals(mesh, w, h);
    mesh_normals_to_layout_axes(layout, &rn.normals);  // glTF's axes → the baker's world
    size_t covered = 0;
    for (uint8_t c : rn.coverage) covered += c;
    std::vector<uint8_t> mesh_coverage = rn.coverage;
    // --allow-unplaced: the texels of the users the scene could not place, left to the SH itself.
    const std::vector<uint8_t> fallback =
        a.godot ? godot_unplaced_texels(*a.godot, page, rn.coverage, w, h) : std::vector<uint8_t>();
    for (size_t i = 0; i < fallback.size(); ++i)
      if (fallback[i]) rn.coverage[i] = 1, rn.normals[i * 3] = rn.normals[i * 3 + 1] = 0, rn.normals[i * 3 + 2] = 1;
    if (covered == 0 && !a.placement.empty() && placed.placed == 0)
      throw file_error(a.placement, "places no instance on atlas page " + std::to_string(a.placement_page) + " (the page of " +
                                        utf8_string(fs_path(a.input).filename()) +
                                        "; --page N names another)");
    if (covered == 0)
      throw file_error(src, "no triangle covers any texel of the " + std::to_string(w) + "x" + std::to_string(h) +
                                   " lightmap in UV set " + std::to_string(mi.uv_set) + " (wrong --uv-set?)");
    // Tangent-space layouts take the coverage only (read_layout uses normals for world space).
    const LayoutNormals ln{src, w, h, std::move(rn.normals), std::move(rn.coverage)};
    sh = read_layout(layout, a.input, &ln, rs);
    const size_t kept = keep_godot_unplaced_texels(fallback, &sh, &mesh_coverage);
    // Never silently wrong: the mesh's coverage against what the baker wrote.
    // Godot 4.4+ (packed L1) dilates farther than 4.2 (scene/coverage_check.h).
    // A KTX2 lightmap's baker (Bevy's Cornell box sample) dilates its charts by up to 16 texels of
    // a 1024² map: lit texels beyond 16 texels of the right mesh are 0.2–1.2 % of the lit ones,
    // beyond 8 texels 1.8–5.5 % (docs/bakers.md "Per-object lightmaps (Bevy)").
    const int ring = layout.name == "godot4-packed" ? kGodot44Dilation : layout.name == "plain-ktx2" ? 16 : kDilation;
    // Godot writes zeros outside its charts (no fill to find) and may light a chart uniformly.
    const CoverageComparison cc = compare_coverage(mesh_coverage, sh, ring, layout.name.rfind("godot", 0) != 0);
    a.notes += "coverage: page " + std::to_string(page) + ": " + describe_coverage(cc) + "\n";
    // A lightmap lit in every texel (gutters filled) says nothing about its charts.
    const std::string bad = cc.lit == sh.texels() ? "" : coverage_mismatch(cc);
    if (!bad.empty() && !a.allow_mismatch)
      throw file_error(src, "UV set " + std::to_string(mi.uv_set) + " does not match the lightmap (" + bad + "): " +
                                (a.scene.empty() ? "give the UV set the lightmap was baked with (--uv-set), its atlas "
                                                         "placement (--placement) or --godot-scene for a Godot project"
                                                       : "the scene, meshes or unwrap caches are not the ones that baked it") +
                                "; --allow-mismatch converts anyway");
    placed.covered = covered;
    if (a.godot && !a.godot->unplaced.empty()) {
      for (const GodotUnplacedUser& u : a.godot->unplaced) placed.unplaced_users += u.page == page;
      placed.unplaced_kept = kept;
      placed.unplaced_where = " on page " + std::to_string(page);
      a.notes += "unplaced: page " + std::to_string(page) + ": " + std::to_string(placed.unplaced_users) + " user(s), " +
                 std::to_string(kept) + " lit texels fitted about the SH's own direction, not the surface's\n";
    }
    from_mesh = mesh_text(a, layout, placed, "");
    if (page_mesh_out) *page_mesh_out = placed;
  } else {
    sh = read_layout(layout, a.input, a.normals, rs);
  }
  *source = a.input + " (layout " + layout.name + ", " + std::to_string(sh.width) + "x" + std::to_string(sh.height) +
            " " + std::string(sh_order_name(sh.coeffs)) + (sh.normals.empty() ? ", tangent space" : ", world space + normals") +
            from_mesh + ")";
  return sh;
}

// The SH to convert: the built-in sample, a baker's files (--layout) or the canonical EXR.
ShImage read_input(const BakeInput& a, int threads, ReadStats* rs, std::string* source) {
  if (a.input.empty()) {
    *source = "built-in sample (analytic scene, " + std::to_string(a.sample_size) + "x" + std::to_string(a.sample_size) +
              (a.sample_order == 2 ? " L2" : " L1") + ", seed " + std::to_string(a.seed) + ")";
    return bake_sample(a.sample_size, a.sample_order, a.seed, threads);
  }
  if (!a.layout.empty()) {
    LayoutPreset layout = load_layout(a.layout);
    layout.input_space = a.input_space;
    return read_layout_input(a, layout, rs, source);
  }
  ShImage sh = read_canonical_sh(a.input, rs, a.input_space);
  *source = a.input + " (" + std::to_string(sh.width) + "x" + std::to_string(sh.height) + " " + std::string(sh_order_name(sh.coeffs)) +
            (sh.normals.empty() ? ", tangent space)" : ", world space + normals)");
  return sh;
}

}  // namespace

namespace {

// The summary names a conversion of colour (nothing for the working space: its lines as before).
void note_colour(const ReadStats* rs, std::string* source) {
  if (rs && !rs->input_space.empty()) *source += ", colour converted from " + rs->input_space;
}

}  // namespace

std::vector<ShImage> read_bake_pages(const BakeInput& a, int threads, ReadStats* rs, std::string* source) {
  if (a.layout.empty() || a.input.empty()) {
    if (a.pages > 1) throw Error("--pages needs a paged layout (Godot's stacked atlas)");
    std::vector<ShImage> one;
    one.push_back(read_input(a, threads, rs, source));
    note_colour(rs, source);
    return one;
  }
  LayoutPreset layout = load_layout(a.layout);
  layout.input_space = a.input_space;
  const LayoutPages lp = layout_pages(layout, a.input, a.pages);
  if (!lp.why.empty()) a.notes += "atlas: " + lp.why + "\n";
  a.page_count_of_input = lp.pages;
  if (lp.pages > 1 && a.page >= 0)
    throw Error("--page names the page of a one-page file; " + a.input + " holds " + std::to_string(lp.pages) + " pages");
  if (lp.pages == 1 && !a.placement.empty()) {
    std::string why;
    const int named = lightmap_page_from_name(a.input, &why);
    a.placement_page = a.page >= 0 ? a.page : std::max(0, named);
    if (a.page >= 0 && named >= 0 && named != a.page)
      a.notes += "placement: page " + std::to_string(a.page) + " (--page; " + why + " says " + std::to_string(named) + ")\n";
    else if (a.page < 0 && named >= 0)
      a.notes += "placement: page " + std::to_string(named) + " (" + why + ")\n";
  }
  std::vector<ShImage> pages;
  std::vector<PageMesh> meshes(size_t(lp.pages));
  for (int p = 0; p < lp.pages; ++p)
    pages.push_back(read_layout_input(a, layout_page(layout, p, lp.pages), rs, source, p, &meshes[size_t(p)]));
  if (lp.pages > 1 && (!a.mesh.empty() || !a.scene.empty())) {
    // The summary of every page, not the last one's: totals, and the placed count of each page.
    PageMesh total = meshes[0];
    std::string per_page;
    for (size_t p = 0; p < meshes.size(); ++p) {
      if (p) {
        total.mi.triangles += meshes[p].mi.triangles, total.covered += meshes[p].covered;
        total.placed += meshes[p].placed, total.overlaps += meshes[p].overlaps;
        total.unplaced_users += meshes[p].unplaced_users, total.unplaced_kept += meshes[p].unplaced_kept;
      }
      per_page += (p ? " + " : "") + std::to_string(meshes[p].placed);
    }
    if (!total.placed_of.empty()) total.placed_of += " (" + per_page + " on pages 0-" + std::to_string(lp.pages - 1) + ")";
    total.unplaced_where = " on pages 0-" + std::to_string(lp.pages - 1);
    *source = a.input + " (layout " + layout.name + ", " + std::to_string(pages[0].width) + "x" +
              std::to_string(pages[0].height) + " " + std::string(sh_order_name(pages[0].coeffs)) +
              (pages[0].normals.empty() ? ", tangent space" : ", world space + normals") +
              mesh_text(a, layout, total, " on " + std::to_string(lp.pages) + " pages") + ")";
  }
  if (lp.pages > 1) *source += ", " + std::to_string(lp.pages) + " atlas pages -> array layers";
  note_colour(rs, source);
  return pages;
}

std::vector<ShImage> read_bake_input(BakeInput* a, int threads, ReadStats* rs, std::string* source) {
  resolve_auto_layout(a);
  find_scene_for_input(a);
  check_bake_input(*a);
  return read_bake_pages(*a, threads, rs, source);
}

}  // namespace ahd
