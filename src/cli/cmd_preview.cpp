// ahdpack preview NAME.json [--source IN] [--layout …] [--mesh …] -o DIR/: a self-contained HTML page
// (no network) with PNGs beside it: every plane and mip level, irradiance for the surface normal and
// tilted normals, error heat maps against the source SH, the report's tables and the time per stage.
// IN and the input options as convert takes them (bakers/bake_input.h: the canonical EXR, a baker's
// set, a Godot project); --mesh is also the 3D view's mesh.
//
// HDR images are PNGs in the fixed log encoding of preview_images.h; the exposure slider rewrites
// the table of an SVG feComponentTransfer filter that every HDR <img> uses, so exposure works on
// file:// pages without reading pixels back (a canvas would be tainted there). The page records
// script errors and images that failed to load in <body data-status>, which the tests read.
//
// The folder is written whole or not at all: everything goes to a hidden temporary folder beside
// DIR, renamed to DIR at the end. An existing DIR is replaced only when it is empty or an earlier
// preview (it holds the marker file), never any other folder. The temporary folder is removed on
// every failure, and on SIGINT/SIGTERM: they raise the CLI's interrupt flag (progress.h), checked
// between the files, and the preview then stops as a failure does ("cancelled: nothing was written").
//
// The report is untrusted text: read_report_file bounds its size and nesting, and every value of it
// reaches the page through one escaping function (markup.h html_escape).

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/conversion_args.h"
#include "cli/conversion_view.h"
#include "cli/preview_3d.h"
#include "cli/preview_html.h"
#include "cli/preview_images.h"
#include "cli/progress.h"
#include "cli/report_file.h"
#include "core/error.h"
#include "fit/ahd_decode.h"
#include "image/image_io.h"
#include "files/os_files.h"
#include "files/output_set.h"
#include "files/utf8_path.h"

namespace ahd::cli {
namespace fs = std::filesystem;

namespace {

constexpr const char* kMarker = ".ahdpack-preview";

struct PreviewArgs {
  std::string manifest, out;
  // --source and the input options: what convert read. source.mesh and source.uv_set are also the
  // 3D view's mesh (preview_3d.h; "" = the sample's plane).
  BakeInput source;
};

// The source's pages as convert read them. A canonical EXR holds its own normals and coverage, so
// --mesh (and --uv-set) beside it give the 3D view's mesh only, as before the input options.
std::vector<ShImage> read_preview_source(const PreviewArgs& a, const Manifest& m, std::string* described,
                                         BakeInput* read_as) {
  BakeInput in = a.source;
  resolve_auto_layout(&in);
  if (in.layout.empty()) in.mesh.clear(), in.uv_set = -1;
  return read_source_for(in, m, described, read_as);
}

// Irradiance of level 0 for one tangent-space unit normal.
std::vector<float> irradiance(const DecodedPlanes& p, const double n[3], double dz_min) {
  std::vector<float> e(size_t(p.width) * p.height * 3);
  for (size_t i = 0; i < e.size() / 3; ++i) {
    double o[3];
    decode_irradiance(&p.iz[i * 3], &p.d[i * 3], &p.ratio[i * 3], n, dz_min, o);
    for (int c = 0; c < 3; ++c) e[i * 3 + c] = float(o[c]);
  }
  return e;
}

// Removes a temporary folder unless released (any failure before the final rename).
struct TempDir {
  fs::path path;
  bool keep = false;
  ~TempDir() {
    std::error_code ec;
    if (!keep && !path.empty()) fs::remove_all(path, ec);
  }
};

// Moves the finished folder `tmp` to `out`, replacing an empty folder or an earlier preview.
void publish_folder(const fs::path& tmp, const fs::path& out) {
  std::error_code ec;
  if (fs::exists(out, ec)) {
    if (!fs::is_directory(out, ec)) throw file_error(utf8_string(out), "exists and is not a folder");
    const bool ours = fs::exists(out / kMarker, ec) || fs::is_empty(out, ec);
    if (!ours) throw file_error(utf8_string(out), "exists and is not an ahdpack preview folder (nothing was replaced)");
    const fs::path old = out.parent_path() / fs_path("." + utf8_string(out.filename()) + ".ahdtmp-" + std::to_string(os::process_id()) + "-old");
    fs::rename(out, old, ec);
    if (ec) throw file_error(utf8_string(out), "cannot replace: " + ec.message());
    fs::rename(tmp, out, ec);
    if (ec) {
      std::error_code ec2;
      fs::rename(old, out, ec2);
      throw file_error(utf8_string(out), "cannot write: " + ec.message());
    }
    fs::remove_all(old, ec);
    return;
  }
  fs::rename(tmp, out, ec);
  if (ec) throw file_error(utf8_string(out), "cannot write: " + ec.message());
}

// Stops the preview at the next file once SIGINT/SIGTERM arrived (the temporary folder goes).
void check_interrupt() {
  if (interrupt_flag()->load()) throw Cancelled();
}

void run_preview(const PreviewArgs& a) {
  install_interrupt_handler();
  const ConversionView v = read_conversion(a.manifest);
  const Manifest& m = v.manifest;
  PreviewPage page;
  page.name = utf8_string(fs_path(a.manifest).stem());
  page.manifest = m;
  fs::path report_path = fs_path(a.manifest).parent_path() / fs_path(page.name + ".report.json");
  std::error_code ec;
  if (fs::exists(report_path, ec)) page.report = read_report_file(utf8_string(report_path));
  const bool has_source = !a.source.input.empty();
  std::string described;
  std::vector<ShImage> pages;  // the source's pages; the page shows (and compares) array layer 0
  BakeInput read_as = a.source;  // the source as read (its scene loaded), for the 3D view's placed scene
  if (has_source) pages = read_preview_source(a, m, &described, &read_as);

  if (a.out.empty()) throw Error("-o needs a folder name");
  fs::path out = fs::absolute(fs_path(a.out)).lexically_normal();
  if (!out.has_filename()) out = out.parent_path();  // "DIR/" or "."
  if (!fs::is_directory(out.parent_path(), ec)) {
    fs::path given = fs_path(a.out).lexically_normal();  // named as the user gave it
    if (!given.has_filename()) given = given.parent_path();
    throw file_error(given.has_parent_path() ? utf8_string(given.parent_path()) : ".", "no such folder");
  }
  TempDir tmp{out.parent_path() / fs_path("." + utf8_string(out.filename()) + ".ahdtmp-" + std::to_string(os::process_id()) + "-preview")};
  fs::remove_all(tmp.path, ec);
  if (!fs::create_directory(tmp.path, ec))
    throw file_error(utf8_string(out), "cannot create its temporary folder beside it (" + ec.message() + ")");

  // Files inside the temporary folder are new files: the folder's rename publishes them all.
  auto write = [&](const std::string& file, const std::vector<uint8_t>& bytes) {
    check_interrupt();
    write_new_file(utf8_string(tmp.path / fs_path(file)), bytes);
  };
  auto png = [&](const std::string& file, const ImageF& img) { write(file, encode_image(utf8_string(tmp.path / fs_path(file)), img)); };
  const DecodedPlanes& l0 = v.levels[0];
  const double white = white_point(l0.iz);
  page.white = white;
  for (size_t l = 0; l < v.levels.size(); ++l) {
    const DecodedPlanes& p = v.levels[l];
    const std::string s = "_L" + std::to_string(l) + ".png";
    png("iz" + s, log_encode(p.iz, p.width, p.height, white));
    if (m.directional) {
      png("dir" + s, direction_colours(p.d, p.width, p.height));
      png("ratio" + s, ratio_image(p.ratio, p.width, p.height));
    }
    page.level_sizes.push_back({p.width, p.height});
  }
  const double t = std::sqrt(0.5);
  const struct {
    const char* file;
    const char* caption;
    double n[3];
  } normals[] = {{"irr_normal.png", "surface normal (0, 0, 1)", {0, 0, 1}},
                 {"irr_tilt_px.png", "tilted 45° toward +x (tangent)", {t, 0, t}},
                 {"irr_tilt_nx.png", "tilted 45° toward −x", {-t, 0, t}},
                 {"irr_tilt_py.png", "tilted 45° toward +y (bitangent)", {0, t, t}},
                 {"irr_tilt_ny.png", "tilted 45° toward −y", {0, -t, t}}};
  for (const auto& n : normals) {
    png(n.file, log_encode(irradiance(l0, n.n, m.dz_min), l0.width, l0.height, white));
    page.irradiance.push_back({n.file, n.caption});
  }
  if (has_source) {
    const TexelErrorMaps e = texel_error_maps(pages[0], l0, m.dz_min);
    png("error_normal.png", heat_map(e.normal, l0.width, l0.height, kHeatLoExp, kHeatHiExp));
    png("error_hemisphere.png", heat_map(e.hemisphere, l0.width, l0.height, kHeatLoExp, kHeatHiExp));
    page.source = described + (pages.size() > 1 ? "; page 0 (array layer 0) shown" : "");
    page.error_normal = summarise_map(e.normal);
    page.error_hemisphere = summarise_map(e.hemisphere);
  }
  // The 3D view's A/B takes a single-page source (its coverage and polynomials are of page 0).
  const ShImage* sh3d = pages.size() == 1 ? &pages[0] : nullptr;
  // A placed scene (a Godot project, --mesh with --placement) puts each instance at its rectangle.
  const PlacedSceneMesh placed = bake_placed_mesh(read_as);
  page.view3d_html = write_preview_3d(tmp.path, {a.manifest, a.source.mesh, a.source.uv_set, sh3d, &placed});
  const std::string html = preview_html(page), marker = "written by ahdpack preview\n";
  write("index.html", std::vector<uint8_t>(html.begin(), html.end()));
  write(kMarker, std::vector<uint8_t>(marker.begin(), marker.end()));
  check_interrupt();
  publish_folder(tmp.path, out);
  tmp.keep = true;
  std::printf("ahdpack preview: %s -> %s/index.html (%zu level(s)%s)\n", a.manifest.c_str(), utf8_string(out).c_str(),
              v.levels.size(), has_source ? ", error heat maps against the source" : "");
}

}  // namespace

void add_preview_command(CLI::App& app) {
  auto a = std::make_shared<PreviewArgs>();
  CLI::App* c = app.add_subcommand("preview", "Write an HTML page (no network) showing a conversion: planes, mips, "
                                              "irradiance, error heat maps, report");
  c->add_option("manifest", a->manifest, "NAME.json written by convert")->required();
  c->add_option("--source", a->source.input,
                "The source SH for the error heat maps, as convert read it: the canonical EXR or any file of a "
                "baker's set (with the same --layout, --normals, --mesh… as the conversion); --mesh is also the mesh "
                "(.glb/.gltf/.obj) the 3D view lights (default: the sample's plane)");
  add_input_options(c, &a->source);
  c->add_option("-o,--output", a->out, "Output folder (replaced if it holds an earlier preview)")->required();
  c->callback([a]() { run_preview(*a); });
}

}  // namespace ahd::cli
