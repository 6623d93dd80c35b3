#include "io/input_record.h"

#include <algorithm>

namespace ahd {

namespace {
thread_local InputRecord* current_record = nullptr;
}

RecordInputs::RecordInputs(InputRecord* record) : previous_(current_record) { current_record = record; }

RecordInputs::~RecordInputs() { current_record = previous_; }

void note_input_file(const std::string& path) {
  InputRecord* r = current_record;
  if (!r) return;
  // A conversion reads a few dozen files at most (a 64-page atlas's images): a linear scan is fine.
  if (std::find(r->files.begin(), r->files.end(), path) == r->files.end()) r->files.push_back(path);
}

}  // namespace ahd
