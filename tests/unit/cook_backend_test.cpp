// The cook behind its cache interface (<ahd/cook.h> CacheBackend, cook/cook.h): a backend that is not
// the folder cache — here one in memory, the shape a remote cache takes — is filled by a conversion,
// serves the next one (direct lookup by the command, then by the key) with the conversion's bytes,
// and a backend that cannot store costs a warning, not the conversion.
#include <gtest/gtest.h>

#include <ahd/cook.h>

#include <filesystem>
#include <map>
#include <mutex>

#include "cook/cook.h"
#include "file_bytes.h"
#include "cli_runner.h"

namespace fs = std::filesystem;
using namespace ahd;

namespace {

class MemoryCache : public CacheBackend {
 public:
  std::optional<std::vector<OutputFile>> lookup(const std::string& key) const override {
    const std::lock_guard<std::mutex> l(m_);
    ++lookups;
    auto it = entries_.find(key);
    if (it == entries_.end()) return std::nullopt;
    return it->second;
  }
  CacheStats store(const std::string& key, const std::vector<OutputFile>& files) const override {
    const std::lock_guard<std::mutex> l(m_);
    if (read_only) throw Error("memory://" + key + ": read-only");
    entries_[key] = files;
    CacheStats s;
    s.entries = entries_.size();
    return s;
  }
  std::optional<InputsRecord> lookup_inputs(const std::string& command_key) const override {
    const std::lock_guard<std::mutex> l(m_);
    auto it = inputs_.find(command_key);
    if (it == inputs_.end()) return std::nullopt;
    return it->second;
  }
  void store_inputs(const std::string& command_key, const InputsRecord& record) const override {
    const std::lock_guard<std::mutex> l(m_);
    if (read_only) throw Error("memory://" + command_key + ": read-only");
    inputs_[command_key] = record;
  }
  std::string entry_path(const std::string& key) const override { return "memory://" + key; }

  bool read_only = false;
  mutable int lookups = 0;
  size_t size() const { return entries_.size(); }
  size_t input_records() const { return inputs_.size(); }

 private:
  mutable std::mutex m_;
  mutable std::map<std::string, std::vector<OutputFile>> entries_;
  mutable std::map<std::string, InputsRecord> inputs_;
};

std::map<std::string, std::string> folder_files(const fs::path& dir) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file()) m[e.path().filename().string()] = ahd_test::read_text(e.path());
  return m;
}

CookRequest sample_request(const fs::path& out, std::shared_ptr<const CacheBackend> cache) {
  CookRequest r;
  r.input.sample_size = 32;  // the built-in sample: no input file
  r.output = out.string();
  r.options.profile = "pc-bc";
  r.options.threads = 1;
  r.cache = std::move(cache);
  return r;
}

}  // namespace

TEST(CookBackend, AnotherBackendIsFilledAndServesTheConversionsBytes) {
  const fs::path d = ahd_test::temp_dir("cook_backend");
  auto cache = std::make_shared<MemoryCache>();
  std::vector<std::string> hits, stored;
  CookHooks h;
  h.events.cache_hit = [&](const CookCacheHit& hit) { hits.push_back(hit.entry); };
  h.events.stored = [&](const std::string& key, const CacheStats&) { stored.push_back(key); };

  const CookResult miss = cook_conversion(sample_request(d / "miss" / "s.ktx2", cache), h);
  EXPECT_EQ(miss.outcome, CookResult::Outcome::Converted);
  ASSERT_EQ(miss.key.size(), 64u);
  ASSERT_EQ(stored, std::vector<std::string>{miss.key});
  EXPECT_EQ(cache->size(), 1u);
  EXPECT_EQ(cache->input_records(), 1u);  // the command's record for the next direct lookup
  EXPECT_EQ(miss.width, 32);

  // The same command: served by the direct lookup, the files the conversion wrote.
  const CookResult hit = cook_conversion(sample_request(d / "miss" / "s.ktx2", cache), h);
  EXPECT_EQ(hit.outcome, CookResult::Outcome::CacheHit);
  EXPECT_EQ(hit.key, miss.key);
  ASSERT_EQ(hits, std::vector<std::string>{"memory://" + miss.key});
  EXPECT_EQ(hit.width, 32);
  EXPECT_EQ(hit.planes, miss.planes);

  // Another output folder (another command, the same key): read, then served by the key.
  const CookResult hit2 = cook_conversion(sample_request(d / "hit" / "s.ktx2", cache), h);
  EXPECT_EQ(hit2.outcome, CookResult::Outcome::CacheHit);
  EXPECT_EQ(cache->size(), 1u);
  const auto a = folder_files(d / "miss"), b = folder_files(d / "hit");
  ASSERT_EQ(a.size(), 5u);  // 3 planes, manifest, report
  for (const auto& [name, bytes] : a) {
    ASSERT_TRUE(b.count(name)) << name;
    EXPECT_EQ(b.at(name), bytes) << name;  // the report too: the stored one
  }
  fs::remove_all(d);
}

TEST(CookBackend, ABackendThatCannotStoreWarnsAndTheConversionIsPublished) {
  const fs::path d = ahd_test::temp_dir("cook_backend_ro");
  auto cache = std::make_shared<MemoryCache>();
  cache->read_only = true;
  std::vector<std::string> warnings;
  CookHooks h;
  h.events.warning = [&](const std::string& m) { warnings.push_back(m); };
  const CookResult r = cook_conversion(sample_request(d / "s.ktx2", cache), h);
  EXPECT_EQ(r.outcome, CookResult::Outcome::Converted);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_EQ(warnings[0], "memory://" + r.key + ": read-only (the conversion is not cached)");
  EXPECT_NE(warnings[1].find("(the inputs are not recorded in the cache)"), std::string::npos) << warnings[1];
  EXPECT_TRUE(fs::exists(d / "s.json"));
  EXPECT_GT(cache->lookups, 0);
  fs::remove_all(d);
}

TEST(CookBackend, KeyOnlyWritesNothingAndGivesTheKey) {
  const fs::path d = ahd_test::temp_dir("cook_backend_key");
  CookRequest r = sample_request(d / "s.ktx2", nullptr);
  r.key_only = true;
  const CookResult k = cook_conversion(r, {});
  EXPECT_EQ(k.outcome, CookResult::Outcome::KeyOnly);
  EXPECT_EQ(k.key.size(), 64u);
  EXPECT_FALSE(fs::exists(d / "s.json"));
  // The key is the cache's: a cook with a cache stores under it.
  auto cache = std::make_shared<MemoryCache>();
  r.key_only = false;
  r.cache = cache;
  EXPECT_EQ(cook_conversion(r, {}).key, k.key);
  fs::remove_all(d);
}
