#include "cook/publish.h"

#include <regex>

#include "containers/container.h"
#include "containers/sha256.h"
#include "core/error.h"
#include "files/file_io.h"
#include "files/manifest_file.h"
#include "files/output_set.h"
#include "pipeline/manifest.h"

namespace ahd {
namespace fs = std::filesystem;

OutputPaths output_paths(const std::string& out) {
  OutputPaths p;
  p.kind = container_kind_from_path(out);
  p.dir = fs::path(out).parent_path();
  p.name = fs::path(out).stem().string();
  if (!is_plain_file_name(p.name) || !is_plain_file_name(p.name + ".json"))
    throw file_error(out, "the set's name \"" + p.name +
                              "\" would make file names decode refuses (it must not be empty, start with '.' or "
                              "hold '/', '\\' or ':')");
  return p;
}

namespace {

// The files of the previous set of `out` that a new set supersedes (evaluated with the folder
// locked): those its manifest names (none when it is missing or unreadable: nothing else is known
// to be ours) and unnamed plane files that prove to be ours by their content hash.
std::vector<std::string> previous_set_files(const OutputPaths& out) {
  std::vector<std::string> files;
  const std::string manifest = out.sibling(".json");
  std::error_code ec;
  if (fs::exists(manifest, ec)) try {
      for (const ManifestPlane& p : read_manifest_file(manifest).planes) files.push_back((out.dir / p.file).string());
    } catch (const std::exception&) {
    }
  static const std::regex plane(R"(^\.(iz|dir|ratio|dirratio|coverage)\.([0-9a-f]{12})\.(ktx2|dds)$)");
  fs::directory_iterator it(out.dir.empty() ? "." : out.dir, ec), end;
  for (; !ec && it != end; it.increment(ec)) {
    const std::string fn = it->path().filename().string();
    std::smatch m;
    const std::string rest = fn.size() > out.name.size() && fn.compare(0, out.name.size(), out.name) == 0
                                 ? fn.substr(out.name.size())
                                 : std::string();
    if (rest.empty() || !std::regex_match(rest, m, plane)) continue;
    try {
      const std::vector<uint8_t> bytes = read_file_bytes(it->path().string());
      if (sha256_hex(bytes.data(), bytes.size()).compare(0, 12, m[2].str()) == 0) files.push_back(it->path().string());
    } catch (const std::exception&) {
    }
  }
  return files;
}

}  // namespace

void publish_conversion(const OutputPaths& out, std::vector<OutputFile> files, IntermediateFile intermediate) {
  OutputSet set;
  const std::string manifest = out.name + ".json", report = out.name + ".report.json";
  for (OutputFile& f : files) {
    FileToPublish p{(out.dir / f.name).string(), std::move(f.bytes)};
    if (f.name == manifest) set.commit = std::move(p);
    else if (f.name == report) set.annexes.push_back(std::move(p));
    else set.members.push_back(std::move(p));
  }
  if (set.commit.path.empty()) throw Error("publish_conversion: no " + manifest);
  set.annex_names.push_back(out.sibling(".report.json"));
  if (intermediate.bytes) set.annexes.push_back({out.sibling(".ahd.exr"), std::move(*intermediate.bytes)});
  if (!intermediate.keep_existing || intermediate.bytes) set.annex_names.push_back(out.sibling(".ahd.exr"));
  set.superseded = [&out] { return previous_set_files(out); };
  publish_output_set(set);
}

}  // namespace ahd
