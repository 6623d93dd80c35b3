#include "files/input_record.h"
#include "files/utf8_path.h"

#include <algorithm>
#include <filesystem>

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

int probe_type(const std::string& path) {
  std::error_code ec;
  const std::filesystem::file_status st = std::filesystem::status(fs_path(path), ec);
  return ec ? int(std::filesystem::file_type::not_found) : int(st.type());
}

namespace {
int probe(const std::string& path) {
  const int type = probe_type(path);
  InputRecord* r = current_record;
  if (r && std::none_of(r->probes.begin(), r->probes.end(), [&](const InputProbe& p) { return p.path == path; }))
    r->probes.push_back({path, type});
  return type;
}
}  // namespace

bool probe_input_file(const std::string& path) {
  const int t = probe(path);
  return t != int(std::filesystem::file_type::not_found) && t != int(std::filesystem::file_type::none);
}

bool probe_regular_file(const std::string& path) { return probe(path) == int(std::filesystem::file_type::regular); }

}  // namespace ahd
