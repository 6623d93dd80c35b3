// The record of every file a conversion reads: ONE list, filled at the io edge, that `convert
// --depfile` writes and `convert --cache` / `--print-key` hash, so the two can never disagree.
//
// How it works: the caller opens a RecordInputs scope on its thread; every file reader (src/files,
// image, bakers, scene) calls note_input_file(path) when it opens a file (after the open succeeded). Outside a scope the call
// does nothing, so readers need no extra parameter and callers that don't care pay nothing.
//
// Hooking in a new reader (a .tscn, .glb, .unwrap_cache…): call note_input_file(path) next to the
// open — for Assimp, scene/mesh_io.h's import_mesh_file reads the files a scene pulls in (a
// .gltf's .bin) through the opener, so they are noted too — and test for optional files with probe_input_file /
// probe_regular_file below instead of std::filesystem. A read that is not noted is a bug: the
// depfile would miss it (no rebuild when it changes) and the cache key would not cover it (a stale
// hit); an existence test that is not probed lets `--cache` reuse a conversion after the file
// appeared. The test Cook.GodotAtlasDepfileNamesEveryFileRead compares the depfile with what strace
// saw the process open, for the Godot set; add a case there for a new reader.
//
// The scope is per thread: a batch converts files on several threads at once, each with its own
// record. Reading happens on the thread that opened the scope (the io readers parallelise over rows
// of data already opened, never over opens).
#pragma once
#include <ahd/bakers.h>

#include <string>
#include <vector>

namespace ahd {

// InputProbe (<ahd/bakers.h>): an existence test a reader's decision rests on.

struct InputRecord {
  // Files in the order first read, each once, as the reader named them (relative paths stay
  // relative to the working directory).
  std::vector<std::string> files;
  // Existence tests in the order made, each path once (its first result).
  std::vector<InputProbe> probes;
};

// Opens a recording scope on this thread; scopes nest (the inner one records, then the outer one
// is current again). Not copyable.
class RecordInputs {
 public:
  explicit RecordInputs(InputRecord* record);
  ~RecordInputs();
  RecordInputs(const RecordInputs&) = delete;
  RecordInputs& operator=(const RecordInputs&) = delete;

 private:
  InputRecord* previous_;
};

// Adds `path` to this thread's current record (once; later reads of the same path are not added
// again). No-op outside a RecordInputs scope. Never throws except std::bad_alloc.
void note_input_file(const std::string& path);

// std::filesystem::exists / is_regular_file that also note the test in the current record. Readers
// use these (not std::filesystem) wherever a file's presence changes what is read or how: a test
// not noted would let `--cache` reuse a conversion after a file appeared that a new run would read.
// Never throw (an unreadable path counts as absent).
bool probe_input_file(const std::string& path);
bool probe_regular_file(const std::string& path);

// The type a path has now, as InputProbe::type records it.
int probe_type(const std::string& path);

}  // namespace ahd
