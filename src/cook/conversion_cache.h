// A folder of finished conversions, addressed by their key (cook/conversion_key.h): what `convert
// --cache DIR` reuses instead of converting again. Safe for several processes (and machines, on a
// shared file system with atomic rename) using one folder at once.
//
// An entry is ONE file, DIR/<key>.ahdcache: a text header (format line, the key, one line per
// output file: size, SHA-256, name) and then the files' bytes, in order. It is written under a
// temporary name in DIR and renamed into place, so a reader sees a whole entry or none; two writers
// of one key both rename a complete entry (last one wins; their planes and manifest are the same
// bytes, deterministic conversion). A lookup checks everything — format, key, names, that the sizes
// add up to the file's length, every file's SHA-256 — and treats any mismatch (a truncated or
// corrupt entry, another tool's file) as a miss, which then replaces it.
//
// A conversion's inputs are only known by reading them, which for a large EXR costs a good part of
// a conversion; so DIR also keeps, per command (the arguments as given, the working directory),
// what that command read and which files it found present or absent (<command_key>.ahdinputs).
// A later run of the same command first checks every probe (same file types), then hashes the
// listed files: the conversion key a full read would compute, without decoding an image. Any
// difference — a probe changed, a file gone — falls back to reading.
//
// Bounded: after each store, when the *.ahdcache and *.ahdinputs files of DIR total more than max_bytes, the least
// recently used (oldest modification time; a hit refreshes it) are removed until they fit — never
// the entry just stored. Temporaries older than an hour (writers that died) are removed too.
#pragma once
#include <ahd/convert.h>
#include <ahd/cook.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "files/input_record.h"

namespace ahd {

// InputsRecord, CacheStats and the backend interface: <ahd/cook.h>.

class ConversionCache : public CacheBackend {
 public:
  // `max_bytes` = 0: unbounded. The folder is created on the first store.
  ConversionCache(std::string dir, uint64_t max_bytes);

  // The files stored under `key` (64 hex digits), or nullopt for a missing, truncated or corrupt
  // entry. Safe on untrusted entries (every length bounded, every byte hashed). Never throws except
  // std::bad_alloc; refreshes the entry's modification time (ignored on a read-only folder).
  std::optional<std::vector<OutputFile>> lookup(const std::string& key) const override;
  // lookup with each file's SHA-256 as computed from its bytes here (the hash the entry's header
  // was checked against): a hit's planes are hashed once.
  std::optional<std::vector<OutputFile>> lookup_hashed(const std::string& key,
                                                       std::vector<std::string>* sha256) const override;

  // Stores `files` under `key` (temporary + rename), then evicts. File names must be plain names
  // (no folder). Throws ahd::Error naming the entry when it cannot be written; eviction never throws.
  CacheStats store(const std::string& key, const std::vector<OutputFile>& files) const override;

  std::string entry_path(const std::string& key) const override;

  // The inputs record stored under `command_key` (DIR/<command_key>.ahdinputs), or nullopt when
  // missing or malformed (its own SHA-256 is checked). Never throws except std::bad_alloc.
  std::optional<InputsRecord> lookup_inputs(const std::string& command_key) const override;
  // Stores it (temporary + rename). Throws ahd::Error when it cannot be written; a record holding
  // a path with a line break is not stored.
  void store_inputs(const std::string& command_key, const InputsRecord& record) const override;

  // The serialised entry (exposed for tests) and its reader (nullopt unless well-formed for `key`).
  static std::vector<uint8_t> encode(const std::string& key, const std::vector<OutputFile>& files);
  static std::optional<std::vector<OutputFile>> decode(const std::string& key, const std::vector<uint8_t>& bytes);
  // The same for an inputs record (the text of DIR/<command_key>.ahdinputs, its SHA-256 last):
  // nullopt from encode_inputs for a record that is not stored (a path with a line break), from
  // decode_inputs unless well-formed for `command_key`. Exposed for the HTTP backend (cook/http_cache.cpp).
  static std::optional<std::string> encode_inputs(const std::string& command_key, const InputsRecord& record);
  static std::optional<InputsRecord> decode_inputs(const std::string& command_key, const std::vector<uint8_t>& bytes);

 private:
  std::string dir_;
  uint64_t max_bytes_;
};

// parse_byte_size: <ahd/cook.h>.

}  // namespace ahd
