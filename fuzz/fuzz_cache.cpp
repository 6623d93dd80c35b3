// The cache's readers on untrusted files (cook/conversion_cache.h, issue 44): byte 0 picks the
// reader, the rest is the file. Even: an entry (ConversionCache::decode, for the key its own "key"
// line names, so the fuzzer gets past the key check); odd: a command's inputs record
// (lookup_inputs on DIR/<key>.ahdinputs; with bit 1 set the record's sha256 trailer is recomputed
// so the lines behind it are reached). Whatever is accepted must be well-formed: plain names, every
// file's bytes those its header hashed. Seeds: an entry and a record written by a cached
// conversion (scripts/fuzz.sh).
#include <unistd.h>

#include <filesystem>
#include <string>

#include "containers/sha256.h"
#include "cook/conversion_cache.h"
#include "fuzz_common.h"

namespace {

// The 64 characters after "key " in `text` (the header's key line) when they are a key (64
// lower-case hex digits: they name a file), else a fixed key.
std::string key_in(const std::string& text) {
  const size_t at = text.find("\nkey ");
  std::string k = at == std::string::npos ? std::string() : text.substr(at + 5, 64);
  const bool hex = k.size() == 64 && k.find_first_not_of("0123456789abcdef") == std::string::npos;
  return hex ? k : std::string(64, '0');
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  const std::string key = key_in(text);
  if (data[0] % 2 == 0) {
    const std::vector<uint8_t> bytes(text.begin(), text.end());
    ahd_fuzz::expect_clean([&] {
      if (const auto files = ahd::ConversionCache::decode(key, bytes))
        for (const ahd::OutputFile& f : *files)
          if (f.name.empty() || f.name.find('/') != std::string::npos) __builtin_trap();
    });
    return 0;
  }
  if (data[0] & 2) {  // the record's own hash, recomputed: the parser behind it is reached
    const size_t tail = text.rfind("sha256 ");
    if (tail != std::string::npos) text.resize(tail);
    text += "sha256 " + ahd::sha256_hex(reinterpret_cast<const uint8_t*>(text.data()), text.size()) + "\n";
  }
  static const std::string dir = "/tmp/ahd_fuzz_cache_" + std::to_string(::getpid());
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/" + key + ".ahdinputs";
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) __builtin_trap();
  std::fwrite(text.data(), 1, text.size(), f);
  std::fclose(f);
  const ahd::ConversionCache cache(dir, 0);
  ahd_fuzz::expect_clean([&] {
    if (const auto r = cache.lookup_inputs(key)) {
      if (r->options_text.empty()) __builtin_trap();
      for (const std::string& p : r->files)
        if (p.find('\n') != std::string::npos) __builtin_trap();
    }
  });
  std::remove(path.c_str());
  return 0;
}
