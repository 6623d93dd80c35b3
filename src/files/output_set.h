// Publishing files whole: a conversion's set (planes, manifest, report, intermediate), or one file
// (`compress`, `decode`, …). Under the final names there is at every instant either the previous
// content or the new one, complete, whatever fails and wherever the process dies. The one place
// that writes a final output name: every writer of the CLI goes through it.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "pipeline/package.h"  // plane_file_name: how members are content-addressed

namespace ahd {

struct FileToPublish {
  std::string path;            // final path
  std::vector<uint8_t> bytes;  // complete content
};

// One set, in the three roles its files play (see publish_output_set for why each role is
// published when it is).
struct OutputSet {
  // Content-addressed files (the planes, package.h's plane_file_name): a new member never replaces
  // a file the previous commit names unless its bytes are identical. Renamed before the commit.
  std::vector<FileToPublish> members;
  // The file that makes the set what it is (the manifest, NAME.json): its rename is the commit.
  FileToPublish commit;
  // Fixed-name files that describe the commit (NAME.report.json, NAME.ahd.exr). Renamed after it.
  std::vector<FileToPublish> annexes;
  // Every fixed name an annex of this set may have (full paths), whether or not this publish has
  // it: the previous set's files of those names are retired (moved aside before the commit,
  // deleted after it), so an annex beside a manifest always belongs to that manifest.
  std::vector<std::string> annex_names;
  // Called once the set's folder is locked, before any rename: the files of the previous set to
  // remove once the new commit is in place (files this set publishes are never removed).
  std::function<std::vector<std::string>()> superseded;
};

// Publishes `set`; all its files must be in one folder (created if missing). Steps:
//  1. lock the folder (flock on the folder itself, held to the end: concurrent publishers into one
//     folder, other processes or threads, take turns, so each sees the set the previous one left
//     and `superseded` never names a file another run's manifest still needs);
//  2. remove stale temporaries of dead processes; evaluate `superseded`;
//  3. write every file under a temporary name in the folder (".<name>.ahdtmp-<pid>-<random>.<ext>",
//     every write, fsync and close checked: a full disk or a file-size limit is an error, never a
//     short file);
//  4. rename the members; move the previous annexes aside (to temporary names);
//  5. rename the commit — the commit point;
//  6. rename the annexes; delete the moved-aside annexes; fsync the folder; remove `superseded`.
// Why any kill leaves a consistent folder: before step 5 the old commit names only old members,
// all still present (new members are content-addressed, so they replaced nothing of the old set),
// and no annex beside it is new (new annexes are still temporaries); at worst an old annex was
// moved aside and is missing. From step 5 on, the new commit names only new members, all renamed,
// and every annex beside it is new or missing (the old ones were moved aside first). A report or an
// intermediate therefore never sits beside a manifest of another run; it may be missing after a
// kill, which readers treat as "not written". Leftovers of a kill (temporaries, moved-aside annexes,
// new members of an uncommitted set) are temporaries or unnamed members that the next publish
// removes (stale temporaries by name; unnamed members by the caller's `superseded`).
// On an error, or SIGINT/SIGTERM during the call, everything done is undone before the commit:
// temporaries and new members removed, moved-aside annexes moved back (a signal then re-raises,
// so the process still dies of it). After the commit, an error (an annex rename) leaves the new set
// without that annex and throws.
// Throws ahd::Error("<file>: <cause>") naming the file that failed (a folder in the way, read-only
// folder, full disk...). Thread-safe (one publish at a time per process: the signal clean-up keeps
// one process-wide list). Test hooks: AHDPACK_TEST_KILL_BEFORE_RENAME=k sends SIGKILL ("k:INT": SIGINT,
// "k:TERM": SIGTERM) just before the k-th rename (0-based, counting every rename above: members, annexes moved aside, commit,
// annexes); k = the number of renames kills after the last one, before the clean-up.
// AHDPACK_TEST_WRITE_FAULT="k:ENOSPC|EROFS|EACCES|EIO" fails the write of the k-th file (members,
// commit, annexes in that order) after its temporary was created.
void publish_output_set(const OutputSet& set);

// The earlier form: files[0..n-2] are members, files[n-1] the commit, `superseded` fixed.
void publish_output_set(const std::vector<FileToPublish>& files, const std::vector<std::string>& superseded = {});

// One file on its own (a commit without members or annexes, and no folder lock: concurrent writers
// of one file leave one of their files whole). Creates the folder. Throws ahd::Error naming it.
void publish_file(const std::string& path, std::vector<uint8_t> bytes);

// publish_file of bytes or text (the form write_image of image/image_io.h uses too).
void write_file_atomic(const std::string& path, std::vector<uint8_t> bytes);
void write_file_atomic(const std::string& path, const std::string& text);


// Writes a file that must not exist yet, every write, the fsync and the close checked (a full disk
// is an error, never a short file); on failure removes it and throws ahd::Error naming `path`. No
// temporary and no rename: for files inside a folder that is itself a temporary, published whole
// by its caller (preview).
void write_new_file(const std::string& path, const std::vector<uint8_t>& bytes);

// Removes temporaries (".*.ahdtmp-<pid>-*") in `dir` whose process no longer runs. Returns how
// many were removed. Never throws.
size_t remove_stale_temporaries(const std::string& dir);

// True when `filename` (no folder) is one of our temporary names.
bool is_temporary_name(const std::string& filename);

}  // namespace ahd
