// The HTTP cache backend (cook/http_cache.cpp) against a real server: Debian's nginx with WebDAV
// PUT, as Bazel's documentation suggests for its HTTP remote cache, started by each test on
// 127.0.0.1 from a configuration written into a temporary folder. A miss then a hit with the same
// bytes, two conversions filling one key at once, a server killed between the conversion and the
// store or during the store (one warning, the conversion published), a corrupt or mixed-up entry on
// the server (a miss or a refusal, never a wrong hit), a server that does not answer (a timeout).
// Integration tests (tests/labels.cmake): they start processes and use sockets.
#include <gtest/gtest.h>

#include <ahd/cook.h>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <sstream>
#include <thread>

#include "cli_runner.h"
#include "containers/sha256.h"
#include "cook/conversion_cache.h"
#include "cook/cook.h"
#include "file_bytes.h"

extern char** environ;

namespace fs = std::filesystem;
using namespace ahd;

namespace {

std::string find_nginx() {
  for (const char* p : {"/usr/sbin/nginx", "/usr/bin/nginx", "/usr/local/sbin/nginx"})
    if (fs::exists(p)) return p;
  return "";
}

// A port nothing listens on now (the kernel's pick), for a server started next.
int free_port() {
  const int s = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(s, reinterpret_cast<sockaddr*>(&a), sizeof(a));
  socklen_t len = sizeof(a);
  getsockname(s, reinterpret_cast<sockaddr*>(&a), &len);
  close(s);
  return ntohs(a.sin_port);
}

bool accepts(int port) {
  const int s = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = htons(uint16_t(port));
  const bool ok = connect(s, reinterpret_cast<sockaddr*>(&a), sizeof(a)) == 0;
  close(s);
  return ok;
}

// nginx in the foreground, one process (master_process off), serving DIR/root with WebDAV PUT.
class Nginx {
 public:
  explicit Nginx(const fs::path& dir) : dir_(dir) {
    fs::create_directories(dir_ / "root");
    fs::create_directories(dir_ / "body");
  }
  ~Nginx() { kill_now(); }

  // Starts it on a free port; "" when it runs, else why not (its error log).
  std::string start() {
    for (int attempt = 0; attempt < 3; ++attempt) {
      port_ = free_port();
      const std::string d = dir_.string();
      ahd_test::spit(dir_ / "nginx.conf",
                     "daemon off;\nmaster_process off;\nworker_processes 1;\npid " + d + "/nginx.pid;\nerror_log " + d +
                         "/error.log;\nevents { worker_connections 64; }\nhttp {\n  access_log off;\n"
                         "  client_body_temp_path " +
                         d +
                         "/body;\n  client_max_body_size 0;\n"
                         "  server {\n    listen 127.0.0.1:" +
                         std::to_string(port_) + ";\n    root " + d +
                         "/root;\n"
                         "    location / {\n      dav_methods PUT;\n      create_full_put_path on;\n"
                         "      dav_access user:rw;\n    }\n  }\n}\n");
      const std::string nginx = find_nginx(), prefix = d + "/", conf = d + "/nginx.conf", err = d + "/error.log";
      std::vector<const char*> argv = {nginx.c_str(), "-p", prefix.c_str(), "-c",
                                       conf.c_str(),  "-e", err.c_str(),    nullptr};
      if (posix_spawn(&pid_, nginx.c_str(), nullptr, nullptr, const_cast<char**>(argv.data()), environ) != 0) {
        pid_ = -1;
        return "posix_spawn failed";
      }
      for (int i = 0; i < 200; ++i) {  // up to 10 s for it to listen
        if (accepts(port_)) return "";
        int st = 0;
        if (waitpid(pid_, &st, WNOHANG) == pid_) {
          pid_ = -1;
          break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
      kill_now();
    }
    return "nginx did not start: " + (fs::exists(dir_ / "error.log") ? ahd_test::read_text(dir_ / "error.log") : "");
  }
  // SIGKILL: the server is gone at once, connections reset.
  void kill_now() {
    if (pid_ <= 0) return;
    kill(pid_, SIGKILL);  // a stopped process too (SIGCONT first would let it answer what waits)
    waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }
  void stop_signal() {
    if (pid_ > 0) kill(pid_, SIGSTOP);
  }
  // True once a connection to the server is established (queued by the kernel, even while the
  // server is stopped): /proc/net/tcp lists it with the server's port as its local port, state 01.
  bool has_connection() const {
    std::istringstream in(ahd_test::read_text("/proc/net/tcp"));
    std::string line;
    char want[8];
    std::snprintf(want, sizeof(want), ":%04X", unsigned(port_));
    while (std::getline(in, line)) {
      std::istringstream f(line);
      std::string sl, local, remote, st;
      f >> sl >> local >> remote >> st;
      if (local.size() > 5 && local.substr(local.size() - 5) == want && st == "01") return true;
    }
    return false;
  }
  std::string url() const { return "http://127.0.0.1:" + std::to_string(port_) + "/team/"; }
  fs::path root() const { return dir_ / "root" / "team"; }

 private:
  fs::path dir_;
  pid_t pid_ = -1;
  int port_ = 0;
};

CookRequest sample_request(const fs::path& out, std::shared_ptr<const CacheBackend> cache, int size = 32) {
  CookRequest r;
  r.input.sample_size = size;  // the built-in sample: no input file
  r.output = out.string();
  r.options.profile = "pc-bc";
  r.options.threads = 1;
  r.cache = std::move(cache);
  return r;
}

std::map<std::string, std::vector<uint8_t>> folder_files(const fs::path& dir) {
  std::map<std::string, std::vector<uint8_t>> m;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file()) m[e.path().filename().string()] = ahd_test::slurp(e.path());
  return m;
}

// Everything but the report (whose seconds differ between two conversions).
std::map<std::string, std::vector<uint8_t>> without_report(std::map<std::string, std::vector<uint8_t>> m) {
  for (auto it = m.begin(); it != m.end();)
    it = it->first.find(".report.") != std::string::npos ? m.erase(it) : std::next(it);
  return m;
}

struct Cooked {
  CookResult result;
  std::vector<std::string> warnings;
  std::string said() const {  // the warnings, for a failure's message
    std::string t;
    for (const std::string& w : warnings) t += "\n  " + w;
    return t;
  }
};

Cooked cook_with(const CookRequest& r, std::function<void()> after_convert = {}) {
  Cooked run;
  CookHooks h;
  h.events.warning = [&](const std::string& m) { run.warnings.push_back(m); };
  if (after_convert) h.converted = [&](const CookConverted&) { after_convert(); };
  run.result = cook_conversion(r, h);
  return run;
}

class CookHttpCache : public ::testing::Test {
 protected:
  void SetUp() override {
    if (find_nginx().empty()) GTEST_SKIP() << "nginx is not installed (scripts/setup.sh installs nginx-light)";
    dir_ = ahd_test::temp_dir("cook_http");
    server_ = std::make_unique<Nginx>(fs::path(dir_) / "server");
    const std::string why = server_->start();
    if (!why.empty()) FAIL() << why;
  }
  void TearDown() override {
    server_.reset();
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  fs::path out(const std::string& name) const { return fs::path(dir_) / name / "s.ktx2"; }
  std::shared_ptr<const CacheBackend> cache() const { return open_cache(server_->url(), 0); }

  std::string dir_;
  std::unique_ptr<Nginx> server_;
};

TEST_F(CookHttpCache, MissThenHitWithIdenticalBytes) {
  const Cooked miss = cook_with(sample_request(out("a"), cache()));
  EXPECT_EQ(miss.result.outcome, CookResult::Outcome::Converted);
  EXPECT_TRUE(miss.warnings.empty()) << miss.said();
  // Bazel's layout on the server: the ActionResult under ac/<key>, the entry's blob under cas/<sha256>.
  ASSERT_TRUE(fs::exists(server_->root() / "ac" / miss.result.key));
  size_t blobs = 0;
  for (const auto& e : fs::directory_iterator(server_->root() / "cas")) {
    const std::vector<uint8_t> b = ahd_test::slurp(e.path());
    EXPECT_EQ(sha256_hex(b.data(), b.size()), e.path().filename().string());
    ++blobs;
  }
  EXPECT_EQ(blobs, 2u);  // the entry and the command's inputs record

  // Another output folder, a new client (another machine): served by the key, the stored bytes.
  const Cooked hit = cook_with(sample_request(out("b"), cache()));
  EXPECT_EQ(hit.result.outcome, CookResult::Outcome::CacheHit);
  EXPECT_EQ(hit.result.key, miss.result.key);
  EXPECT_EQ(folder_files(fs::path(dir_) / "a"), folder_files(fs::path(dir_) / "b"));  // the report too: the stored one
  // The first command again: the direct lookup (the inputs record) serves it.
  const Cooked direct = cook_with(sample_request(out("a"), cache()));
  EXPECT_EQ(direct.result.outcome, CookResult::Outcome::CacheHit);

  // The command line takes the URL with the same flag as a folder (its options differ from the
  // request's above, so it has its own key): a miss that stores, then a hit.
  const auto cli = [&](const std::string& name) {
    return ahd_test::run_cli(
        {"convert", "-o", out(name).string(), "--sample-size", "32", "--profile", "pc-bc", "--cache", server_->url()});
  };
  const auto c1 = cli("c1");
  ASSERT_EQ(c1.exit_code, 0) << c1.output;
  EXPECT_NE(c1.output.find("cache: stored "), std::string::npos) << c1.output;
  const auto c2 = cli("c2");
  ASSERT_EQ(c2.exit_code, 0) << c2.output;
  EXPECT_NE(c2.output.find("cache hit "), std::string::npos) << c2.output;
  EXPECT_NE(c2.output.find("(" + server_->url() + "ac/"), std::string::npos) << c2.output;
  EXPECT_EQ(folder_files(fs::path(dir_) / "c1"), folder_files(fs::path(dir_) / "c2"));
}

TEST_F(CookHttpCache, TwoConversionsFillOneKeyAtOnce) {
  Cooked r1, r2;
  std::thread t1([&] { r1 = cook_with(sample_request(out("p"), cache(), 64)); });
  std::thread t2([&] { r2 = cook_with(sample_request(out("q"), cache(), 64)); });
  t1.join(), t2.join();
  EXPECT_TRUE(r1.warnings.empty() && r2.warnings.empty()) << r1.said() << r2.said();
  ASSERT_EQ(r1.result.key, r2.result.key);
  EXPECT_EQ(without_report(folder_files(fs::path(dir_) / "p")), without_report(folder_files(fs::path(dir_) / "q")));
  // Whoever wrote last, the entry is whole: the next conversion is a hit with the same planes.
  const Cooked third = cook_with(sample_request(out("r"), cache(), 64));
  EXPECT_EQ(third.result.outcome, CookResult::Outcome::CacheHit);
  EXPECT_EQ(without_report(folder_files(fs::path(dir_) / "p")), without_report(folder_files(fs::path(dir_) / "r")));
}

TEST_F(CookHttpCache, ServerKilledBeforeTheStoreIsOneWarning) {
  const Cooked r = cook_with(sample_request(out("a"), cache()), [&] { server_->kill_now(); });
  EXPECT_EQ(r.result.outcome, CookResult::Outcome::Converted);
  ASSERT_EQ(r.warnings.size(), 1u) << r.said();
  EXPECT_EQ(r.warnings[0].rfind(server_->url() + "ac/" + r.result.key + ": not stored: ", 0), 0u) << r.said();
  EXPECT_NE(r.warnings[0].find("(the conversion is not cached)"), std::string::npos) << r.said();
  EXPECT_TRUE(fs::exists(out("a").parent_path() / "s.json"));

  // Nothing usable was left: a server started again on the same files misses and stores.
  ASSERT_EQ(server_->start(), "");
  const Cooked again = cook_with(sample_request(out("b"), cache()));
  EXPECT_EQ(again.result.outcome, CookResult::Outcome::Converted);
  EXPECT_TRUE(again.warnings.empty()) << again.said();
  EXPECT_EQ(without_report(folder_files(fs::path(dir_) / "a")), without_report(folder_files(fs::path(dir_) / "b")));
}

TEST_F(CookHttpCache, ServerKilledDuringTheStoreIsOneWarning) {
  // Stopped when the conversion is done, so the store's PUT waits on it (the kernel accepts the
  // connection and buffers the request); killed once that connection is there.
  std::thread killer;
  const Cooked r = cook_with(sample_request(out("a"), cache(), 256), [&] {
    server_->stop_signal();
    killer = std::thread([&] {
      for (int i = 0; i < 3000 && !server_->has_connection(); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      server_->kill_now();
    });
  });
  killer.join();
  EXPECT_EQ(r.result.outcome, CookResult::Outcome::Converted);
  ASSERT_EQ(r.warnings.size(), 1u) << r.said();
  EXPECT_NE(r.warnings[0].find(": not stored: "), std::string::npos) << r.said();
  // Cut during the exchange, not refused before it.
  EXPECT_TRUE(r.warnings[0].find("the connection broke") != std::string::npos ||
              r.warnings[0].find("closed the connection without an answer") != std::string::npos)
      << r.said();
  EXPECT_TRUE(fs::exists(out("a").parent_path() / "s.json"));
  // No result on the server names a blob that is not whole (the blob goes first).
  ASSERT_EQ(server_->start(), "");
  const Cooked again = cook_with(sample_request(out("b"), cache(), 256));
  EXPECT_EQ(again.result.outcome, CookResult::Outcome::Converted);
  EXPECT_EQ(without_report(folder_files(fs::path(dir_) / "a")), without_report(folder_files(fs::path(dir_) / "b")));
}

TEST_F(CookHttpCache, CorruptEntriesOnTheServerAreNeverAHit) {
  const Cooked a32 = cook_with(sample_request(out("a32"), cache(), 32));
  const Cooked a16 = cook_with(sample_request(out("a16"), cache(), 16));
  ASSERT_TRUE(a32.warnings.empty() && a16.warnings.empty());
  const std::string key = a32.result.key;
  const fs::path ac = server_->root() / "ac" / key, ac16 = server_->root() / "ac" / a16.result.key;
  const auto reference = without_report(folder_files(fs::path(dir_) / "a32"));
  // The blob the result names now (each conversion stores its own: the report's seconds differ).
  const auto current_blob = [&](std::vector<uint8_t>* entry) {
    const std::optional<std::vector<OutputFile>> files = cache()->lookup(key);
    EXPECT_TRUE(files);
    *entry = ConversionCache::encode(key, files ? *files : std::vector<OutputFile>{});
    const fs::path p = server_->root() / "cas" / sha256_hex(entry->data(), entry->size());
    EXPECT_TRUE(fs::exists(p));
    return p;
  };

  // Each damage: the backend misses, and a conversion through it writes the right bytes (and
  // stores a good entry again).
  int round = 0;
  const auto expect_converted = [&](const std::string& what) {
    EXPECT_FALSE(cache()->lookup(key)) << what;
    const fs::path o = out("r" + std::to_string(round++));
    const Cooked r = cook_with(sample_request(o, cache(), 32));
    EXPECT_EQ(r.result.outcome, CookResult::Outcome::Converted) << what;
    EXPECT_TRUE(r.warnings.empty()) << what << ": " << r.said();
    EXPECT_EQ(without_report(folder_files(o.parent_path())), reference) << what;
  };
  std::vector<uint8_t> entry;
  fs::path blob = current_blob(&entry);
  std::vector<uint8_t> flipped = entry;
  flipped[flipped.size() - 100] ^= 1;
  ahd_test::spit(blob, flipped);
  expect_converted("a flipped bit in the blob");
  blob = current_blob(&entry);
  ahd_test::spit(blob, std::vector<uint8_t>(entry.begin(), entry.end() - 7));
  expect_converted("a truncated blob");
  fs::copy_file(ac16, ac, fs::copy_options::overwrite_existing);
  expect_converted("the result of another key (a whole, valid entry of a 16x16 sample)");
  ahd_test::spit(ac, std::string("\x12\x05garbage"));
  expect_converted("a malformed ActionResult");
  fs::remove(current_blob(&entry));
  expect_converted("a result whose blob is gone");
  blob = current_blob(&entry);
  const std::vector<uint8_t> good_ac = ahd_test::slurp(ac);
  const std::vector<OutputFile> good = *cache()->lookup(key);

  // A self-consistent entry (every hash in its header right) whose plane does not match its
  // manifest: the backend returns it, the cook refuses it (the manifest's plane hashes).
  std::vector<OutputFile> forged = good;
  for (OutputFile& f : forged)
    if (f.name.find(".ktx2") != std::string::npos) {
      f.bytes[f.bytes.size() - 1] ^= 0x55;
      break;
    }
  const std::vector<uint8_t> fe = ConversionCache::encode(key, forged);
  // Stored as the backend stores: blob under its SHA-256, the ActionResult naming it.
  std::string ar(good_ac.begin(), good_ac.end());
  const std::string old_sha = sha256_hex(entry.data(), entry.size()), new_sha = sha256_hex(fe.data(), fe.size());
  ASSERT_NE(ar.find(old_sha), std::string::npos);
  ar.replace(ar.find(old_sha), 64, new_sha);
  ahd_test::spit(server_->root() / "cas" / new_sha, fe);
  ahd_test::spit(ac, ar);
  ASSERT_TRUE(cache()->lookup(key));
  const Cooked r = cook_with(sample_request(out("forged"), cache(), 32));
  EXPECT_EQ(r.result.outcome, CookResult::Outcome::Converted);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("cache entry refused"), std::string::npos) << r.said();
  EXPECT_EQ(without_report(folder_files(out("forged").parent_path())), reference);
  // The conversion stored a good entry again: the next one is a hit.
  EXPECT_EQ(cook_with(sample_request(out("healed"), cache(), 32)).result.outcome, CookResult::Outcome::CacheHit);
}

// No nginx needed below: nothing listening, and a listener that never answers.
TEST(CookHttpCacheNoServer, UnreachableServerIsOneWarning) {
  const fs::path d = ahd_test::temp_dir("cook_http_none");
  const std::string url = "http://127.0.0.1:" + std::to_string(free_port()) + "/";
  const Cooked r = cook_with(sample_request(d / "s.ktx2", open_cache(url, 0)));
  EXPECT_EQ(r.result.outcome, CookResult::Outcome::Converted);
  ASSERT_EQ(r.warnings.size(), 1u) << r.said();
  EXPECT_NE(r.warnings[0].find("cannot connect"), std::string::npos) << r.said();
  EXPECT_TRUE(fs::exists(d / "s.json"));
  fs::remove_all(d);
}

TEST(CookHttpCacheNoServer, SilentServerTimesOut) {
  const int s = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(bind(s, reinterpret_cast<sockaddr*>(&a), sizeof(a)), 0);
  ASSERT_EQ(listen(s, 16), 0);  // the kernel completes connections; nobody reads or answers
  socklen_t len = sizeof(a);
  getsockname(s, reinterpret_cast<sockaddr*>(&a), &len);
  const fs::path d = ahd_test::temp_dir("cook_http_silent");
  const std::string url = "http://127.0.0.1:" + std::to_string(ntohs(a.sin_port)) + "/?timeout=1";
  const Cooked r = cook_with(sample_request(d / "s.ktx2", open_cache(url, 0)));
  close(s);
  EXPECT_EQ(r.result.outcome, CookResult::Outcome::Converted);
  ASSERT_EQ(r.warnings.size(), 1u) << r.said();
  EXPECT_NE(r.warnings[0].find("did not answer earlier"), std::string::npos) << r.said();
  EXPECT_NE(r.warnings[0].find("sent nothing for 1 s"), std::string::npos) << r.said();
  fs::remove_all(d);
}

TEST(CookHttpCacheNoServer, UrlsItCannotUseAreOneError) {
  for (const char* u : {"https://cache.example/", "http://", "http://host:0/", "http://host:99999/", "http://u:p@host/",
                        "http://host/a b/", "http://host/?timeout=0", "http://host/?x=1"})
    EXPECT_THROW(open_cache(u, 0), Error) << u;
  EXPECT_EQ(open_cache("http://127.0.0.1:8080/p", 0)->entry_path(std::string(64, 'a')),
            "http://127.0.0.1:8080/p/ac/" + std::string(64, 'a'));
}

}  // namespace
