// ahdpack convert [IN.exr] [-o OUT.ktx2|OUT.dds]: SH lightmap → AHD planes + manifest + report.
#include <ahd/sample.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <set>

#include "api/options.h"
#include "cli/batch_schedule.h"
#include "cli/commands.h"
#include "cli/conversion_args.h"
#include "cli/output.h"
#include "cli/progress.h"
#include "core/error.h"
#include "core/parallel.h"
#include "io/ahd_intermediate.h"
#include "io/baker_layout.h"
#include "io/colour_space.h"
#include "io/godot_scene.h"
#include "io/image_io.h"
#include "io/layout_detect.h"
#include "io/layout_pages.h"
#include "io/mesh_io.h"
#include "io/placement_io.h"
#include "io/profile_file.h"
#include "io/sh_exr.h"
#include "mesh/coverage_check.h"
#include "pipeline/run.h"
#include "sh/sh.h"

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
  int pages = 0;        // atlas pages of a paged layout (0 = as recorded by the baker)
  std::string placement;  // per-instance atlas placement of the mesh (JSON or Unity scene)
  std::string godot_scene;  // or: a Godot scene (.tscn) whose LightmapGI baked the input
  bool allow_mismatch = false;
  std::string iz_scale = "E";  // stored I_z: E, E/pi, or a factor times E  // convert even when the mesh's coverage disagrees with the lightmap
  mutable std::shared_ptr<const GodotSceneMeshes> godot;  // the scene, loaded once for every page
  // What reading found (detection, pages, overlaps), printed once the input has been read, so that
  // a failure prints its one error line and nothing else.
  mutable std::string notes;
  int sample_size = 256;
  int sample_order = 2;
  unsigned seed = 0;
  bool keep_intermediate = false;
  ConversionArgs conv;
};

// --layout auto, and the default for an input that is not the canonical EXR: the baker's set is
// detected from the files present and their contents, and what was found is printed with why.
// Without --layout, an input nothing recognises goes to the canonical reader (its errors).
void resolve_auto_layout(ConvertArgs* a) {
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

// --iz-scale: "E" (1), "E/pi" (1/π) or a positive factor.
double iz_scale_factor(const std::string& s) {
  if (s == "E" || s == "e") return 1.0;
  if (s == "E/pi" || s == "e/pi" || s == "E/π") return 1.0 / 3.14159265358979323846;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || *end != '\0' || !(v > 0) || !std::isfinite(v))
    throw Error("--iz-scale takes E, E/pi or a positive factor, not '" + s + "'");
  return v;
}

// A Godot world-space bake without normals: the scene that baked it, when it lies beside the EXR.
void find_godot_scene_for_input(ConvertArgs* a) {
  if (a->layout.empty() || a->input.empty() || !a->normals.empty() || !a->mesh.empty() || !a->godot_scene.empty()) return;
  const LayoutPreset layout = load_layout(a->layout);
  if (!layout.world_space || layout.name.rfind("godot", 0) != 0) return;
  const std::string exr = layout_base(layout, a->input) + ".exr";
  const std::string scene = find_godot_scene(exr);
  if (scene.empty()) return;
  a->godot_scene = scene;
  a->notes += "godot scene: " + scene + " (its LightmapGI baked " + fs::path(exr).filename().string() +
              "): meshes, normals and atlas placement from the project\n";
}

// The baker's files through a layout preset, with normals/coverage from --normals or --mesh.
// The mesh's triangles for atlas page `page`: as stored, or each instance moved into its atlas
// rectangle by --placement (overlaps printed; *note says what was placed).
// What gives the normals and coverage: the mesh file or the Godot scene.
const std::string& mesh_source(const ConvertArgs& a) { return a.godot_scene.empty() ? a.mesh : a.godot_scene; }

MeshTriangles godot_page_mesh(const ConvertArgs& a, int page, MeshReadInfo* mi, std::string* note) {
  if (!a.godot) {
    a.godot = std::make_shared<const GodotSceneMeshes>(load_godot_scene(a.godot_scene));
    for (const std::string& n : a.godot->notes) a.notes += "godot scene: " + n + "\n";
  }
  const GodotSceneMeshes& g = *a.godot;
  PlacedMesh pm = place_instances(g.scene, g.placements, page, g.lmbake);
  *mi = {2, 2, int(pm.placed.size()), pm.mesh.indices.size() / 3};
  *note = ", " + std::to_string(pm.placed.size()) + " of " + std::to_string(g.users) + " lightmap users placed by " + g.lmbake;
  for (const std::string& o : pm.overlaps) a.notes += "placement: page " + std::to_string(page) + ": instances " + o + " overlap in the atlas\n";
  return std::move(pm.mesh);
}

MeshTriangles page_mesh(const ConvertArgs& a, int page, MeshReadInfo* mi, std::string* note) {
  if (!a.godot_scene.empty()) return godot_page_mesh(a, page, mi, note);
  if (a.placement.empty()) {
    // Several instances whose lightmap UVs overlap need their atlas placement: merged, they
    // would be rasterised on top of each other.
    const MeshInstances scene = read_mesh_instances(a.mesh, a.uv_set, mi);
    if (!a.allow_mismatch) {
      const PlacedMesh all = place_instances(scene, identity_placements(scene, page), page, a.mesh);
      if (!all.overlaps.empty())
        throw file_error(a.mesh, std::to_string(all.overlaps.size()) + " pair(s) of instances overlap in UV set " +
                                     std::to_string(mi->uv_set) + " (first: " + all.overlaps.front() +
                                     ") and no placement was given: give --placement (JSON or the Unity scene), "
                                     "--godot-scene for a Godot project, or --allow-mismatch");
    }
    return read_mesh_lightmap(a.mesh, a.uv_set, mi);
  }
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

ShImage read_layout_input(const ConvertArgs& a, const LayoutPreset& layout, ReadStats* rs, std::string* source,
                          int page = 0) {
  std::string from_mesh;
  ShImage sh;
  if (!a.mesh.empty() || !a.godot_scene.empty()) {
    const std::string& src = mesh_source(a);
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
    const std::vector<uint8_t> mesh_coverage = rn.coverage;
    if (covered == 0)
      throw file_error(src, "no triangle covers any texel of the " + std::to_string(w) + "x" + std::to_string(h) +
                                   " lightmap in UV set " + std::to_string(mi.uv_set) + " (wrong --uv-set?)");
    // Tangent-space layouts take the coverage only (read_layout uses normals for world space).
    const LayoutNormals ln{src, w, h, std::move(rn.normals), std::move(rn.coverage)};
    sh = read_layout(layout, a.input, &ln, rs);
    // Never silently wrong: the mesh's coverage against what the baker wrote.
    const CoverageComparison cc = compare_coverage(mesh_coverage, sh);
    a.notes += "coverage: page " + std::to_string(page) + ": " + describe_coverage(cc) + "\n";
    // A lightmap lit in every texel (gutters filled) says nothing about its charts.
    const std::string bad = cc.lit == sh.texels() ? "" : coverage_mismatch(cc);
    if (!bad.empty() && !a.allow_mismatch)
      throw file_error(src, "UV set " + std::to_string(mi.uv_set) + " does not match the lightmap (" + bad + "): " +
                                (a.godot_scene.empty() ? "give the UV set the lightmap was baked with (--uv-set), its atlas "
                                                         "placement (--placement) or --godot-scene for a Godot project"
                                                       : "the scene, meshes or unwrap caches are not the ones that baked it") +
                                "; --allow-mismatch converts anyway");
    from_mesh = ", " + std::string(layout.world_space ? "normals and coverage" : "coverage") + " from " + src + " (" +
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
ShImage read_input(const ConvertArgs& a, ReadStats* rs, std::string* source) {
  if (a.input.empty()) {
    *source = "built-in sample (analytic scene, " + std::to_string(a.sample_size) + "x" + std::to_string(a.sample_size) +
              (a.sample_order == 2 ? " L2" : " L1") + ", seed " + std::to_string(a.seed) + ")";
    return bake_sample(a.sample_size, a.sample_order, a.seed, a.conv.options.threads);
  }
  if (!a.layout.empty()) return read_layout_input(a, load_layout(a.layout), rs, source);
  ShImage sh = read_canonical_sh(a.input, rs);
  *source = a.input + " (" + std::to_string(sh.width) + "x" + std::to_string(sh.height) + " " + std::string(sh_order_name(sh.coeffs)) +
            (sh.normals.empty() ? ", tangent space)" : ", world space + normals)");
  return sh;
}

// The input's atlas pages: one, unless a paged layout (Godot) holds several — then every page, in
// order, with the count's origin printed and appended to *source.
std::vector<ShImage> read_input_pages(const ConvertArgs& a, ReadStats* rs, std::string* source) {
  if (a.layout.empty() || a.input.empty()) {
    if (a.pages > 1) throw Error("--pages needs a paged layout (Godot's stacked atlas)");
    return {read_input(a, rs, source)};
  }
  const LayoutPreset layout = load_layout(a.layout);
  const LayoutPages lp = layout_pages(layout, a.input, a.pages);
  if (!lp.why.empty()) a.notes += "atlas: " + lp.why + "\n";
  std::vector<ShImage> pages;
  for (int p = 0; p < lp.pages; ++p) pages.push_back(read_layout_input(a, layout_page(layout, p, lp.pages), rs, source, p));
  if (lp.pages > 1) *source += ", " + std::to_string(lp.pages) + " atlas pages -> array layers";
  return pages;
}

// What one conversion of a batch reports for the summary table.
struct BatchRow {
  int width = 0, height = 0;
  size_t planes = 0;
  bool directional = true;
  double rel_mean = -1, rel_p99 = -1;  // the error estimate (−1: not measured)
};

// How a batch runs one conversion (run_convert's defaults: the terminal's progress, no lock).
struct BatchJob {
  std::function<void(const char* stage, double fraction)> progress;  // the batch's line, or none
  // Held while publishing: publish_output_set swaps the process's SIGINT/SIGTERM handlers and
  // keeps one process-wide list of temporaries, so two sets are never published at once.
  std::mutex* publish_lock = nullptr;
};

BatchRow run_convert(ConvertArgs a, const BatchJob* job = nullptr) {
  resolve_auto_layout(&a);
  find_godot_scene_for_input(&a);
  const size_t detection_notes = a.notes.size();  // why this path was taken: printed even on failure
  std::string out_path = a.output;
  if (out_path.empty())
    out_path = "ahdpack-out/" + (a.input.empty() ? std::string("sample") : fs::path(a.input).stem().string()) + ".ktx2";
  const OutputPaths out = output_paths(out_path);
  ConversionOptions co = conversion_options(a.conv);
  co.container = out.kind;
  if (job) co.cancel = interrupt_flag(), co.progress = job->progress;  // the batch installed the handler
  else attach_terminal_progress(&co, a.conv.quiet);

  // Checked before anything is read or written: one clear line, no output.
  const ResolvedOptions ro = resolve_options(co, out.name, load_profile(a.conv.profile));
  if (!a.mesh.empty() && !a.normals.empty()) throw Error("--mesh and --normals both give the normals: use one");
  const double iz_scale = iz_scale_factor(a.iz_scale);
  if (!a.godot_scene.empty() && (!a.mesh.empty() || !a.normals.empty() || !a.placement.empty()))
    throw Error("--godot-scene gives the meshes, normals and placement: not with --mesh, --normals or --placement");
  if (!a.mesh.empty() && a.layout.empty()) throw Error("--mesh needs --layout (a baker's files to pair it with)");
  if (a.uv_set >= 0 && a.mesh.empty()) throw Error("--uv-set needs --mesh");
  if (!a.placement.empty() && a.mesh.empty()) throw Error("--placement needs --mesh (the instances it places)");

  const auto t0 = std::chrono::steady_clock::now();
  ReadStats rs;
  std::string source;
  std::vector<ShImage> pages;
  try {
    pages = read_input_pages(a, &rs, &source);
  } catch (const std::exception&) {
    // What detection found says why the run took this path: printed before the one error line.
    if (!a.conv.quiet) std::fputs(a.notes.substr(0, detection_notes).c_str(), stdout), std::fflush(stdout);
    throw;
  }
  if (!a.conv.quiet) std::fputs(a.notes.c_str(), stdout);
  const double read_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  PackageOptions pkg = ro.package;
  pkg.world_frame = !pages[0].normals.empty();
  pkg.iz_scale = iz_scale;
  if (pkg.iz_scale != 1.0)  // the SH is linear in the light: scaling it scales I_z and keeps d and the ratio
    for (ShImage& p : pages)
      for (float& v : p.data) v = float(double(v) * pkg.iz_scale);
  pkg.report_extra = {{"source", source},
                      {"working_space", kWorkingSpace},
                      {"read", {{"non_finite_texels", rs.non_finite_texels}, {"coverage_derived", rs.coverage_derived}}}};
  const std::vector<StageCost> read_stage = {{a.input.empty() ? "bake sample" : "read", read_seconds}};
  ConversionRun run;
  IntermediateFile intermediate;  // none: an earlier NAME.ahd.exr goes with the set it belonged to
  if (pages.size() > 1) {  // an atlas: every page converted alone, planes stacked as array layers
    if (a.keep_intermediate) throw Error("--keep-intermediate holds one page: not available for a multi-page atlas");
    run = run_pages(pages, ro.profile, ro.convert, pkg, read_stage);
  } else {
    std::function<void(const std::vector<FittedLevel>&)> on_fitted;
    // Kept in memory and published with the set: a conversion that fails or is cancelled after the
    // fit leaves the previous NAME.ahd.exr as it was.
    if (a.keep_intermediate)
      on_fitted = [&](const std::vector<FittedLevel>& levels) {
        intermediate.bytes = encode_intermediate(out.sibling(".ahd.exr"), levels, ro.convert.fit);
      };
    run = run_conversion(std::move(pages[0]), ro.profile, ro.convert, pkg, read_stage, on_fitted);
  }
  {
    std::unique_lock<std::mutex> l;
    if (job && job->publish_lock) l = std::unique_lock<std::mutex>(*job->publish_lock);
    // The summary needs the manifest, not the bytes.
    publish_conversion(out, std::move(run.output.files), std::move(intermediate));
  }
  if (!a.conv.quiet) print_conversion(source, out, run, ro.convert.closed_loop, rs.non_finite_texels);
  BatchRow row;
  row.width = int(run.output.manifest.width);
  row.height = int(run.output.manifest.height);
  row.planes = run.output.manifest.planes.size();
  row.directional = run.result.directional;
  if (run.result.final_error.texels)
    row.rel_mean = run.result.final_error.relative.mean, row.rel_p99 = run.result.final_error.relative.p99;
  return row;
}

// The files a batch converts: each input, a folder standing for its *.exr files (sorted; not
// recursive). Globs are the shell's.
std::vector<std::string> batch_files(const std::vector<std::string>& inputs) {
  std::vector<std::string> files;
  for (const std::string& in : inputs) {
    std::error_code ec;
    if (!fs::is_directory(in, ec)) {
      files.push_back(in);
      continue;
    }
    std::vector<std::string> found;
    for (const auto& e : fs::directory_iterator(in, ec))
      if (e.is_regular_file() && e.path().extension() == ".exr") found.push_back(e.path().string());
    std::sort(found.begin(), found.end());
    if (found.empty()) throw file_error(in, "folder holds no .exr file to convert");
    files.insert(files.end(), found.begin(), found.end());
  }
  return files;
}

// The texels of a batch input, from its header alone (0 when unreadable: its conversion then
// names the cause). The header, not the file size: EXR compression makes bytes a poor measure of
// texels, and texels are what time and memory follow.
size_t header_texels(const std::string& file) {
  try {
    const ImageFileInfo info = read_image_info(file);
    return size_t(std::max(info.width, 0)) * size_t(std::max(info.height, 0));
  } catch (const std::exception&) {
    return 0;
  }
}

// `convert IN1 IN2 … -o OUTDIR/` (or one folder, or -o an existing folder): every file into OUTDIR
// with its own manifest, past failures; small files side by side with one thread each, large ones
// one at a time with every thread (batch_schedule.h); the bytes of each output are those of the
// file converted alone. One summary table in input order; exit 1 naming the failed files.
void run_batch(const ConvertArgs& a, const std::vector<std::string>& inputs) {
  const std::vector<std::string> files = batch_files(inputs);
  const fs::path dir = a.output.empty() ? fs::path("ahdpack-out") : fs::path(a.output);
  {
    // `-o out.ktx2` with several inputs is a mistake for `-o OUTDIR/`, not a folder to create.
    std::error_code ec;
    std::string ext = dir.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if ((ext == ".ktx2" || ext == ".dds") && a.output.back() != '/' && !fs::is_directory(dir, ec))
      throw file_error(a.output, "names one output file, but " + std::to_string(files.size()) +
                                     " inputs are converted: give a folder (-o OUTDIR/)");
  }
  const char* ext = a.conv.container == "dds" ? ".dds" : ".ktx2";
  struct Done {
    std::string file;
    BatchRow row;
    double seconds = 0;
    std::string error;
    bool same_name = false;  // a second input whose outputs would collide with an earlier one's
  };
  std::vector<Done> done(files.size());
  std::set<std::string> stems;
  std::vector<size_t> texels(files.size());
  for (size_t i = 0; i < files.size(); ++i) {
    done[i].file = files[i];
    done[i].same_name = !stems.insert(fs::path(files[i]).stem().string()).second;
    texels[i] = header_texels(files[i]);
  }
  const BatchPlan plan = plan_batch(texels, resolve_threads(a.conv.options.threads));
  install_interrupt_handler();
  BatchProgress progress(files.size(), a.conv.quiet);
  std::mutex publish_lock;
  const auto t_batch = std::chrono::steady_clock::now();
  const auto convert_one = [&](size_t i, int threads) {
    if (interrupt_flag()->load()) throw Cancelled();  // Ctrl-C: start no further file
    Done& d = done[i];
    const auto t0 = std::chrono::steady_clock::now();
    try {
      if (d.same_name) throw file_error(d.file, "another input has the same name: its outputs would collide");
      ConvertArgs one = a;
      one.input = d.file;
      one.output = (dir / (fs::path(d.file).stem().string() + ext)).string();
      one.conv.quiet = true;
      one.conv.options.threads = threads;
      BatchJob job;
      if (plan.jobs == 1 || threads > 1) job.progress = progress.stage_of(d.file);  // alone: its stages
      job.publish_lock = &publish_lock;
      d.row = run_convert(std::move(one), &job);
    } catch (const Cancelled&) {
      throw;
    } catch (const std::exception& e) {
      d.error = e.what();
      progress.error(d.error);
    }
    d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    progress.file_done();
  };
  try {
    run_batch_plan(plan, convert_one);
  } catch (const Cancelled&) {  // main then says the running conversions wrote nothing
    progress.finish();
    size_t converted = 0;
    for (const Done& d : done) converted += d.seconds > 0 && d.error.empty();
    std::fprintf(stderr, "ahdpack: %zu of %zu file(s) were converted before the interruption (complete outputs); of the others:\n",
                 converted, done.size());
    throw;
  }
  progress.finish();
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_batch).count();
  std::string failed;
  size_t n_failed = 0;
  if (!a.conv.quiet) std::printf("%-40s %-11s %-12s %-21s %8s\n", "file", "size", "planes", "rel. error mean / p99", "seconds");
  for (const Done& d : done) {
    if (!d.error.empty()) failed += (n_failed++ ? ", " : "") + d.file;
    if (a.conv.quiet) continue;
    const std::string size = d.error.empty() ? std::to_string(d.row.width) + "x" + std::to_string(d.row.height) : "-";
    const std::string planes = d.error.empty() ? std::to_string(d.row.planes) + (d.row.directional ? " (AHD)" : " (I_z only)") : "FAILED";
    char err[32] = "-";
    if (d.row.rel_mean >= 0) std::snprintf(err, sizeof err, "%.2e / %.2e", d.row.rel_mean, d.row.rel_p99);
    std::printf("%-40s %-11s %-12s %-21s %8.2f\n", d.file.c_str(), size.c_str(), planes.c_str(), err, d.seconds);
  }
  if (!a.conv.quiet && plan.small.empty())
    std::printf("%zu file(s) in %.2f s, one at a time (%d thread(s) each)\n", done.size(), total, plan.threads);
  else if (!a.conv.quiet)
    std::printf("%zu file(s) in %.2f s: %zu small (at most %dx%d texels) %d at a time with 1 thread each, %zu larger (or "
                "unread) one at a time with %d threads\n",
                done.size(), total, plan.small.size(), kSmallBatchSide, kSmallBatchSide, plan.jobs, plan.large.size(),
                plan.threads);
  if (n_failed)
    throw Error(std::to_string(n_failed) + " of " + std::to_string(done.size()) + " conversions failed: " + failed);
}

}  // namespace

void add_layouts_command(CLI::App& app) {
  CLI::App* c = app.add_subcommand("layouts", "List the baker layout presets (formats/bakers)");
  c->callback([]() {
    const std::vector<std::string> detected = auto_detected_layouts();
    std::printf("%-18s %-5s %s\n", "preset", "auto", "description (auto: --layout auto recognises its files)");
    for (const std::string& n : list_layouts()) {
      const LayoutPreset p = load_layout(n);
      const bool a = std::find(detected.begin(), detected.end(), n) != detected.end();
      std::printf("%-18s %-5s %s\n", n.c_str(), a ? "yes" : "no", p.description.c_str());
    }
  });
}

void add_convert_command(CLI::App& app) {
  auto a = std::make_shared<ConvertArgs>();
  CLI::App* c = app.add_subcommand("convert", "Convert an SH lightmap (or, with no input, the built-in sample) to AHD planes");
  auto inputs = std::make_shared<std::vector<std::string>>();
  c->add_option("input", *inputs,
                "Canonical SH EXR (sh0.R … sh8.B) or any file of a baker's set; omit for the built-in sample. Several "
                "inputs, or a folder (its .exr files), convert each into the folder -o names");
  c->add_option("-o,--output", a->output,
                "OUT.ktx2 or OUT.dds: writes OUT.<plane>.<hash>.<ext>, OUT.json, OUT.report.json; with several "
                "inputs, the folder OUTDIR/ for all of them (KTX2, or DDS with --container dds)");
  c->add_option("--container", a->conv.container, "Batch: the container of every output (ktx2 or dds)")
      ->check(CLI::IsMember({"ktx2", "dds"}));
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
  c->add_option("--godot-scene", a->godot_scene,
                "A Godot project's scene (.tscn) holding the LightmapGI that baked the input: every lightmap user's "
                "mesh (.glb + its .unwrap_cache UV2, or TEXCOORD_1), transform and atlas rectangle (.lmbake); "
                "found by itself when the .tscn lies beside the EXR");
  c->add_option("--iz-scale", a->iz_scale,
                "What the iz plane stores: E (irradiance, the default), E/pi (what most engines' lightmaps hold: "
                "multiply by albedo), or a factor times E; recorded in the manifest and the planes (iz_scale)");
  c->add_flag("--allow-mismatch", a->allow_mismatch,
              "Convert even when the mesh's coverage disagrees with the lightmap (lit texels outside it, covered "
              "texels black, overlapping instances without placement)");
  add_conversion_options(c, &a->conv, true);
  c->add_flag("--keep-intermediate", a->keep_intermediate, "Also write OUT.ahd.exr, the lossless fitted planes for transcode");
  c->add_option("--sample-size", a->sample_size, "Built-in sample: width and height")->check(CLI::Range(1, 8192));
  c->add_option("--sample-order", a->sample_order, "Built-in sample: SH order 1 (L1) or 2 (L2)")->check(CLI::IsMember({1, 2}));
  c->add_option("--seed", a->seed, "Built-in sample: scene seed (0 = canonical)");
  c->callback([a, inputs]() {
    std::error_code ec;
    const bool to_folder = !a->output.empty() && (a->output.back() == '/' || fs::is_directory(a->output, ec));
    const bool folder_in = inputs->size() == 1 && fs::is_directory((*inputs)[0], ec);
    if (inputs->size() > 1 || folder_in || (to_folder && !inputs->empty())) return run_batch(*a, *inputs);
    a->input = inputs->empty() ? std::string() : (*inputs)[0];
    run_convert(*a);
  });
}

}  // namespace ahd::cli
