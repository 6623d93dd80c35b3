// files/os_files.h on Windows (Win32 wide APIs; MinGW-w64 and MSVC). The POSIX form is
// files/os_files_posix.cpp. UTF-8 paths become UTF-16 through std::filesystem::path(u8string).
#ifdef _WIN32
#include "files/os_files.h"

#ifndef WIN32_LEAN_AND_MEAN
#define WIN32_LEAN_AND_MEAN
#endif
#ifndef NOMINMAX
#define NOMINMAX
#endif
#include <windows.h>

#include <fcntl.h>
#include <io.h>
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/error.h"

namespace ahd::os {
namespace {

std::wstring wide(const std::string& utf8) {
  return std::filesystem::path(std::u8string(utf8.begin(), utf8.end())).wstring();
}

std::string utf8(const std::wstring& w) {
  const std::u8string s = std::filesystem::path(w).u8string();
  return std::string(s.begin(), s.end());
}

// GetLastError as an errno value, for the callers' messages.
int errno_of(DWORD e) {
  switch (e) {
    case ERROR_FILE_NOT_FOUND: return ENOENT;
    case ERROR_PATH_NOT_FOUND: return ENOENT;
    case ERROR_INVALID_NAME: return ENOENT;
    case ERROR_ACCESS_DENIED: return EACCES;
    case ERROR_SHARING_VIOLATION: return EACCES;
    case ERROR_LOCK_VIOLATION: return EACCES;
    case ERROR_WRITE_PROTECT: return EROFS;
    case ERROR_FILE_EXISTS: return EEXIST;
    case ERROR_ALREADY_EXISTS: return EEXIST;
    case ERROR_DISK_FULL: return ENOSPC;
    case ERROR_HANDLE_DISK_FULL: return ENOSPC;
    case ERROR_NOT_SAME_DEVICE: return EXDEV;
    case ERROR_DIRECTORY: return ENOTDIR;
    case ERROR_NOT_ENOUGH_MEMORY: return ENOMEM;
    default: return EIO;
  }
}

}  // namespace

long process_id() { return long(GetCurrentProcessId()); }

bool process_may_run(long pid) {
  HANDLE h = OpenProcess(PROCESS_QUERY_LIMITED_INFORMATION, FALSE, DWORD(pid));
  if (!h) return GetLastError() != ERROR_INVALID_PARAMETER;  // no such process; else (access denied) it runs
  DWORD code = 0;
  const bool running = !GetExitCodeProcess(h, &code) || code == STILL_ACTIVE;
  CloseHandle(h);
  return running;
}

std::string error_text(int e) {
  char buf[256];
  strerror_s(buf, sizeof buf, e);
  return buf;
}

ReadFile::~ReadFile() {
  if (fd >= 0) ::_close(fd);
}

int path_status(const std::string& path, bool* regular, uint64_t* size) {
  struct _stat64 st {};
  if (::_wstat64(wide(path).c_str(), &st) != 0) return errno;
  *regular = (st.st_mode & _S_IFMT) == _S_IFREG;
  *size = uint64_t(st.st_size);
  return 0;
}

int open_for_reading(const std::string& path, bool no_symlink, ReadFile* f) {
  // Windows has no FIFOs in the file system and no controlling terminal; a symlink (or junction)
  // is refused by its attributes when `no_symlink`.
  const std::wstring w = wide(path);
  if (no_symlink) {
    const DWORD a = GetFileAttributesW(w.c_str());
    if (a != INVALID_FILE_ATTRIBUTES && (a & FILE_ATTRIBUTE_REPARSE_POINT)) return ELOOP;
  }
  f->fd = ::_wopen(w.c_str(), _O_RDONLY | _O_BINARY | _O_NOINHERIT);
  return f->fd < 0 ? errno : 0;
}

int file_status(const ReadFile& f, bool* regular, uint64_t* size) {
  struct _stat64 st {};
  if (::_fstat64(f.fd, &st) != 0) return errno;
  *regular = (st.st_mode & _S_IFMT) == _S_IFREG;
  *size = uint64_t(st.st_size);
  return 0;
}

long read_some(const ReadFile& f, uint8_t* out, size_t n) {
  return long(::_read(f.fd, out, unsigned(std::min<size_t>(n, size_t(1) << 30))));
}

int write_new_synced(const std::string& path, const std::vector<uint8_t>& bytes, int fault, bool* created) {
  *created = false;
  const std::wstring w = wide(path);
  HANDLE h = CreateFileW(w.c_str(), GENERIC_WRITE, 0, nullptr, CREATE_NEW, FILE_ATTRIBUTE_NORMAL, nullptr);
  if (h == INVALID_HANDLE_VALUE) return errno_of(GetLastError());
  *created = true;
  auto fail = [&](int e, bool close_it) {
    if (close_it) CloseHandle(h);
    DeleteFileW(w.c_str());
    return e;
  };
  if (fault) return fail(fault, true);
  size_t done = 0;
  while (done < bytes.size()) {
    DWORD n = 0;
    const DWORD want = DWORD(std::min<size_t>(bytes.size() - done, size_t(1) << 30));
    if (!WriteFile(h, bytes.data() + done, want, &n, nullptr)) return fail(errno_of(GetLastError()), true);
    if (n == 0) return fail(ENOSPC, true);
    done += n;
  }
  // Flushed before the rename: otherwise a crash can publish a name whose data never reached the disk.
  if (!FlushFileBuffers(h)) return fail(errno_of(GetLastError()), true);
  if (!CloseHandle(h)) return fail(errno_of(GetLastError()), false);
  return 0;
}

void sync_folder(const std::string&) {}

int rename_replace(const char* from, const char* to) {
  if (MoveFileExW(wide(from).c_str(), wide(to).c_str(), MOVEFILE_REPLACE_EXISTING | MOVEFILE_WRITE_THROUGH)) return 0;
  return errno_of(GetLastError());
}

void remove_file(const char* path) { DeleteFileW(wide(path).c_str()); }

// A folder cannot be locked with LockFileEx (no byte range): a named mutex keyed by the folder's
// identity (volume serial number and file index, the same whatever path names the folder) stands
// for the lock, for every process of the session.
FolderLock::FolderLock(const std::string& dir) {
  const std::wstring w = wide(dir.empty() ? "." : dir);
  HANDLE d = CreateFileW(w.c_str(), 0, FILE_SHARE_READ | FILE_SHARE_WRITE | FILE_SHARE_DELETE, nullptr, OPEN_EXISTING,
                         FILE_FLAG_BACKUP_SEMANTICS, nullptr);
  if (d == INVALID_HANDLE_VALUE)
    throw file_error(dir, "cannot open the folder (" + error_text(errno_of(GetLastError())) + ")");
  BY_HANDLE_FILE_INFORMATION info{};
  const bool known = GetFileInformationByHandle(d, &info);
  CloseHandle(d);
  if (!known) return;  // a file system without file ids: publish unlocked rather than not at all
  wchar_t name[96];
  swprintf(name, sizeof name / sizeof name[0], L"Local\\ahdpack-folder-%08lx-%08lx%08lx",
           static_cast<unsigned long>(info.dwVolumeSerialNumber), static_cast<unsigned long>(info.nFileIndexHigh),
           static_cast<unsigned long>(info.nFileIndexLow));
  HANDLE m = CreateMutexW(nullptr, FALSE, name);
  if (!m) throw file_error(dir, "cannot lock the folder (" + error_text(errno_of(GetLastError())) + ")");
  const DWORD r = WaitForSingleObject(m, INFINITE);
  if (r != WAIT_OBJECT_0 && r != WAIT_ABANDONED) {  // abandoned: its holder died; the lock is ours
    CloseHandle(m);
    throw file_error(dir, "cannot lock the folder (" + error_text(errno_of(GetLastError())) + ")");
  }
  handle_ = reinterpret_cast<intptr_t>(m);
}

FolderLock::~FolderLock() {
  if (handle_ == -1) return;
  HANDLE m = reinterpret_cast<HANDLE>(handle_);
  ReleaseMutex(m);
  CloseHandle(m);
}

namespace {

void (*volatile g_cleanup)() = nullptr;

// Runs on a thread of its own that Windows starts for the console event; returning FALSE passes
// the event on to the default handler, which ends the process (as the signal's default would).
BOOL WINAPI on_console_event(DWORD event) {
  if (event == CTRL_C_EVENT || event == CTRL_BREAK_EVENT || event == CTRL_CLOSE_EVENT) {
    if (auto f = g_cleanup) f();
  }
  return FALSE;
}

}  // namespace

InterruptCleanup::InterruptCleanup(void (*cleanup)()) {
  g_cleanup = cleanup;
  SetConsoleCtrlHandler(on_console_event, TRUE);
}

InterruptCleanup::~InterruptCleanup() {
  SetConsoleCtrlHandler(on_console_event, FALSE);
  g_cleanup = nullptr;
}

void signal_self(SelfSignal s) {
  if (s != SelfSignal::kKill)
    if (auto f = g_cleanup) f();
  // 128 + the POSIX signal number, as a shell reports a process killed by it.
  TerminateProcess(GetCurrentProcess(), s == SelfSignal::kInterrupt ? 130 : s == SelfSignal::kTerminate ? 143 : 137);
}

std::string executable_path() {
  std::wstring buf(MAX_PATH, L'\0');
  for (;;) {
    const DWORD n = GetModuleFileNameW(nullptr, buf.data(), DWORD(buf.size()));
    if (n == 0) return {};
    if (n < buf.size()) return utf8(buf.substr(0, n));
    buf.resize(buf.size() * 2);
  }
}

std::string module_path_of(const void* address) {
  HMODULE m = nullptr;
  if (!GetModuleHandleExW(GET_MODULE_HANDLE_EX_FLAG_FROM_ADDRESS | GET_MODULE_HANDLE_EX_FLAG_UNCHANGED_REFCOUNT,
                          static_cast<LPCWSTR>(address), &m))
    return {};
  std::wstring buf(MAX_PATH, L'\0');
  for (;;) {
    const DWORD n = GetModuleFileNameW(m, buf.data(), DWORD(buf.size()));
    if (n == 0) return {};
    if (n < buf.size()) return utf8(buf.substr(0, n));
    buf.resize(buf.size() * 2);
  }
}

bool stderr_is_terminal() { return ::_isatty(::_fileno(stderr)) != 0; }

void* load_module(const std::string& path, std::string* error) {
  // LOAD_WITH_ALTERED_SEARCH_PATH: the module's own dependencies are looked for beside it first.
  HMODULE m = LoadLibraryExW(wide(path).c_str(), nullptr, LOAD_WITH_ALTERED_SEARCH_PATH);
  if (!m) *error = path + ": cannot load (Windows error " + std::to_string(GetLastError()) + ")";
  return reinterpret_cast<void*>(m);
}

void* module_symbol(void* module, const char* name) {
  return reinterpret_cast<void*>(GetProcAddress(static_cast<HMODULE>(module), name));
}

}  // namespace ahd::os
#endif  // _WIN32
