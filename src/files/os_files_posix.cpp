// files/os_files.h on POSIX systems (Linux; macOS but for executable_path). The Windows form is
// files/os_files_win32.cpp.
#ifndef _WIN32
#include "files/os_files.h"

#include <dlfcn.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "core/error.h"
#include "files/utf8_path.h"

namespace ahd::os {

long process_id() { return long(::getpid()); }

bool process_may_run(long pid) { return ::kill(pid_t(pid), 0) == 0 || errno != ESRCH; }

std::string error_text(int e) { return std::strerror(e); }

ReadFile::~ReadFile() {
  if (fd >= 0) ::close(fd);
}

int path_status(const std::string& path, bool* regular, uint64_t* size) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return errno;
  *regular = S_ISREG(st.st_mode);
  *size = uint64_t(st.st_size);
  return 0;
}

int open_for_reading(const std::string& path, bool no_symlink, ReadFile* f) {
  f->fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY | (no_symlink ? O_NOFOLLOW : 0));
  if (f->fd < 0) return errno;
  // Back to blocking reads (a regular file never blocks on O_NONBLOCK anyway).
  ::fcntl(f->fd, F_SETFL, ::fcntl(f->fd, F_GETFL) & ~O_NONBLOCK);
  return 0;
}

int file_status(const ReadFile& f, bool* regular, uint64_t* size) {
  struct stat st {};
  if (::fstat(f.fd, &st) != 0) return errno;
  *regular = S_ISREG(st.st_mode);
  *size = uint64_t(st.st_size);
  return 0;
}

long read_some(const ReadFile& f, uint8_t* out, size_t n) { return long(::read(f.fd, out, n)); }

int write_new_synced(const std::string& path, const std::vector<uint8_t>& bytes, int fault, bool* created) {
  *created = false;
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) return errno;
  *created = true;
  auto fail = [&](int e, bool close_it) {
    if (close_it) ::close(fd);
    ::unlink(path.c_str());
    return e;
  };
  if (fault) return fail(fault, true);
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return fail(n < 0 ? errno : ENOSPC, true);
    done += size_t(n);
  }
  // fsync before the rename: otherwise a crash can publish a name whose data never reached the disk.
  if (::fsync(fd) != 0) return fail(errno, true);
  if (::close(fd) != 0) return fail(errno, false);
  return 0;
}

void sync_folder(const std::string& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);  // best effort: some file systems refuse fsync on folders
  ::close(fd);
}

int rename_replace(const char* from, const char* to) { return ::rename(from, to) == 0 ? 0 : errno; }

void remove_file(const char* path) { ::unlink(path); }

FolderLock::FolderLock(const std::string& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) throw file_error(dir, "cannot open the folder (" + error_text(errno) + ")");
  handle_ = fd;
  while (::flock(fd, LOCK_EX) != 0) {
    if (errno == EINTR) continue;
    // A file system without locks (some network mounts): publish unlocked rather than not at all.
    if (errno == ENOLCK || errno == EBADF || errno == EINVAL || errno == EOPNOTSUPP) break;
    const int e = errno;
    ::close(fd);
    handle_ = -1;
    throw file_error(dir, "cannot lock the folder (" + error_text(e) + ")");
  }
}

FolderLock::~FolderLock() {
  if (handle_ >= 0) ::close(int(handle_));
}

namespace {

void (*g_cleanup)() = nullptr;
struct Saved {
  struct sigaction old_int {}, old_term {};
};

extern "C" void on_interrupt(int sig) {
  if (g_cleanup) g_cleanup();
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

}  // namespace

InterruptCleanup::InterruptCleanup(void (*cleanup)()) {
  g_cleanup = cleanup;
  auto* saved = new Saved;
  struct sigaction sa {};
  sa.sa_handler = on_interrupt;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &saved->old_int);
  sigaction(SIGTERM, &sa, &saved->old_term);
  saved_ = saved;
}

InterruptCleanup::~InterruptCleanup() {
  auto* saved = static_cast<Saved*>(saved_);
  sigaction(SIGINT, &saved->old_int, nullptr);
  sigaction(SIGTERM, &saved->old_term, nullptr);
  delete saved;
  g_cleanup = nullptr;
}

void signal_self(SelfSignal s) {
  ::kill(::getpid(), s == SelfSignal::kInterrupt ? SIGINT : s == SelfSignal::kTerminate ? SIGTERM : SIGKILL);
}

std::string executable_path() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : utf8_string(exe);
}

std::string module_path_of(const void* address) {
  Dl_info info{};
  if (!::dladdr(const_cast<void*>(address), &info) || !info.dli_fname) return {};
  return info.dli_fname;
}

bool stderr_is_terminal() { return ::isatty(STDERR_FILENO) != 0; }

void* load_module(const std::string& path, std::string* error) {
  // RTLD_LOCAL: the module's symbols (OpenImageIO's) stay out of the process's global scope.
  void* so = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!so) {
    const char* e = ::dlerror();  // names the path
    *error = e ? e : path + ": cannot load";
  }
  return so;
}

void* module_symbol(void* module, const char* name) { return ::dlsym(module, name); }

}  // namespace ahd::os
#endif  // !_WIN32
