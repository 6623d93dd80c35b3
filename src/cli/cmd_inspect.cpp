// ahdpack inspect FILE: what a container (or a manifest) holds.
#include <cstdio>
#include <filesystem>

#include "files/manifest_file.h"
#include "cli/commands.h"
#include "files/container_file.h"
#include "core/error.h"

#include "pipeline/manifest.h"
#include "files/utf8_path.h"

namespace ahd::cli {
namespace fs = std::filesystem;

namespace {

void inspect_texture(const std::string& path) {
  const Texture t = read_container_file(path);
  const FormatInfo& f = format_info(t.format);
  std::printf("%s: %s, vkFormat %u, DXGI %u, %zu level(s)\n", path.c_str(), f.name, f.vk_format, f.dxgi_format,
              t.levels.size());
  for (size_t l = 0; l < t.levels.size(); ++l)
    std::printf("  level %zu: %ux%u, %zu bytes\n", l, t.levels[l].width, t.levels[l].height, t.levels[l].data.size());
  for (const auto& [k, v] : t.metadata) std::printf("  %s = %s\n", k.c_str(), v.c_str());
}

void run_inspect(const std::string& path) {
  if (fs_path(path).extension() == ".json") {
    const Manifest m = read_manifest_file(path);
    std::printf("%s: manifest v%d, profile %s, %ux%u, %u level(s), ratio %s, dz_min %g, direction %s (%s)\n",
                path.c_str(), m.version, m.profile.c_str(), m.width, m.height, m.levels,
                m.ratio_form == RatioForm::Rgb ? "rgb" : "luminance", m.dz_min, m.direction_encoding.c_str(),
                m.direction_frame.c_str());
    for (const auto& p : m.planes) {
      read_manifest_plane(path, p);  // size and SHA-256 as the manifest records them
      inspect_texture(utf8_string(fs_path(path).parent_path() / fs_path(p.file)));
    }
    return;
  }
  inspect_texture(path);
}

}  // namespace

void add_inspect_command(CLI::App& app) {
  auto path = std::make_shared<std::string>();
  CLI::App* c = app.add_subcommand("inspect", "Print what a KTX2/DDS file or a conversion manifest holds");
  c->add_option("file", *path, "FILE.ktx2, FILE.dds or NAME.json")->required();
  c->callback([path]() { run_inspect(*path); });
}

}  // namespace ahd::cli
