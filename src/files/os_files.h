// The operating system under the file edge: the few calls whose POSIX and Win32 forms differ, one
// file per system (files/os_files_posix.cpp, files/os_files_win32.cpp), listed in
// docs/platforms.md "POSIX-only code on the file edge". Paths are UTF-8 (std::string); the Win32
// forms convert them to UTF-16 and call the wide APIs, so drive letters, backslashes and non-ASCII
// names work there. Errors are errno values (ENOENT, ENOSPC, …; the Win32 forms map GetLastError
// to them) for the callers' messages.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ahd::os {

// This process's id (getpid / GetCurrentProcessId): the temporaries' names carry it.
long process_id();

// False only when no process `pid` runs (kill(pid, 0) fails with ESRCH / OpenProcess fails, or the
// process has exited): another writer's temporaries are kept while it may still be writing.
bool process_may_run(long pid);

// The text of an errno value.
std::string error_text(int e);

// A file opened for reading. `fd` is a descriptor of the C runtime (open / _wopen).
struct ReadFile {
  int fd = -1;
  ~ReadFile();
  ReadFile() = default;
  ReadFile(const ReadFile&) = delete;
  ReadFile& operator=(const ReadFile&) = delete;
};

// stat of a path (following symlinks): 0 with *regular and *size set, else the errno value (ENOENT,
// ENOTDIR, ELOOP, …).
int path_status(const std::string& path, bool* regular, uint64_t* size);

// Opens `path` for reading without blocking on a FIFO, without following a symlink when
// `no_symlink`, never as a controlling terminal: 0 or the errno value.
int open_for_reading(const std::string& path, bool no_symlink, ReadFile* f);

// fstat of the open file: 0 with *regular and *size set, else the errno value.
int file_status(const ReadFile& f, bool* regular, uint64_t* size);

// Reads up to n bytes: the count (0 at the end), or -1 with errno set (EINTR: retry).
long read_some(const ReadFile& f, uint8_t* out, size_t n);

// Creates `path` (which must not exist), writes `bytes`, flushes it to the disk (fsync /
// FlushFileBuffers) and closes it, every step checked. `fault` (a test hook's errno value, or 0)
// fails the write after the file was created. On failure removes the file and returns the errno
// value; *created tells whether the file had been created (the cause then lies in the write).
int write_new_synced(const std::string& path, const std::vector<uint8_t>& bytes, int fault, bool* created);

// Flushes a folder's entries to the disk, best effort (fsync of the folder; nothing on Windows,
// whose MoveFileEx with MOVEFILE_WRITE_THROUGH already flushed the rename).
void sync_folder(const std::string& dir);

// Renames `from` to `to`, replacing `to` atomically when it exists (rename /
// MoveFileExW(MOVEFILE_REPLACE_EXISTING | MOVEFILE_WRITE_THROUGH)): 0 or the errno value.
// Async-signal-safe on POSIX (called from the interrupt clean-up).
int rename_replace(const char* from, const char* to);

// Removes a file; async-signal-safe on POSIX (called from the interrupt clean-up).
void remove_file(const char* path);

// An exclusive lock on a folder for other processes and threads (flock on the folder itself / a
// named mutex keyed by the folder's volume and file index), held until destruction. A file system
// without locks publishes unlocked. Throws ahd::Error("<dir>: <cause>") when the folder cannot be
// opened or the lock fails otherwise.
class FolderLock {
 public:
  explicit FolderLock(const std::string& dir);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  intptr_t handle_ = -1;
};

// While one exists, SIGINT and SIGTERM (Ctrl+C, Ctrl+Break, closing the console on Windows) first
// call `cleanup` (which may use only rename_replace and remove_file) and then end the process as
// the signal would have. The previous handlers come back on destruction. One at a time per process.
class InterruptCleanup {
 public:
  explicit InterruptCleanup(void (*cleanup)());
  ~InterruptCleanup();
  InterruptCleanup(const InterruptCleanup&) = delete;
  InterruptCleanup& operator=(const InterruptCleanup&) = delete;

 private:
  void* saved_ = nullptr;
};

// What a test hook makes this process undergo: killed outright, or interrupted (the clean-up of an
// InterruptCleanup runs first).
enum class SelfSignal { kKill, kInterrupt, kTerminate };
void signal_self(SelfSignal s);

// Where the running program is (/proc/self/exe, GetModuleFileNameW), or "" when unknown.
std::string executable_path();

// The file of the executable or shared library that holds the code at `address` (dladdr,
// GetModuleHandleExW(FROM_ADDRESS) + GetModuleFileNameW), or "" when unknown.
std::string module_path_of(const void* address);

// Whether stderr is a terminal (isatty / _isatty): progress lines are drawn only there.
bool stderr_is_terminal();

// Loads a shared library (dlopen RTLD_NOW | RTLD_LOCAL / LoadLibraryExW): its handle, or null with
// *error naming the path and the cause. Never unloaded.
void* load_module(const std::string& path, std::string* error);

// The address of `name` in a module load_module returned (dlsym / GetProcAddress), or null.
void* module_symbol(void* module, const char* name);

}  // namespace ahd::os
