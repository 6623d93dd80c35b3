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
#include "bakers/bake_input.h"
#include "cook/conversion_key.h"
#include "cli/output.h"
#include "cli/progress.h"
#include "core/error.h"
#include "core/parallel.h"
#include "image/ahd_intermediate.h"
#include "bakers/baker_layout.h"
#include "image/colour_space.h"
#include "cook/conversion_cache.h"
#include "cook/depfile.h"
#include "files/input_record.h"
#include "image/image_io.h"
#include "bakers/layout_detect.h"
#include "bakers/layout_pages.h"
#include "scene/mesh_io.h"
#include "scene/placement_io.h"
#include "files/profile_file.h"
#include "image/sh_exr.h"
#include "pipeline/manifest.h"
#include "pipeline/run.h"
#include "sh/sh.h"

namespace ahd::cli {
namespace fs = std::filesystem;

namespace {

struct ConvertArgs : BakeInput {
  std::string output;
  std::string iz_scale = "E";  // --iz-scale: stored I_z = E, E/pi, or a factor times E (a conversion option)
  bool keep_intermediate = false;
  std::string depfile;        // --depfile: the Make/Ninja depfile of every file read
  std::string cache;          // --cache: the folder of finished conversions (cook/conversion_cache.h)
  std::string cache_max_size = "10G";
  bool print_key = false;     // --print-key: print the key, convert nothing
  ConversionArgs conv;
};

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

// A cache entry's files are usable as this conversion's outputs when each is named for `out` and
// one of them is the manifest (an entry is only found by the key, which covers the name: this
// guards against a hand-edited or foreign folder, never writing outside out.dir).
const OutputFile* cached_manifest(const std::vector<OutputFile>& files, const OutputPaths& out) {
  const OutputFile* manifest = nullptr;
  for (const OutputFile& f : files) {
    if (f.name.rfind(out.name + ".", 0) != 0) return nullptr;
    if (f.name == out.name + ".json") manifest = &f;
  }
  return manifest;
}

BatchRow row_of(const Manifest& m) {
  BatchRow row;
  row.width = int(m.width), row.height = int(m.height), row.planes = m.planes.size(), row.directional = m.directional;
  return row;
}

// --cache's direct lookup (cook/conversion_cache.h): what this command read last time, if every file
// it probed is as it was then, gives the conversion key without reading an image. The hit's files
// and the files read, or nullopt (then the input is read as without a cache).
struct DirectHit {
  std::vector<OutputFile> files;
  InputsRecord inputs;
  std::string key;
};
std::optional<DirectHit> direct_lookup(const ConversionCache& cache, const std::string& command_key, const OutputPaths& out) {
  std::optional<InputsRecord> rec = cache.lookup_inputs(command_key);
  if (!rec) return std::nullopt;
  for (const InputProbe& p : rec->probes)
    if (probe_type(p.path) != p.type) return std::nullopt;
  DirectHit h;
  try {
    h.key = conversion_key(rec->options_text + input_files_text(rec->files));
  } catch (const Error&) {
    return std::nullopt;  // a file it read is gone: read again (and fail there, naming it)
  }
  std::optional<std::vector<OutputFile>> files = cache.lookup(h.key);
  if (!files || !cached_manifest(*files, out)) return std::nullopt;
  h.files = std::move(*files);
  h.inputs = std::move(*rec);
  return h;
}

BatchRow run_convert(ConvertArgs a, const BatchJob* job = nullptr) {
  const auto publish = [&](const OutputPaths& out, std::vector<OutputFile> files, IntermediateFile im = {}) {
    std::unique_lock<std::mutex> l;
    if (job && job->publish_lock) l = std::unique_lock<std::mutex>(*job->publish_lock);
    publish_conversion(out, std::move(files), std::move(im));
  };
  const auto print_hit = [&](const std::string& source, const std::string& key, const ConversionCache& cache,
                             const OutputPaths& out, size_t n) {
    if (a.conv.quiet) return;
    std::printf("ahdpack: %s\n", source.c_str());
    std::printf("cache hit %s (%s): %zu files -> %s\n", key.c_str(), cache.entry_path(key).c_str(), n,
                out.sibling(".json").c_str());
  };
  if (!a.cache.empty() && a.keep_intermediate)
    throw Error("--cache stores the conversion's outputs, not --keep-intermediate's file: use one of them");
  const ConversionCache cache(a.cache, a.cache.empty() ? 0 : parse_byte_size(a.cache_max_size, "--cache-max-size"));
  std::string cmd_key;
  if (!a.cache.empty() && !a.output.empty() && !a.print_key) {
    const OutputPaths out = output_paths(a.output);
    ConversionOptions given = conversion_options(a.conv);
    given.container = out.kind;
    cmd_key = command_key(a, given, out.name, a.conv.options.profile, iz_scale_factor(a.iz_scale));
    if (std::optional<DirectHit> h = direct_lookup(cache, cmd_key, out)) {
      const Manifest m = manifest_from_json(std::string(cached_manifest(h->files, out)->bytes.begin(),
                                                        cached_manifest(h->files, out)->bytes.end()),
                                            out.sibling(".json"));
      const size_t n = h->files.size();
      publish(out, std::move(h->files));
      if (!a.depfile.empty()) write_depfile(a.depfile, out.sibling(".json"), h->inputs.files);
      print_hit(h->inputs.source, h->key, cache, out, n);
      return row_of(m);
    }
  }

  // Everything read from here to the end of the block is noted in `record` (files/input_record.h):
  // the one list the depfile names and the key hashes. Nothing read after it is an input.
  InputRecord record;
  OutputPaths out;
  ConversionOptions co;
  ResolvedOptions ro;
  ReadStats rs;
  std::string source;
  std::vector<ShImage> pages;
  size_t detection_notes = 0;
  double iz_scale = 1.0;
  const auto t0 = std::chrono::steady_clock::now();
  {
    const RecordInputs recording(&record);
    resolve_auto_layout(&a);
    find_scene_for_input(&a);
    detection_notes = a.notes.size();  // why this path was taken: printed even on failure
    std::string out_path = a.output;
    if (out_path.empty())
      out_path = "ahdpack-out/" + (a.input.empty() ? std::string("sample") : fs::path(a.input).stem().string()) + ".ktx2";
    out = output_paths(out_path);
    co = conversion_options(a.conv);
    co.container = out.kind;
    if (job) co.cancel = interrupt_flag(), co.progress = job->progress;  // the batch installed the handler
    else attach_terminal_progress(&co, a.conv.quiet);

    // Checked before anything is read or written: one clear line, no output.
    ro = resolve_options(co, out.name, load_profile(a.conv.options.profile));
    iz_scale = iz_scale_factor(a.iz_scale);
    check_bake_input(a);
    try {
      pages = read_bake_pages(a, a.conv.options.threads, &rs, &source);
    } catch (const std::exception&) {
      // What detection found says why the run took this path: printed before the one error line.
      if (!a.conv.quiet && !a.print_key) std::fputs(a.notes.substr(0, detection_notes).c_str(), stdout), std::fflush(stdout);
      throw;
    }
  }
  if (!a.conv.quiet && !a.print_key) std::fputs(a.notes.c_str(), stdout);
  const double read_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  std::string key;
  if (a.print_key || !a.cache.empty()) key = conversion_key(conversion_key_text(a, co, out.name, record, iz_scale));
  if (a.print_key) {
    std::printf("%s\n", key.c_str());
    return {};
  }
  // What the direct lookup of the next run of this command needs (best effort, as the store).
  const auto remember_inputs = [&]() {
    if (cmd_key.empty()) return;
    try {
      cache.store_inputs(cmd_key, {conversion_options_text(a, co, out.name, iz_scale), source, record.files, record.probes});
    } catch (const std::exception& e) {
      std::fprintf(stderr, "ahdpack: warning: %s (the inputs are not recorded in the cache)\n", e.what());
    }
  };
  const auto write_deps = [&]() {
    if (!a.depfile.empty()) write_depfile(a.depfile, out.sibling(".json"), record.files);
  };

  if (!a.cache.empty()) {
    std::optional<std::vector<OutputFile>> hit = cache.lookup(key);
    const OutputFile* mf = hit ? cached_manifest(*hit, out) : nullptr;
    if (mf) {  // a hit: the stored files, published exactly as a conversion's (cli/output.h)
      const Manifest m = manifest_from_json(std::string(mf->bytes.begin(), mf->bytes.end()), out.sibling(".json"));
      const size_t n = hit->size();
      publish(out, std::move(*hit));
      write_deps();
      remember_inputs();
      print_hit(source, key, cache, out, n);
      return row_of(m);
    }
  }

  PackageOptions pkg = ro.package;
  pkg.world_frame = !pages[0].normals.empty();
  pkg.iz_scale = iz_scale;
  if (pkg.iz_scale != 1.0)  // the SH is linear in the light: scaling it scales I_z and keeps d and the ratio
    for (ShImage& p : pages)
      for (float& v : p.data) v = float(double(v) * pkg.iz_scale);
  pkg.report_extra = {{"source", source},
                      {"working_space", kWorkingSpace},
                      {"read", {{"non_finite_texels", rs.non_finite_texels}, {"coverage_derived", rs.coverage_derived}}}};
  // The space the input was converted from; absent when it was read in the working space (reports as before).
  if (!rs.input_space.empty()) pkg.report_extra["input_space"] = rs.input_space;
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
  std::vector<OutputFile> to_store;
  if (!a.cache.empty()) to_store = run.output.files;
  publish(out, std::move(run.output.files), std::move(intermediate));  // the summary needs the manifest, not the bytes
  write_deps();
  if (!a.conv.quiet) print_conversion(source, out, run, ro.convert.closed_loop, rs.non_finite_texels);
  if (!a.cache.empty()) {
    // The outputs are published: a cache that cannot be written (read-only shared folder, full
    // disk) costs the next run a conversion, it does not fail this one.
    try {
      const CacheStats st = cache.store(key, to_store);
      if (!a.conv.quiet)
        std::printf("cache: stored %s (%zu entries, %.1f MiB%s)\n", key.c_str(), st.entries, double(st.bytes) / 1048576.0,
                    st.evicted ? (", " + std::to_string(st.evicted) + " least recently used evicted").c_str() : "");
    } catch (const std::exception& e) {
      std::fprintf(stderr, "ahdpack: warning: %s (the conversion is not cached)\n", e.what());
    }
    remember_inputs();
  }
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
  add_input_options(c, a.get());
  c->add_option("--iz-scale", a->iz_scale,
                "What the iz plane stores: E (irradiance, the default), E/pi (what most engines' lightmaps hold: "
                "multiply by albedo), or a factor times E; recorded in the manifest and the planes (iz_scale)");
  add_conversion_options(c, &a->conv, true);
  c->add_option("--depfile", a->depfile,
                "Also write OUT.d, a Make/Ninja depfile naming every file the conversion read (target: the manifest)");
  c->add_option("--cache", a->cache,
                "Folder of finished conversions, shared between runs and processes: reuse the outputs stored under "
                "the conversion's key (--print-key), or store them");
  c->add_option("--cache-max-size", a->cache_max_size,
                "Bound of the --cache folder (bytes, or with a K/M/G/T suffix; 0 = none): least recently used entries "
                "are evicted past it (default 10G)");
  c->add_flag("--print-key", a->print_key,
              "Print the conversion's key (its inputs' bytes, the effective options, the tool version) and convert "
              "nothing");
  c->add_flag("--keep-intermediate", a->keep_intermediate, "Also write OUT.ahd.exr, the lossless fitted planes for transcode");
  c->add_option("--sample-size", a->sample_size, "Built-in sample: width and height")->check(CLI::Range(1, 8192));
  c->add_option("--sample-order", a->sample_order, "Built-in sample: SH order 1 (L1) or 2 (L2)")->check(CLI::IsMember({1, 2}));
  c->add_option("--seed", a->seed, "Built-in sample: scene seed (0 = canonical)");
  c->callback([a, inputs]() {
    std::error_code ec;
    const bool to_folder = !a->output.empty() && (a->output.back() == '/' || fs::is_directory(a->output, ec));
    const bool folder_in = inputs->size() == 1 && fs::is_directory((*inputs)[0], ec);
    if (inputs->size() > 1 || folder_in || (to_folder && !inputs->empty())) {
      if (!a->depfile.empty() || a->print_key)
        throw Error(std::string(a->print_key ? "--print-key" : "--depfile") + " describes one conversion: not with several inputs");
      return run_batch(*a, *inputs);
    }
    a->input = inputs->empty() ? std::string() : (*inputs)[0];
    run_convert(*a);
  });
}

}  // namespace ahd::cli
