// The cook sequence, lifted out of `ahdpack convert` (cli/cmd_convert.cpp): the same steps in the
// same order, so the command's outputs, keys, depfiles and messages are what they were.
#include "cook/cook.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <mutex>
#include <set>

#include "api/options.h"
#include "bakers/bake_input.h"
#include "bakers/scene_export.h"
#include "cook/conversion_cache.h"
#include "cook/conversion_key.h"
#include "containers/sha256.h"
#include "cook/depfile.h"
#include "core/error.h"
#include "files/input_record.h"
#include "image/image_io.h"
#include "files/output_set.h"
#include "files/profile_file.h"
#include "image/ahd_intermediate.h"
#include "image/colour_space.h"
#include "image/sh_exr.h"
#include "pipeline/manifest.h"
#include "files/utf8_path.h"

namespace ahd {
namespace fs = std::filesystem;

namespace {

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

// The manifest of a hit, checked against the entry's planes before anything is published: every
// plane it names is in the entry once, with the size and SHA-256 it records, and the entry holds
// nothing else but the report. A backend returns what it stored, and a store can be damaged or
// written by another tool: a broken entry is a miss (`why` says what), never a broken set published.
// `sha256`: each file's SHA-256 as the backend computed it (CacheBackend::lookup_hashed), or empty
// (hashed here): each plane of a hit is hashed once.
std::optional<Manifest> checked_hit(const std::vector<OutputFile>& files, const std::vector<std::string>& sha256,
                                    const OutputPaths& out, std::string* why) {
  const OutputFile* mf = cached_manifest(files, out);
  if (!mf) {
    *why = "it holds no " + out.name + ".json or a file of another name";
    return std::nullopt;
  }
  Manifest m;
  try {
    m = manifest_from_json(std::string(mf->bytes.begin(), mf->bytes.end()), out.sibling(".json"));
  } catch (const std::exception& e) {
    *why = e.what();
    return std::nullopt;
  }
  std::set<std::string> names;
  for (const OutputFile& f : files)
    if (!names.insert(f.name).second) {
      *why = f.name + " twice";
      return std::nullopt;
    }
  std::set<std::string> planes;
  for (const ManifestPlane& p : m.planes) {
    const auto f = std::find_if(files.begin(), files.end(), [&](const OutputFile& o) { return o.name == p.file; });
    if (f == files.end() || !planes.insert(p.file).second) {
      *why = "plane " + p.file + " is missing";
      return std::nullopt;
    }
    const size_t i = size_t(f - files.begin());
    if (f->bytes.size() != p.bytes ||
        (sha256.size() == files.size() ? sha256[i] : sha256_hex(f->bytes.data(), f->bytes.size())) != p.sha256) {
      *why = "plane " + p.file + " is not the one its manifest records (size or SHA-256)";
      return std::nullopt;
    }
  }
  for (const OutputFile& f : files)
    if (f.name != mf->name && f.name != out.name + ".report.json" && !planes.count(f.name)) {
      *why = f.name + " is named by no manifest";
      return std::nullopt;
    }
  return m;
}

// The result of a hit: the stored manifest's size and planes (no error estimate).
CookResult hit_result(const Manifest& m) {
  CookResult r;
  r.outcome = CookResult::Outcome::CacheHit;
  r.width = int(m.width), r.height = int(m.height), r.planes = m.planes.size(), r.directional = m.directional;
  return r;
}

// The cache's direct lookup (cook/conversion_cache.h): what this command read last time, if every
// file it probed is as it was then, gives the conversion key without reading an image. The hit's
// files and the files read, or nullopt (then the input is read as without a cache).
struct DirectHit {
  std::vector<OutputFile> files;
  Manifest manifest;
  InputsRecord inputs;
  std::string key;
};
std::optional<DirectHit> direct_lookup(const CacheBackend& cache, const std::string& command_key,
                                       const OutputPaths& out, const std::function<void(const std::string&)>& warn) {
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
  std::vector<std::string> sha256;
  std::optional<std::vector<OutputFile>> files = cache.lookup_hashed(h.key, &sha256);
  if (!files) return std::nullopt;
  std::string why;
  std::optional<Manifest> m = checked_hit(*files, sha256, out, &why);
  if (!m) {
    if (warn) warn(cache.entry_path(h.key) + ": cache entry refused (" + why + "): converting again");
    return std::nullopt;
  }
  h.manifest = std::move(*m);
  h.files = std::move(*files);
  h.inputs = std::move(*rec);
  return h;
}

// publish_output_set swaps the process's SIGINT/SIGTERM handlers and keeps one process-wide list
// of temporaries: two sets are never published at once (a batch cooks on several threads).
std::mutex& publish_lock() {
  static std::mutex m;
  return m;
}

void publish(const OutputPaths& out, std::vector<OutputFile> files, IntermediateFile im = {}) {
  const std::lock_guard<std::mutex> l(publish_lock());
  publish_conversion(out, std::move(files), std::move(im));
}

}  // namespace

CookResult cook_conversion(const CookRequest& request, const CookHooks& hooks) {
  if (request.struct_size != sizeof(CookRequest) || request.input.struct_size != sizeof(BakeSource))
    throw Error("ahd::cook: CookRequest of another ahdpack version (struct_size " +
                std::to_string(request.struct_size) + ", this library " + std::to_string(sizeof(CookRequest)) + ")");
  const CookEvents& ev = hooks.events;
  BakeInput a;
  static_cast<BakeSource&>(a) = request.input;
  const CacheBackend* cache = request.cache.get();
  const auto print_hit = [&](const std::string& source, const std::string& key, const OutputPaths& out, size_t n) {
    if (ev.cache_hit) ev.cache_hit({source, key, cache->entry_path(key), out.sibling(".json"), n});
  };
  if (cache && request.keep_intermediate)
    throw Error("--cache stores the conversion's outputs, not --keep-intermediate's file: use one of them");
  std::string cmd_key;
  bool refused_warned = false;  // the direct lookup refused the entry the key names (said once)
  if (cache && !request.output.empty() && !request.key_only) {
    const OutputPaths out = output_paths(request.output);
    ConversionOptions given = request.options;
    given.container = out.kind;
    cmd_key = command_key(a, given, out.name, request.options.profile);
    const auto warn_once = [&](const std::string& message) {
      refused_warned = true;
      if (ev.warning) ev.warning(message);
    };
    if (std::optional<DirectHit> h = direct_lookup(*cache, cmd_key, out, warn_once)) {
      const Manifest m = h->manifest;
      const size_t n = h->files.size();
      // Refused paths (cook/depfile.cpp) fail before anything is published.
      const std::string deps = request.depfile.empty() ? "" : depfile_text(out.sibling(".json"), h->inputs.files);
      publish(out, std::move(h->files));
      if (!request.depfile.empty()) write_file_atomic(request.depfile, deps);
      print_hit(h->inputs.source, h->key, out, n);
      CookResult r = hit_result(m);
      r.key = h->key, r.source = h->inputs.source, r.manifest = out.sibling(".json");
      r.files_read = std::move(h->inputs.files);
      return r;
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
  const auto t0 = std::chrono::steady_clock::now();
  {
    const RecordInputs recording(&record);
    const ImageInfoScope headers;  // the input's header read once (image/image_io.h)
    resolve_auto_layout(&a);
    find_scene_for_input(&a);
    detection_notes = a.notes.size();  // why this path was taken: told even on failure
    std::string out_path = request.output;
    if (out_path.empty())
      out_path =
          "ahdpack-out/" + (a.input.empty() ? std::string("sample") : utf8_string(fs_path(a.input).stem())) + ".ktx2";
    out = output_paths(out_path);
    co = request.options;
    co.container = out.kind;

    // Checked before anything is read or written: one clear line, no output.
    // iz_scale 0: the input's own scale (input_iz_scale), once its layout is known; 1 until then.
    const bool own_iz_scale = co.iz_scale == 0;
    if (own_iz_scale) co.iz_scale = 1;
    ro = co.profile_json.empty() ? resolve_options(co, out.name, load_profile(co.profile))
                                 : resolve_options(co, out.name);
    check_bake_input(a);
    try {
      pages = read_bake_pages(a, co.threads, &rs, &source);
      if (own_iz_scale) {  // the input's own scale, once its layout is read (its preset already recorded)
        std::string why;
        co.iz_scale = ro.package.iz_scale = input_iz_scale(a, &why);
        if (!why.empty()) a.notes += why + "\n";
      }
    } catch (const std::exception&) {
      // What detection found says why the run took this path: told before the one error line.
      if (ev.notes && !request.key_only && detection_notes) ev.notes(a.notes.substr(0, detection_notes));
      throw;
    }
  }
  if (ev.notes && !request.key_only && !a.notes.empty()) ev.notes(a.notes);
  const double read_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  std::string key;
  if (request.key_only || cache) key = conversion_key(conversion_key_text(a, co, out.name, record));
  if (request.key_only) {
    CookResult r;
    r.outcome = CookResult::Outcome::KeyOnly;
    r.key = key, r.source = source, r.files_read = record.files;
    return r;
  }
  // What the direct lookup of the next run of this command needs (best effort, as the store).
  const auto remember_inputs = [&]() {
    if (cmd_key.empty()) return;
    try {
      cache->store_inputs(cmd_key,
                          {conversion_options_text(a, co, out.name), source, record.files, record.probes});
    } catch (const std::exception& e) {
      if (ev.warning) ev.warning(std::string(e.what()) + " (the inputs are not recorded in the cache)");
    }
  };
  // Made before anything is published: a path no depfile can carry (cook/depfile.cpp) is one error
  // line and no output.
  const std::string deps = request.depfile.empty() ? "" : depfile_text(out.sibling(".json"), record.files);
  const auto write_deps = [&]() {
    if (!request.depfile.empty()) write_file_atomic(request.depfile, deps);
  };

  if (cache) {
    std::vector<std::string> sha256;
    std::optional<std::vector<OutputFile>> hit = cache->lookup_hashed(key, &sha256);
    std::string why;
    std::optional<Manifest> checked = hit ? checked_hit(*hit, sha256, out, &why) : std::nullopt;
    if (hit && !checked && ev.warning && !refused_warned)
      ev.warning(cache->entry_path(key) + ": cache entry refused (" + why + "): converting again");
    if (checked) {  // a hit: the stored files, published exactly as a conversion's (cook/publish.h)
      const Manifest m = *checked;
      const size_t n = hit->size();
      publish(out, std::move(*hit));
      write_deps();
      remember_inputs();
      print_hit(source, key, out, n);
      CookResult r = hit_result(m);
      r.key = key, r.source = source, r.manifest = out.sibling(".json"), r.files_read = record.files;
      return r;
    }
  }

  PackageOptions pkg = ro.package;
  pkg.world_frame = !pages[0].normals.empty();
  pkg.instances = bake_instances(a);  // the placed scene's instances, when the input has one
  pkg.report_extra = {
      {"source", source},
      {"working_space", kWorkingSpace},
      {"read", {{"non_finite_texels", rs.non_finite_texels}, {"coverage_derived", rs.coverage_derived}}}};
  // The space the input was converted from; absent when it was read in the working space (reports as before).
  if (!rs.input_space.empty()) pkg.report_extra["input_space"] = rs.input_space;
  const std::vector<StageCost> read_stage = {{a.input.empty() ? "bake sample" : "read", read_seconds}};
  ConversionRun run;
  IntermediateFile intermediate;  // none: an earlier NAME.ahd.exr goes with the set it belonged to
  if (pages.size() > 1) {         // an atlas: every page converted alone, planes stacked as array layers
    if (request.keep_intermediate)
      throw Error("--keep-intermediate holds one page: not available for a multi-page atlas");
    run = run_pages(std::move(pages), ro.profile, ro.convert, pkg, read_stage);
  } else {
    std::function<void(const std::vector<FittedLevel>&)> on_fitted;
    // Kept in memory and published with the set: a conversion that fails or is cancelled after the
    // fit leaves the previous NAME.ahd.exr as it was.
    if (request.keep_intermediate)
      on_fitted = [&](const std::vector<FittedLevel>& levels) {
        intermediate.bytes = encode_intermediate(out.sibling(".ahd.exr"), levels, ro.convert.fit);
      };
    run = run_conversion(std::move(pages[0]), ro.profile, ro.convert, pkg, read_stage, on_fitted);
  }
  std::vector<OutputFile> to_store;
  if (cache) to_store = run.output.files;
  publish(out, std::move(run.output.files), std::move(intermediate));  // the summary needs the manifest, not the bytes
  write_deps();
  if (hooks.converted) hooks.converted({source, out, run, ro.convert.closed_loop, rs.non_finite_texels});
  // Bad or unsuitable data (pipeline/sh_input_check.h): said, one warning each, naming the input.
  if (hooks.events.warning)
    for (const std::string& w : run.result.warnings)
      hooks.events.warning((request.input.input.empty() ? std::string() : request.input.input + ": ") + w);
  if (cache) {
    // The outputs are published: a cache that cannot be written (read-only shared folder, full
    // disk) costs the next run a conversion, it does not fail this one.
    try {
      const CacheStats st = cache->store(key, to_store);
      if (ev.stored) ev.stored(key, st);
    } catch (const std::exception& e) {
      if (ev.warning) ev.warning(std::string(e.what()) + " (the conversion is not cached)");
    }
    remember_inputs();
  }
  CookResult r;
  r.key = key, r.source = source, r.manifest = out.sibling(".json"), r.files_read = std::move(record.files);
  r.width = int(run.output.manifest.width);
  r.height = int(run.output.manifest.height);
  r.planes = run.output.manifest.planes.size();
  r.directional = run.result.directional;
  if (run.result.final_error.texels)
    r.error_mean = run.result.final_error.relative.mean, r.error_p99 = run.result.final_error.relative.p99;
  return r;
}

}  // namespace ahd
