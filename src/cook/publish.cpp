#include "cook/publish.h"

#include <algorithm>
#include <regex>

#include "containers/container.h"
#include "containers/sha256.h"
#include "core/error.h"
#include "files/file_io.h"
#include "files/manifest_file.h"
#include "files/output_set.h"
#include "pipeline/set_name.h"
#include "files/regular_file.h"
#include "pipeline/manifest.h"
#include "files/utf8_path.h"

namespace ahd {
namespace fs = std::filesystem;

OutputPaths output_paths(const std::string& out) {
  OutputPaths p;
  p.kind = container_kind_from_path(out);
  p.dir = fs_path(out).parent_path();
  p.name = utf8_string(fs_path(out).stem());
  const std::string problem = set_name_problem(p.name);
  if (!problem.empty()) throw file_error(out, "the set's name \"" + p.name + "\" " + problem);
  return p;
}

namespace {

// Plane files hashed for the clean-up are streamed (files/regular_file.h file_sha256); one larger than
// this is never ours to remove (kept).
constexpr uint64_t kMaxPlaneFileBytes = uint64_t(1) << 34;

// True when `path` is a regular file (not a symlink) of `size` bytes whose SHA-256 is `sha256`.
bool file_is(const fs::path& path, uint64_t size, const std::string& sha256) {
  try {
    uint64_t n = 0;
    return file_sha256(utf8_string(path), size, &n, true) == sha256 && n == size;
  } catch (const std::exception&) {
    return false;
  }
}

// The plane a file name NAME.<plane>.<ktx2|dds> of stem `name` names (package.h, stable_names), or "".
std::string stable_plane_of(const std::string& name, const std::string& file) {
  static const std::regex plane(R"(^\.(iz|dir|ratio|dirratio|coverage)\.(ktx2|dds)$)");
  std::smatch m;
  if (file.size() <= name.size() || file.compare(0, name.size(), name) != 0) return "";
  const std::string rest = file.substr(name.size());
  return std::regex_match(rest, m, plane) ? m[1].str() : "";
}

// The files of the previous set of `out` that a new set supersedes (evaluated with the folder
// locked). Only files ahdpack wrote for this stem go: a plane the previous NAME.json names when its
// name is package.h's plane_file_name for NAME (NAME.<plane>.<12 hex>.<ktx2|dds>, the hex the
// manifest's SHA-256 prefix) and the file's size and SHA-256 are the manifest's; and unnamed plane
// files of NAME that prove to be ours by their content hash. A stale or crafted manifest naming
// README.md or other.json, a plane edited since, a symlink: kept. A manifest without a valid
// SHA-256 per plane is refused by read_manifest_file, so its planes are kept too (nothing proves
// them ours).
std::vector<std::string> previous_set_files(const OutputPaths& out) {
  std::vector<std::string> files;
  const std::string manifest = out.sibling(".json");
  static const std::regex plane(R"(^\.(iz|dir|ratio|dirratio|coverage)\.([0-9a-f]{12})\.(ktx2|dds)$)");

  // NAME.<plane>.<12 hex>.<ext>: `rest` keeps the part after NAME that `m` points into.
  const auto plane_of_name = [&out](const std::string& fn, std::string* rest, std::smatch* m) {
    if (fn.size() <= out.name.size() || fn.compare(0, out.name.size(), out.name) != 0) return false;
    *rest = fn.substr(out.name.size());
    return std::regex_match(*rest, *m, plane);
  };
  std::error_code ec;
  if (fs::exists(fs_path(manifest), ec)) try {
      for (const ManifestPlane& p : read_manifest_file(manifest).planes) {
        std::string rest;
        std::smatch m;
        // NAME.<plane>.<ext> (--stable-names): ours when the manifest names it as that plane and
        // the file is the manifest's; a killed run never leaves one unnamed (they are annexes).
        const bool stable = stable_plane_of(out.name, p.file) == p.name;
        if (!stable && (!plane_of_name(p.file, &rest, &m) || m[1].str() != p.name ||
                        p.sha256.compare(0, 12, m[2].str()) != 0))
          continue;
        if (file_is(out.dir / fs_path(p.file), p.bytes, p.sha256)) files.push_back(utf8_string(out.dir / fs_path(p.file)));
      }
    } catch (const std::exception&) {
    }
  fs::directory_iterator it(out.dir.empty() ? fs::path(".") : out.dir, ec), end;
  for (; !ec && it != end; it.increment(ec)) {
    const std::string fn = utf8_string(it->path().filename());
    std::string rest;
    std::smatch m;
    if (!plane_of_name(fn, &rest, &m)) continue;
    // Already proven ours by the manifest's full SHA-256 above: not hashed a second time.
    if (std::find(files.begin(), files.end(), utf8_string(it->path())) != files.end()) continue;
    try {
      if (file_sha256(utf8_string(it->path()), kMaxPlaneFileBytes, nullptr, true).compare(0, 12, m[2].str()) == 0)
        files.push_back(utf8_string(it->path()));
    } catch (const std::exception&) {
    }
  }
  std::sort(files.begin(), files.end());
  files.erase(std::unique(files.begin(), files.end()), files.end());
  return files;
}

}  // namespace

void publish_conversion(const OutputPaths& out, std::vector<OutputFile> files, IntermediateFile intermediate) {
  OutputSet set;
  std::vector<FileToPublish> stable;
  const std::string manifest = out.name + ".json", report = out.name + ".report.json";
  for (OutputFile& f : files) {
    FileToPublish p{utf8_string(out.dir / fs_path(f.name)), std::move(f.bytes)};
    if (f.name == manifest) set.commit = std::move(p);
    else if (f.name == report) set.annexes.push_back(std::move(p));
    else if (!stable_plane_of(out.name, f.name).empty()) stable.push_back(std::move(p));
    else set.members.push_back(std::move(p));
  }
  // Stable plane names (--stable-names) cannot be content-addressed members: a new plane would
  // replace one the previous manifest names before the commit. They are published as annexes: the
  // previous files of those names are moved aside before the commit and the new ones renamed after
  // it, so a plane beside NAME.json is always the one it names (or missing after a kill), and an
  // error before the commit puts the previous ones back (docs/asset-cook.md "Stable names for engines").
  for (FileToPublish& p : stable) {
    set.annex_names.push_back(p.path);
    set.annexes.push_back(std::move(p));
  }
  if (set.commit.path.empty()) throw Error("publish_conversion: no " + manifest);
  set.annex_names.push_back(out.sibling(".report.json"));
  if (intermediate.bytes) set.annexes.push_back({out.sibling(".ahd.exr"), std::move(*intermediate.bytes)});
  if (!intermediate.keep_existing || intermediate.bytes) set.annex_names.push_back(out.sibling(".ahd.exr"));
  set.superseded = [&out] { return previous_set_files(out); };
  publish_output_set(set);
}

}  // namespace ahd
