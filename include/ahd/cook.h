// ahdpack's cook: what `ahdpack convert IN -o OUT [--cache DIR] [--depfile F]` does, as one call —
// read the bake (<ahd/bakers.h>), key it, reuse a cached conversion or convert it
// (<ahd/convert.h>), publish the set, store it in the cache, write the depfile. Link ahdpack::cook
// (a shared library; it brings ahdpack::bakers and ahdpack::ahd). The same bytes as the command:
// planes, manifest, depfile and cache keys (the report differs only in its seconds).
//
// Pieces a build system may use alone: the conversion's cache behind CacheBackend (the directory
// cache is one implementation; a remote one is one more class), and the depfile writer.
#pragma once
#include <ahd/bakers.h>
#include <ahd/convert.h>
#include <ahd/export.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace ahd {

// ---- The cache ------------------------------------------------------------------------------

struct CacheStats {
  size_t entries = 0;
  uint64_t bytes = 0;
  size_t evicted = 0;  // entries removed by the last store
};

// What a conversion read and probed, stored under its command key beside the entries: a later run
// of the same command checks the probes and hashes the files to find the conversion's key without
// decoding an image. `options_text` is the option part of the conversion key, `source` the
// summary's description of the input.
struct InputsRecord {
  std::string options_text;
  std::string source;
  std::vector<std::string> files;
  std::vector<InputProbe> probes;
};

// Where finished conversions are kept, addressed by their key (64 lower-case hex digits, the
// SHA-256 of everything that decides the bytes: docs/asset-cook.md "The key and the cache").
// Contract of every backend:
// - lookup/lookup_inputs return nullopt for anything missing, truncated, corrupt or foreign (the
//   cook then converts and stores again), and never throw except std::bad_alloc;
// - store/store_inputs throw ahd::Error naming the entry when they cannot write (the cook warns
//   and goes on: the outputs are already published);
// - each call may come from several threads and processes at once (a batch, parallel builds);
//   a reader sees a whole entry or none.
// A new backend (a remote cache over HTTP, …) is one class implementing these five functions.
class AHD_API CacheBackend {
 public:
  virtual ~CacheBackend() = default;
  // The files stored under `key` (plain names, no folder), or nullopt.
  virtual std::optional<std::vector<OutputFile>> lookup(const std::string& key) const = 0;
  // Stores `files` under `key` (replacing an entry of that key); the backend's size afterwards.
  virtual CacheStats store(const std::string& key, const std::vector<OutputFile>& files) const = 0;
  virtual std::optional<InputsRecord> lookup_inputs(const std::string& command_key) const = 0;
  virtual void store_inputs(const std::string& command_key, const InputsRecord& record) const = 0;
  // Where `key`'s entry is (a path, a URL), for messages.
  virtual std::string entry_path(const std::string& key) const = 0;
  // lookup, and each returned file's SHA-256 (64 lower-case hex digits, (*sha256)[i] for file i)
  // as the backend computed it from the bytes it returns while checking them, so a hit is not
  // hashed twice (the cook checks the manifest against these). Never a hash read from the store.
  // The default calls lookup and leaves *sha256 empty: the cook then hashes the files itself.
  virtual std::optional<std::vector<OutputFile>> lookup_hashed(const std::string& key,
                                                               std::vector<std::string>* sha256) const {
    sha256->clear();
    return lookup(key);
  }
};

// The folder cache of `ahdpack convert --cache DIR` (one file per entry, atomic rename, shared
// between processes; least recently used entries evicted past `max_bytes`, 0 = unbounded). The
// folder is created on the first store.
AHD_API std::shared_ptr<const CacheBackend> directory_cache(const std::string& dir, uint64_t max_bytes);

// The cache `where` names: a backend's scheme ("http://…", when one is built in), else a folder
// (directory_cache). What `ahdpack convert --cache WHERE` opens.
AHD_API std::shared_ptr<const CacheBackend> open_cache(const std::string& where, uint64_t max_bytes);

// "10G", "512M", "4096": a size with an optional K, M, G or T suffix (powers of 1024). Throws
// ahd::Error naming `option` for anything else.
AHD_API uint64_t parse_byte_size(const std::string& text, const std::string& option);

// ---- Depfiles -------------------------------------------------------------------------------

// "TARGET: \\\n  DEP1 \\\n  DEP2\n" with each dependency made absolute (Ninja resolves relative
// paths against its build folder, not the tool's working directory) and escaped as both GNU Make
// and Ninja read it: space, '#' and ':' after a backslash, '$' doubled. The target is written as
// given (it must match the build rule's output as the build system names it). Throws ahd::Error
// ("<path>: cannot be written to a depfile: …") for a path no spelling carries to both: control
// characters (newline, tab), ; | * ? [ ] % = quotes & < > ` ^, a backslash before a space, '#',
// ':', '$', a backslash or the end, a leading '~', "a(b)" (cook/depfile.cpp says why each).
AHD_API std::string depfile_text(const std::string& target, const std::vector<std::string>& deps);

// depfile_text written to `path` through a temporary file and a rename. Throws ahd::Error naming
// the file.
AHD_API void write_depfile(const std::string& path, const std::string& target, const std::vector<std::string>& deps);

// ---- The cook -------------------------------------------------------------------------------

struct CookRequest {
  uint32_t struct_size = sizeof(CookRequest);  // leave as initialised (see <ahd/bakers.h> BakeSource)
  BakeSource input;
  // OUT.ktx2 or OUT.dds (the container follows the extension): writes OUT.<plane>.<hash>.<ext>,
  // OUT.json, OUT.report.json. "" = ahdpack-out/<input stem, or "sample">.ktx2.
  std::string output;
  // The conversion's options; `profile` is a profile's name (formats/profiles) or a .json file,
  // read from disk (and then part of the key); `container` is set from `output`; `iz_scale` may be
  // 0 here: the input's own scale (a plain lightmap's E/π: 1/π; else 1).
  ConversionOptions options;
  bool keep_intermediate = false;  // also OUT.ahd.exr, the lossless fitted planes (one page; not with a cache)
  std::string depfile;             // "" = none; else every file read, target OUT.json
  std::shared_ptr<const CacheBackend> cache;  // null = no cache
  bool key_only = false;                      // compute the conversion's key (result.key) and write nothing
};

// A conversion served from the cache.
struct CookCacheHit {
  std::string source;  // the input, as the run that stored it described it
  std::string key;
  std::string entry;     // CacheBackend::entry_path
  std::string manifest;  // OUT.json
  size_t files = 0;
};

// What the cook tells along the way (each optional; called on the calling thread).
struct CookEvents {
  // What detection found (layout, scene, pages), once the input is read; when reading fails, the
  // part found before the failure, before the exception leaves cook(). Not called with key_only.
  std::function<void(const std::string& text)> notes;
  std::function<void(const CookCacheHit& hit)> cache_hit;
  std::function<void(const std::string& key, const CacheStats& after)> stored;
  // A cache that cannot be written: the conversion is published all the same.
  std::function<void(const std::string& message)> warning;
};

struct CookResult {
  uint32_t struct_size = sizeof(CookResult);
  enum class Outcome { Converted, CacheHit, KeyOnly } outcome = Outcome::Converted;
  std::string key;                      // the conversion's key (with a cache or key_only; else "")
  std::string source;                   // what was read, one line
  std::string manifest;                 // OUT.json as published ("" with key_only)
  std::vector<std::string> files_read;  // the depfile's list (empty for a direct cache hit's reuse: see files)
  int width = 0, height = 0;
  size_t planes = 0;
  bool directional = true;
  double error_mean = -1, error_p99 = -1;  // relative error estimate of level 0 (−1: not measured)
};

// Cooks `request` (see the top of this file). Contract: throws ahd::Error("<file>: <cause>") for a
// bad input or option, before anything is written; ahd::Cancelled when options.cancel rises. The
// outputs are published as one set (planes, then the manifest): a failure or kill leaves the
// previous set intact. Sets are published one at a time per process (the publish holds a lock),
// so several cooks may run on different threads at once. Deterministic: same inputs and options,
// same bytes, at any thread count.
AHD_API CookResult cook(const CookRequest& request, const CookEvents& events = {});

}  // namespace ahd
