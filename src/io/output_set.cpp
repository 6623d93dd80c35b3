#include "io/output_set.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <regex>
#include <set>

#include "containers/sha256.h"
#include "core/error.h"
#include "io/image_io.h"

namespace ahd {
namespace fs = std::filesystem;

namespace {

// Temporaries to unlink if SIGINT/SIGTERM arrives during publish_output_set. Fixed storage: the
// handler may only call async-signal-safe functions (unlink, signal, raise).
constexpr int kMaxTemps = 64;
char g_temps[kMaxTemps][4096];
std::atomic<int> g_temp_count{0};
std::atomic<bool> g_temp_live[kMaxTemps];

extern "C" void on_interrupt(int sig) {
  const int n = g_temp_count.load();
  for (int i = 0; i < n && i < kMaxTemps; ++i)
    if (g_temp_live[i].load()) ::unlink(g_temps[i]);
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

// Installs the handler for the lifetime of one publish; restores the previous ones after.
struct InterruptGuard {
  struct sigaction old_int {}, old_term {};
  InterruptGuard() {
    g_temp_count.store(0);
    struct sigaction sa {};
    sa.sa_handler = on_interrupt;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &old_int);
    sigaction(SIGTERM, &sa, &old_term);
  }
  ~InterruptGuard() {
    sigaction(SIGINT, &old_int, nullptr);
    sigaction(SIGTERM, &old_term, nullptr);
    g_temp_count.store(0);
  }
  // Returns the slot (or -1 when full: the file is then only cleaned up by the next run).
  int add(const std::string& path) {
    const int i = g_temp_count.load();
    if (i >= kMaxTemps || path.size() >= sizeof g_temps[0]) return -1;
    std::memcpy(g_temps[i], path.c_str(), path.size() + 1);
    g_temp_live[i].store(true);
    g_temp_count.store(i + 1);
    return i;
  }
  static void drop(int slot) {
    if (slot >= 0) g_temp_live[slot].store(false);
  }
};

std::string errno_text(int e) { return std::strerror(e); }

// Test hook AHDPACK_TEST_WRITE_FAULT="k:ENOSPC|EROFS|EACCES|EIO": writing the k-th file of a set
// fails with that error after its temporary file was created (a full disk, a folder turned
// read-only), since root ignores permissions and a real full disk cannot be had in a test.
int injected_write_fault(size_t index) {
  const char* s = std::getenv("AHDPACK_TEST_WRITE_FAULT");
  if (!s || !*s) return 0;
  char* end = nullptr;
  const long k = std::strtol(s, &end, 10);
  if (*end != ':' || k < 0 || size_t(k) != index) return 0;
  const std::string e = end + 1;
  return e == "ENOSPC" ? ENOSPC : e == "EROFS" ? EROFS : e == "EACCES" ? EACCES : EIO;
}

// Writes and fsyncs one temporary file; throws naming the final path.
void write_synced(const std::string& tmp, const std::string& final_path, const std::vector<uint8_t>& bytes,
                  int fault = 0) {
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) throw file_error(final_path, "cannot create a file in its folder (" + errno_text(errno) + ")");
  if (fault) {
    ::close(fd);
    ::unlink(tmp.c_str());
    throw file_error(final_path, "write failed (" + errno_text(fault) + ")");
  }
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int e = n < 0 ? errno : ENOSPC;
      ::close(fd);
      ::unlink(tmp.c_str());
      throw file_error(final_path, "write failed (" + errno_text(e) + ")");
    }
    done += size_t(n);
  }
  // fsync before the rename: otherwise a crash can publish a name whose data never reached the disk.
  if (::fsync(fd) != 0) {
    const int e = errno;
    ::close(fd);
    ::unlink(tmp.c_str());
    throw file_error(final_path, "write failed (" + errno_text(e) + ")");
  }
  if (::close(fd) != 0) {
    const int e = errno;
    ::unlink(tmp.c_str());
    throw file_error(final_path, "write failed (" + errno_text(e) + ")");
  }
}

void fsync_dir(const fs::path& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);  // best effort: some file systems refuse fsync on folders
  ::close(fd);
}

long kill_before_rename_hook() {
  const char* s = std::getenv("AHDPACK_TEST_KILL_BEFORE_RENAME");
  if (!s || !*s) return -1;
  char* end = nullptr;
  const long v = std::strtol(s, &end, 10);
  return *end == '\0' && v >= 0 ? v : -1;
}

void maybe_kill(long hook, size_t index) {
  if (hook >= 0 && size_t(hook) == index) ::kill(::getpid(), SIGKILL);
}

}  // namespace

bool is_temporary_name(const std::string& filename) {
  static const std::regex re(R"(^\..+\.ahdtmp-[0-9]+-[0-9a-f]{8}.*$)");
  return std::regex_match(filename, re);
}

size_t remove_stale_temporaries(const std::string& dir) {
  size_t removed = 0;
  std::error_code ec;
  fs::directory_iterator it(dir.empty() ? "." : dir, ec), end;
  for (; !ec && it != end; it.increment(ec)) {
    const std::string fn = it->path().filename().string();
    if (!is_temporary_name(fn)) continue;
    const size_t at = fn.find(".ahdtmp-") + 8;
    const long pid = std::strtol(fn.c_str() + at, nullptr, 10);
    // Another ahdpack still writing into this folder keeps its temporaries.
    if (pid > 0 && pid != long(::getpid()) && (::kill(pid_t(pid), 0) == 0 || errno != ESRCH)) continue;
    std::error_code rm;
    if (pid != long(::getpid()) && fs::remove(it->path(), rm)) ++removed;
  }
  return removed;
}


std::vector<std::string> superseded_planes(const std::string& dir, const std::string& name,
                                           const std::vector<FileToPublish>& keep) {
  std::set<std::string> kept;
  for (const auto& f : keep) kept.insert(fs::path(f.path).filename().string());
  std::vector<std::string> out;
  std::error_code ec;
  fs::directory_iterator it(dir.empty() ? "." : dir, ec), end;
  for (; !ec && it != end; it.increment(ec)) {
    const std::string fn = it->path().filename().string();
    if (fn.size() <= name.size() + 1 || fn.compare(0, name.size() + 1, name + ".") != 0 || kept.count(fn)) continue;
    static const std::regex re(R"(^(iz|dir|ratio|dirratio|coverage)(\.[0-9a-f]{12})?\.(ktx2|dds)$)");
    if (std::regex_match(fn.substr(name.size() + 1), re)) out.push_back((fs::path(dir) / fn).string());
  }
  return out;
}

void publish_output_set(const std::vector<FileToPublish>& files, const std::vector<std::string>& superseded) {
  if (files.empty()) return;
  std::set<fs::path> dirs;
  for (const auto& f : files) {
    const fs::path parent = fs::path(f.path).parent_path();
    std::error_code ec;
    if (!parent.empty()) fs::create_directories(parent, ec);
    if (ec) throw file_error(f.path, "cannot create folder " + parent.string() + " (" + ec.message() + ")");
    if (fs::is_directory(f.path, ec)) throw file_error(f.path, "is a folder");
    dirs.insert(parent);
  }
  for (const auto& d : dirs) remove_stale_temporaries(d.string());

  InterruptGuard guard;
  std::vector<std::string> temps(files.size());
  std::vector<int> slots(files.size(), -1);
  size_t renamed = 0;
  std::vector<std::string> created;  // final names that did not exist before this publish
  auto clean_up = [&]() {
    for (size_t i = renamed; i < files.size(); ++i)
      if (!temps[i].empty()) {
        ::unlink(temps[i].c_str());
        InterruptGuard::drop(slots[i]);
      }
    for (const auto& p : created) ::unlink(p.c_str());
  };
  try {
    for (size_t i = 0; i < files.size(); ++i) {
      temps[i] = temp_path_for(files[i].path);
      slots[i] = guard.add(temps[i]);
      write_synced(temps[i], files[i].path, files[i].bytes, injected_write_fault(i));
    }
    const long hook = kill_before_rename_hook();
    for (; renamed < files.size(); ++renamed) {
      maybe_kill(hook, renamed);
      const std::string& path = files[renamed].path;
      std::error_code ec;
      const bool existed = fs::exists(path, ec);
      if (::rename(temps[renamed].c_str(), path.c_str()) != 0)
        throw file_error(path, "cannot rename its temporary file (" + errno_text(errno) + ")");
      InterruptGuard::drop(slots[renamed]);
      // Only the manifest (last) makes the new files part of a set; before it, files new to the
      // folder are orphans to remove on failure, files that replaced identical ones stay.
      if (!existed && renamed + 1 < files.size()) created.push_back(path);
    }
  } catch (...) {
    clean_up();
    throw;
  }
  for (const auto& d : dirs) fsync_dir(d);
  maybe_kill(kill_before_rename_hook(), files.size());
  std::set<std::string> published;
  for (const auto& f : files) published.insert(fs::path(f.path).lexically_normal().string());
  bool removed = false;
  for (const auto& s : superseded) {
    if (published.count(fs::path(s).lexically_normal().string())) continue;
    std::error_code ec;
    removed |= fs::remove(s, ec);
  }
  if (removed)
    for (const auto& d : dirs) fsync_dir(d);
}

}  // namespace ahd
