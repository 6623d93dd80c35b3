// Issue 44: a cache hit hashes each plane once. The folder cache's lookup_hashed returns the SHA-256
// it computed from each file's bytes while checking the entry (cook/conversion_cache.h), and the
// cook checks the hit's manifest against those hashes instead of hashing the planes again
// (cook/cook.cpp checked_hit). Shown without timing: a backend reporting a hash its bytes do not have
// is refused (the cook used the hash it was given), one reporting none is hashed by the cook and
// served, and both serve the conversion's bytes. Unit tests: in process (the built-in sample), no CLI.
#include <gtest/gtest.h>

#include <ahd/cook.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "containers/sha256.h"
#include "cook/conversion_cache.h"
#include "cook/cook.h"
#include "file_bytes.h"

namespace fs = std::filesystem;
using namespace ahd;

namespace {

// The folder cache, its hashes passed on as they are, dropped, or one of them replaced.
class HashedView : public CacheBackend {
 public:
  enum class Mode { Forward, NoHashes, WrongHash };
  HashedView(std::shared_ptr<const CacheBackend> inner, Mode mode) : inner_(std::move(inner)), mode_(mode) {}
  std::optional<std::vector<OutputFile>> lookup(const std::string& key) const override { return inner_->lookup(key); }
  std::optional<std::vector<OutputFile>> lookup_hashed(const std::string& key, std::vector<std::string>* sha256) const override {
    auto files = inner_->lookup_hashed(key, sha256);
    if (mode_ == Mode::NoHashes) sha256->clear();
    if (mode_ == Mode::WrongHash && files)
      for (size_t i = 0; i < files->size(); ++i)
        if ((*files)[i].name.find(".iz.") != std::string::npos) (*sha256)[i] = std::string(64, '0');
    return files;
  }
  CacheStats store(const std::string& key, const std::vector<OutputFile>& files) const override { return inner_->store(key, files); }
  std::optional<InputsRecord> lookup_inputs(const std::string& k) const override { return inner_->lookup_inputs(k); }
  void store_inputs(const std::string& k, const InputsRecord& r) const override { inner_->store_inputs(k, r); }
  std::string entry_path(const std::string& key) const override { return inner_->entry_path(key); }

 private:
  std::shared_ptr<const CacheBackend> inner_;
  Mode mode_;
};

CookRequest sample_request(const fs::path& out, std::shared_ptr<const CacheBackend> cache) {
  CookRequest r;
  r.input.sample_size = 32;  // the built-in sample: no input file
  r.output = out.string();
  r.options.profile = "uncompressed";
  r.options.threads = 1;
  r.cache = std::move(cache);
  return r;
}

std::map<std::string, std::string> folder_files(const fs::path& dir) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && e.path().filename().string().find(".report.") == std::string::npos)
      m[e.path().filename().string()] = ahd_test::read_text(e.path());
  return m;
}

}  // namespace

TEST(CacheHitHashesUnit, FolderCacheReturnsTheHashOfEachFileItRead) {
  const fs::path d = ahd_test::temp_dir("cache_hashes");
  const ConversionCache cache(d.string(), 0);
  const std::string key(64, 'a');
  const std::vector<OutputFile> files = {{"s.iz.0.ktx2", {1, 2, 3}}, {"s.json", {'{', '}'}}, {"s.empty", {}}};
  cache.store(key, files);
  std::vector<std::string> sha = {"stale"};
  const auto got = cache.lookup_hashed(key, &sha);
  ASSERT_TRUE(got);
  ASSERT_EQ(sha.size(), files.size());
  for (size_t i = 0; i < files.size(); ++i) {
    EXPECT_EQ((*got)[i].bytes, files[i].bytes);
    EXPECT_EQ(sha[i], sha256_hex(files[i].bytes.data(), files[i].bytes.size())) << files[i].name;
  }
  // A damaged entry: a miss, and no hashes left behind.
  std::vector<uint8_t> b = ahd_test::slurp(cache.entry_path(key));
  b[b.size() - 3] ^= 1;
  ahd_test::spit(cache.entry_path(key), b);
  EXPECT_FALSE(cache.lookup_hashed(key, &sha));
  EXPECT_TRUE(sha.empty());
  fs::remove_all(d);
}

TEST(CacheHitHashesUnit, CookChecksAHitAgainstTheBackendsHashes) {
  const fs::path d = ahd_test::temp_dir("cache_hit_hashes");
  const std::shared_ptr<const CacheBackend> folder = std::make_shared<ConversionCache>((d / "cache").string(), 0);
  CookHooks h;
  const CookResult miss = cook_conversion(sample_request(d / "miss" / "s.ktx2", folder), h);
  ASSERT_EQ(miss.outcome, CookResult::Outcome::Converted);
  const auto want = folder_files(d / "miss");

  // The backend's hashes are the planes': a hit with the conversion's bytes.
  const CookResult hit =
      cook_conversion(sample_request(d / "hit" / "s.ktx2", std::make_shared<HashedView>(folder, HashedView::Mode::Forward)), h);
  EXPECT_EQ(hit.outcome, CookResult::Outcome::CacheHit);
  EXPECT_EQ(folder_files(d / "hit"), want);

  // No hashes: the cook hashes the planes itself and serves the same bytes.
  const CookResult own =
      cook_conversion(sample_request(d / "own" / "s.ktx2", std::make_shared<HashedView>(folder, HashedView::Mode::NoHashes)), h);
  EXPECT_EQ(own.outcome, CookResult::Outcome::CacheHit);
  EXPECT_EQ(folder_files(d / "own"), want);

  // The iz plane's hash is not its manifest's: refused (so the given hash is the one checked; the
  // bytes themselves are right) and converted again, one warning.
  std::vector<std::string> warnings;
  CookHooks hw;
  hw.events.warning = [&](const std::string& m) { warnings.push_back(m); };
  const CookResult wrong =
      cook_conversion(sample_request(d / "wrong" / "s.ktx2", std::make_shared<HashedView>(folder, HashedView::Mode::WrongHash)), hw);
  EXPECT_EQ(wrong.outcome, CookResult::Outcome::Converted);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("cache entry refused (plane s.iz."), std::string::npos) << warnings[0];
  EXPECT_EQ(folder_files(d / "wrong"), want);
  fs::remove_all(d);
}
