// ahdpack convert [IN.exr] [-o OUT.ktx2|OUT.dds]: SH lightmap → AHD planes + manifest + report.
#include <ahd/sample.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <set>

#include "cli/batch_schedule.h"
#include "cli/commands.h"
#include "cli/conversion_args.h"
#include "bakers/bake_input.h"
#include "bakers/bake_jobs.h"
#include "cli/output.h"
#include "cli/progress.h"
#include "core/error.h"
#include "core/parallel.h"
#include "bakers/baker_layout.h"
#include "cook/cook.h"
#include "image/image_io.h"
#include "bakers/layout_detect.h"
#include "files/utf8_path.h"

namespace ahd::cli {
namespace fs = std::filesystem;

namespace {

struct ConvertArgs : BakeInput {
  std::string output;
  std::string iz_scale;  // --iz-scale: stored I_z = E, E/pi, or a factor times E; "" = the input's own scale
  bool keep_intermediate = false;
  std::string depfile;        // --depfile: the Make/Ninja depfile of every file read
  std::string cache;          // --cache: the folder of finished conversions (cook/conversion_cache.h)
  std::string cache_max_size = "10G";
  std::string jobs;           // --jobs: a batch job file (bakers/bake_jobs.h)
  bool print_key = false;     // --print-key: print the key, convert nothing
  ConversionArgs conv;
};

// --iz-scale: "E" (1), "E/pi" (1/π) or a positive factor; not given: 0, the input's scale (the cook decides).
double iz_scale_factor(const std::string& s) {
  if (s.empty()) return 0;
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

// How a batch runs one conversion (run_convert's default: the terminal's progress).
struct BatchJob {
  std::function<void(const char* stage, double fraction)> progress;  // the batch's line, or none
};

// The cook (cook/cook.h) with this command's options, its terminal output as it goes.
BatchRow run_convert(ConvertArgs a, const BatchJob* job = nullptr) {
  CookRequest r;
  r.input = a;
  r.output = a.output;
  r.options = conversion_options(a.conv);
  if (job) r.options.cancel = interrupt_flag(), r.options.progress = job->progress;  // the batch installed the handler
  else attach_terminal_progress(&r.options, a.conv.quiet);
  r.options.iz_scale = iz_scale_factor(a.iz_scale);
  r.keep_intermediate = a.keep_intermediate;
  r.depfile = a.depfile;
  r.key_only = a.print_key;
  if (!a.cache.empty()) r.cache = open_cache(a.cache, parse_byte_size(a.cache_max_size, "--cache-max-size"));
  CookHooks h;
  h.events.warning = [](const std::string& m) {
    std::fflush(stdout);  // after the summary, when both go to one terminal
    std::fprintf(stderr, "ahdpack: warning: %s\n", m.c_str());
  };
  if (!a.conv.quiet) {
    h.events.notes = [](const std::string& text) { std::fputs(text.c_str(), stdout), std::fflush(stdout); };
    h.events.cache_hit = [](const CookCacheHit& hit) {
      std::printf("ahdpack: %s\n", hit.source.c_str());
      std::printf("cache hit %s (%s): %zu files -> %s\n", hit.key.c_str(), hit.entry.c_str(), hit.files,
                  hit.manifest.c_str());
    };
    h.events.stored = [](const std::string& key, const CacheStats& st) {
      if (st.entries == 0) return (void)std::printf("cache: stored %s\n", key.c_str());  // a server's size is its own
      std::printf("cache: stored %s (%zu entries, %.1f MiB%s)\n", key.c_str(), st.entries, double(st.bytes) / 1048576.0,
                  st.evicted ? (", " + std::to_string(st.evicted) + " least recently used evicted").c_str() : "");
    };
    h.converted = [](const CookConverted& c) {
      print_conversion(c.source, c.out, c.run, c.closed_loop, c.non_finite_texels);
    };
  }
  const CookResult res = cook_conversion(r, h);
  if (res.outcome == CookResult::Outcome::KeyOnly) {
    std::printf("%s\n", res.key.c_str());
    return {};
  }
  BatchRow row;
  row.width = res.width, row.height = res.height, row.planes = res.planes, row.directional = res.directional;
  row.rel_mean = res.error_mean, row.rel_p99 = res.error_p99;
  return row;
}

// The files a batch converts: each input, a folder standing for its *.exr files (sorted; not
// recursive). Globs are the shell's.
std::vector<std::string> batch_files(const std::vector<std::string>& inputs) {
  std::vector<std::string> files;
  for (const std::string& in : inputs) {
    std::error_code ec;
    if (!fs::is_directory(fs_path(in), ec)) {
      files.push_back(in);
      continue;
    }
    std::vector<std::string> found;
    for (const auto& e : fs::directory_iterator(fs_path(in), ec))
      if (e.is_regular_file() && e.path().extension() == ".exr") {
        // A baker's other files beside its lightmaps (bakers/unity/lightmap_page.h): skipped saying so.
        if (const std::string why = not_a_lightmap_reason(utf8_string(e.path())); !why.empty())
          std::printf("ahdpack: %s skipped: %s\n", utf8_string(e.path()).c_str(), why.c_str());
        else
          found.push_back(utf8_string(e.path()));
      }
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
void run_batch(const ConvertArgs& a, const std::vector<std::string>& inputs, const std::vector<BakeJob>* jobs = nullptr) {
  std::vector<std::string> files;
  if (jobs)
    for (const BakeJob& j : *jobs) files.push_back(j.input.input);
  else
    files = batch_files(inputs);
  const auto out_name = [&](size_t i) { return jobs ? (*jobs)[i].output : utf8_string(fs_path(files[i]).stem()); };
  const fs::path dir = a.output.empty() ? fs::path("ahdpack-out") : fs_path(a.output);
  {
    // `-o out.ktx2` with several inputs is a mistake for `-o OUTDIR/`, not a folder to create.
    std::error_code ec;
    std::string ext = utf8_string(dir.extension());
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
    done[i].same_name = !stems.insert(out_name(i)).second;
    texels[i] = header_texels(files[i]);
  }
  const BatchPlan plan = plan_batch(texels, resolve_threads(a.conv.options.threads));
  install_interrupt_handler();
  BatchProgress progress(files.size(), a.conv.quiet);
  const auto t_batch = std::chrono::steady_clock::now();
  const auto convert_one = [&](size_t i, int threads) {
    if (interrupt_flag()->load()) throw Cancelled();  // Ctrl-C: start no further file
    Done& d = done[i];
    const auto t0 = std::chrono::steady_clock::now();
    try {
      if (d.same_name) throw file_error(d.file, "another input has the same name: its outputs would collide");
      ConvertArgs one = a;
      if (jobs) static_cast<BakeInput&>(one) = (*jobs)[i].input;  // the job's input options over the command's
      one.input = d.file;
      one.output = utf8_string(dir / fs_path(out_name(i) + ext));
      one.conv.quiet = true;
      one.conv.options.threads = threads;
      BatchJob job;
      if (plan.jobs == 1 || threads > 1) job.progress = progress.stage_of(d.file);  // alone: its stages
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
                "What the iz plane stores: E (irradiance), E/pi (what most engines' lightmaps hold: multiply by albedo), "
                "or a factor times E; recorded in the manifest and the planes (iz_scale). Default: the input's own "
                "scale, E/pi for a plain lightmap, E for SH");
  add_conversion_options(c, &a->conv, true);
  c->add_option("--jobs", a->jobs,
                "A batch job file: one conversion per lightmap with its own input options (JSON {\"jobs\": [{\"input\", "
                "\"mesh\", \"node\", …, \"output\"}]}, paths relative to it; see docs/bakers.md), "
                "every output into the folder -o names");
  c->add_option("--depfile", a->depfile,
                "Also write OUT.d, a Make/Ninja depfile naming every file the conversion read (target: the manifest)");
  c->add_option("--cache", a->cache,
                "Folder of finished conversions, shared between runs and processes, or http://host:port/prefix/ "
                "(a Bazel HTTP remote cache): reuse the outputs stored under the conversion's key (--print-key), or "
                "store them");
  c->add_option("--cache-max-size", a->cache_max_size,
                "Bound of a --cache folder (bytes, or with a K/M/G/T suffix; 0 = none): least recently used entries "
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
    const bool to_folder = !a->output.empty() && (a->output.back() == '/' || fs::is_directory(fs_path(a->output), ec));
    const bool folder_in = inputs->size() == 1 && fs::is_directory(fs_path((*inputs)[0]), ec);
    if (!a->jobs.empty()) {
      if (!inputs->empty()) throw Error("--jobs names every input: give no other input");
      if (!a->depfile.empty() || a->print_key)
        throw Error(std::string(a->print_key ? "--print-key" : "--depfile") + " describes one conversion: not with --jobs");
      const std::vector<BakeJob> jobs = read_bake_jobs(a->jobs, *a);
      return run_batch(*a, {}, &jobs);
    }
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
