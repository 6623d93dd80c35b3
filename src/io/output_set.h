// Publishing the files of one conversion as a whole: either the previous set or the new one is
// complete under the final names at every instant, whatever fails and wherever the process dies.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "pipeline/package.h"  // plane_file_name

namespace ahd {

struct FileToPublish {
  std::string path;            // final path
  std::vector<uint8_t> bytes;  // complete content
};

// Writes every file under a recognisable temporary name in its final folder
// (".<name>.ahdtmp-<pid>-<random>.<ext>", fsync'd), then renames them in the order given (put the
// manifest last: it is the commit point) and fsyncs each folder, then removes `superseded` (files
// of the previous set that the new one no longer names). First removes stale temporaries that an
// earlier killed run left in those folders (their process is gone). Temporaries are removed on any
// failure and on SIGINT/SIGTERM during the call.
//
// Why the set stays consistent across a kill between two renames: plane files are content-addressed
// (plane_file_name), so a new plane never replaces a plane of the previous set unless its bytes are
// identical; until the manifest is renamed the old manifest names only old files, all still present.
// After it, the new manifest names only new files, all already renamed. Files renamed before a
// failure are removed again unless they replaced an existing file. Each manifest also records every
// plane's byte size and SHA-256, verified by every reader, so a set mixed by any other means is
// reported, never decoded.
//
// Throws ahd::Error("<file>: <cause>") naming the file that failed (a folder in the way, read-only
// folder, full disk...). Test hook: AHDPACK_TEST_KILL_BEFORE_RENAME=k sends SIGKILL to this process
// just before the k-th rename (0-based); k = files.size() kills after the last rename, before the
// superseded files are removed.
void publish_output_set(const std::vector<FileToPublish>& files, const std::vector<std::string>& superseded = {});


// Files of folder `dir` named like a plane of conversion `name` (NAME.<plane>[.<hash>].<ktx2|dds>)
// other than those in `keep` (full paths): what a new set of that conversion supersedes.
std::vector<std::string> superseded_planes(const std::string& dir, const std::string& name,
                                           const std::vector<FileToPublish>& keep);

// Removes temporaries (".*.ahdtmp-<pid>-*") in `dir` whose process no longer runs. Returns how
// many were removed. Never throws.
size_t remove_stale_temporaries(const std::string& dir);

// True when `filename` (no folder) is one of our temporary names.
bool is_temporary_name(const std::string& filename);

}  // namespace ahd
