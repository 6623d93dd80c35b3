#include "files/output_set.h"

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <mutex>
#include <regex>
#include <set>

#include "containers/sha256.h"
#include "core/error.h"
#include "files/file_io.h"
#include "files/os_files.h"
#include "files/utf8_path.h"

namespace ahd {
namespace fs = std::filesystem;

namespace {

// What to undo if SIGINT/SIGTERM arrives during a publish. Fixed storage: the handler may only call
// async-signal-safe functions (os::remove_file, os::rename_replace: unlink, rename). Each slot: kUnlink removes a[i]
// (a temporary, or a member renamed before the commit), kRestore renames a[i] back to b[i] (an
// annex moved aside).
constexpr int kMaxSlots = 64;
enum : int { kIdle = 0, kUnlink = 1, kRestore = 2 };
char g_a[kMaxSlots][4096], g_b[kMaxSlots][4096];
std::atomic<int> g_state[kMaxSlots];
std::atomic<int> g_slots{0};

void on_interrupt() {
  const int n = g_slots.load();
  for (int i = 0; i < n && i < kMaxSlots; ++i) {
    const int st = g_state[i].load();
    if (st == kUnlink) os::remove_file(g_a[i]);
    else if (st == kRestore) os::rename_replace(g_a[i], g_b[i]);
  }
}

void reset_slots() {
  for (auto& s : g_state) s.store(kIdle);
  g_slots.store(0);
}

// Installs the handler for the lifetime of one publish; restores the previous ones after.
struct InterruptGuard {
  // Slots first: the handler must never see a previous publish's slots.
  bool reset = (reset_slots(), true);
  os::InterruptCleanup cleanup{on_interrupt};
  ~InterruptGuard() { reset_slots(); }
  // A new slot (or -1 when full or the path is too long: that file is then only cleaned up by the
  // next run, as a stale temporary).
  int add() {
    const int i = g_slots.load();
    if (i >= kMaxSlots) return -1;
    g_slots.store(i + 1);
    return i;
  }
  // The slot's action from now on. The state goes idle while the paths change, so the handler
  // never reads a half-written path.
  static void set(int slot, int state, const std::string& a = {}, const std::string& b = {}) {
    if (slot < 0) return;
    g_state[slot].store(kIdle);
    if (state == kIdle) return;
    if (a.size() >= sizeof g_a[0] || b.size() >= sizeof g_b[0]) return;
    std::memcpy(g_a[slot], a.c_str(), a.size() + 1);
    std::memcpy(g_b[slot], b.c_str(), b.size() + 1);
    g_state[slot].store(state);
  }
};

std::string errno_text(int e) { return os::error_text(e); }

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
  // Written, fsynced and closed, every step checked; removed on failure (files/os_files.h).
  bool created = false;
  const int e = os::write_new_synced(tmp, bytes, fault, &created);
  if (e == 0) return;
  if (!created) throw file_error(final_path, "cannot create a file in its folder (" + errno_text(e) + ")");
  throw file_error(final_path, "write failed (" + errno_text(e) + ")");
}

void fsync_dir(const fs::path& dir) { os::sync_folder(utf8_string(dir)); }

// AHDPACK_TEST_KILL_BEFORE_RENAME="k" (SIGKILL), "k:INT" or "k:TERM": the signal this process sends
// itself before rename k.
struct KillHook {
  long index = -1;
  os::SelfSignal sig = os::SelfSignal::kKill;
};

KillHook kill_before_rename_hook() {
  KillHook h;
  const char* s = std::getenv("AHDPACK_TEST_KILL_BEFORE_RENAME");
  if (!s || !*s) return h;
  char* end = nullptr;
  const long v = std::strtol(s, &end, 10);
  const std::string sig = *end == ':' ? end + 1 : "";
  if (v < 0 || (*end != '\0' && *end != ':')) return h;
  h.index = v;
  using S = os::SelfSignal;
  h.sig = sig == "INT" ? S::kInterrupt : sig == "TERM" ? S::kTerminate : S::kKill;
  return h;
}

void maybe_kill(const KillHook& hook, size_t index) {
  if (hook.index >= 0 && size_t(hook.index) == index) os::signal_self(hook.sig);
}

}  // namespace

bool is_temporary_name(const std::string& filename) {
  static const std::regex re(R"(^\..+\.ahdtmp-[0-9]+-[0-9a-f]{8}.*$)");
  return std::regex_match(filename, re);
}

size_t remove_stale_temporaries(const std::string& dir) {
  size_t removed = 0;
  std::error_code ec;
  fs::directory_iterator it(fs_path(dir.empty() ? "." : dir), ec), end;
  for (; !ec && it != end; it.increment(ec)) {
    const std::string fn = utf8_string(it->path().filename());
    if (!is_temporary_name(fn)) continue;
    const size_t at = fn.find(".ahdtmp-") + 8;
    const long pid = std::strtol(fn.c_str() + at, nullptr, 10);
    // Another ahdpack still writing into this folder keeps its temporaries.
    if (pid > 0 && pid != os::process_id() && os::process_may_run(pid)) continue;
    std::error_code rm;
    if (pid != os::process_id() && fs::remove(it->path(), rm)) ++removed;
  }
  return removed;
}


namespace {

std::mutex g_publish_mutex;  // one publish per process at a time: the signal clean-up is process-wide

// Renames with the kill hook in front of each; `count` numbers every rename of one publish.
struct Renamer {
  KillHook hook = kill_before_rename_hook();
  size_t count = 0;
  void operator()(const std::string& from, const std::string& to) {
    maybe_kill(hook, count++);
    if (const int e = os::rename_replace(from.c_str(), to.c_str()))
      throw file_error(to, "cannot rename its temporary file (" + errno_text(e) + ")");
  }
};

}  // namespace

void publish_output_set(const OutputSet& set) {
  std::lock_guard<std::mutex> process_lock(g_publish_mutex);
  std::vector<const FileToPublish*> files;  // members, commit, annexes: the order of the writes
  for (const auto& f : set.members) files.push_back(&f);
  files.push_back(&set.commit);
  for (const auto& f : set.annexes) files.push_back(&f);
  const fs::path dir = fs_path(set.commit.path).parent_path();
  {
    std::error_code ec;
    if (!dir.empty()) fs::create_directories(dir, ec);
    if (ec) throw file_error(set.commit.path, "cannot create folder " + utf8_string(dir) + " (" + ec.message() + ")");
  }
  for (const FileToPublish* f : files) {
    std::error_code ec;
    if (fs_path(f->path).parent_path() != dir) throw Error("publish_output_set: " + f->path + " is not beside " + set.commit.path);
    if (fs::is_directory(fs_path(f->path), ec)) throw file_error(f->path, "is a folder");
  }
  const bool is_set = !set.members.empty() || !set.annexes.empty() || !set.annex_names.empty() || set.superseded;
  std::unique_ptr<os::FolderLock> folder_lock;
  if (is_set) folder_lock = std::make_unique<os::FolderLock>(utf8_string(dir));
  remove_stale_temporaries(utf8_string(dir));
  const std::vector<std::string> superseded = set.superseded ? set.superseded() : std::vector<std::string>{};

  std::set<std::string> published;
  for (const FileToPublish* f : files) published.insert(utf8_string(fs_path(f->path).lexically_normal()));

  InterruptGuard guard;
  const size_t n = files.size(), n_members = set.members.size();
  std::vector<std::string> temps(n);
  std::vector<int> slots(n, -1);
  std::vector<bool> renamed(n, false);
  std::vector<std::string> created;  // members new to the folder, renamed before the commit
  std::vector<int> created_slots;
  struct Aside {
    std::string final_path, tmp;
    int slot;
  };
  std::vector<Aside> aside;  // previous annexes moved out of the way
  bool committed = false;
  auto undo = [&]() {
    for (size_t i = 0; i < n; ++i)
      if (!temps[i].empty() && !renamed[i]) os::remove_file(temps[i].c_str());
    if (committed) {
      for (const Aside& a : aside) os::remove_file(a.tmp.c_str());
      return;
    }
    for (const auto& p : created) os::remove_file(p.c_str());
    for (const Aside& a : aside) os::rename_replace(a.tmp.c_str(), a.final_path.c_str());
  };
  Renamer rename;
  try {
    for (size_t i = 0; i < n; ++i) {
      temps[i] = temp_path_for(files[i]->path);
      slots[i] = guard.add();
      InterruptGuard::set(slots[i], kUnlink, temps[i]);
      write_synced(temps[i], files[i]->path, files[i]->bytes, injected_write_fault(i));
    }
    for (size_t i = 0; i < n_members; ++i) {
      const std::string& path = files[i]->path;
      std::error_code ec;
      const bool existed = fs::exists(fs_path(path), ec);
      rename(temps[i], path);
      renamed[i] = true;
      // New to the folder: an orphan to remove if the commit does not happen. A member that replaced
      // a file had identical bytes (content-addressed) and stays.
      InterruptGuard::set(slots[i], existed ? kIdle : kUnlink, path);
      if (!existed) created.push_back(path);
    }
    for (const std::string& name : set.annex_names) {
      std::error_code ec;
      if (!fs::exists(fs::symlink_status(fs_path(name), ec))) continue;
      if (fs::is_directory(fs_path(name), ec)) throw file_error(name, "is a folder");
      Aside a{name, temp_path_for(name), guard.add()};
      InterruptGuard::set(a.slot, kRestore, a.tmp, a.final_path);
      rename(name, a.tmp);
      aside.push_back(a);
    }
    rename(temps[n_members], set.commit.path);  // the commit point
    renamed[n_members] = true;
    committed = true;
    for (size_t i = 0; i <= n_members; ++i) InterruptGuard::set(slots[i], kIdle);
    for (const Aside& a : aside) InterruptGuard::set(a.slot, kUnlink, a.tmp);
    // From the commit on, a signal finishes the clean-up the new set needs: the superseded files go.
    for (const std::string& f : superseded)
      if (!published.count(utf8_string(fs_path(f).lexically_normal()))) InterruptGuard::set(guard.add(), kUnlink, f);
    for (size_t i = n_members + 1; i < n; ++i) {
      rename(temps[i], files[i]->path);
      renamed[i] = true;
      InterruptGuard::set(slots[i], kIdle);
    }
  } catch (...) {
    undo();
    fsync_dir(dir);
    throw;
  }
  for (const Aside& a : aside) os::remove_file(a.tmp.c_str());
  fsync_dir(dir);
  maybe_kill(rename.hook, rename.count);
  bool removed = false;
  for (const auto& s : superseded) {
    if (published.count(utf8_string(fs_path(s).lexically_normal()))) continue;
    std::error_code ec;
    removed |= fs::remove(fs_path(s), ec);
  }
  if (removed) fsync_dir(dir);
}

void publish_output_set(const std::vector<FileToPublish>& files, const std::vector<std::string>& superseded) {
  if (files.empty()) return;
  OutputSet set;
  set.members.assign(files.begin(), files.end() - 1);
  set.commit = files.back();
  if (!superseded.empty()) set.superseded = [superseded] { return superseded; };
  publish_output_set(set);
}

void write_new_file(const std::string& path, const std::vector<uint8_t>& bytes) { write_synced(path, path, bytes); }

void publish_file(const std::string& path, std::vector<uint8_t> bytes) {
  OutputSet set;
  set.commit = {path, std::move(bytes)};
  publish_output_set(set);
}

void write_file_atomic(const std::string& path, std::vector<uint8_t> bytes) { publish_file(path, std::move(bytes)); }

void write_file_atomic(const std::string& path, const std::string& text) {
  publish_file(path, std::vector<uint8_t>(text.begin(), text.end()));
}

}  // namespace ahd
