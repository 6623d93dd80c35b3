// The 3D view of `ahdpack preview` (preview_3d.h). What it writes:
//   three_classic.js  three.js's two ES modules (build/three.core.js + three.module.js) joined into
//                     one classic script that sets window.THREE: a page opened from file:// may not
//                     load module scripts (origin null), classic ones it may.
//   view3d_data.js    window.AHD_VIEW = {...}: every page and mip level of the decoded planes
//                     (float32, base64), the source SH as irradiance polynomials, coverage, the fit
//                     rules per texel, the mesh, and formats/shaders/ahd_decode.glsl's text, which
//                     the page's shader pastes in unchanged.
//   view3d.js, view3d.html  copied from formats/preview/ (the page's title is the only value put
//                     into its HTML, escaped).
#include "cli/preview_3d.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <nlohmann/json.hpp>

#include "cli/markup.h"
#include "core/error.h"
#include "fit/ahd_fit.h"
#include "files/file_io.h"
#include "files/output_set.h"
#include "scene/mesh_io.h"
#include "files/paths.h"
#include "scene/lightmap_raster.h"
#include "files/utf8_path.h"

namespace ahd::cli {
namespace fs = std::filesystem;

namespace {

// The page holds float32 copies of every level plus the source SH (about 230 bytes per texel of
// level 0 in base64): 512² is ~60 MB, the most a browser tab loads comfortably.
constexpr size_t kMaxTexels = size_t(512) * 512;

std::string base64(const void* data, size_t n) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* b = static_cast<const uint8_t*>(data);
  std::string o;
  o.reserve((n + 2) / 3 * 4);
  for (size_t i = 0; i < n; i += 3) {
    const uint32_t v = uint32_t(b[i]) << 16 | (i + 1 < n ? uint32_t(b[i + 1]) << 8 : 0) | (i + 2 < n ? b[i + 2] : 0);
    o += k[v >> 18 & 63], o += k[v >> 12 & 63];
    o += i + 1 < n ? k[v >> 6 & 63] : '=';
    o += i + 2 < n ? k[v & 63] : '=';
  }
  return o;
}
template <class T>
std::string b64(const std::vector<T>& v) { return base64(v.data(), v.size() * sizeof(T)); }

std::string read_text(const fs::path& p) {
  const std::vector<uint8_t> b = read_file_bytes(utf8_string(p), size_t(64) << 20);
  return std::string(b.begin(), b.end());
}

// three.core.js ends with one `export { … };` line; three.module.js imports from three.core.js
// and re-exports it on its first lines and ends with its own export line. Each file becomes a
// function of its own (their private top-level names collide) returning its exports; the module's
// imports are taken from the core's. No aliases (`as`) occur in r187; a layout that differs is
// refused (the 3D view is then left out with the reason).
std::string classic_three(const fs::path& three) {
  std::string out = "(function () {\n'use strict';\n";
  for (const char* file : {"three.core.js", "three.module.js"}) {
    const fs::path path = three / "build" / fs_path(file);
    const std::string src = read_text(path);
    std::string body, exports, imports;
    size_t pos = 0;
    while (pos < src.size()) {
      size_t end = src.find('\n', pos);
      if (end == std::string::npos) end = src.size();
      const std::string line = src.substr(pos, end - pos);
      pos = end + 1;
      const bool imp = line.rfind("import {", 0) == 0, exp = line.rfind("export {", 0) == 0;
      if (imp || exp) {
        if (line.find(" as ") != std::string::npos) throw file_error(utf8_string(path), "renames an import or export (unsupported three.js layout)");
        const std::string names = line.substr(8, line.rfind('}') - 8);
        if (imp) imports += names + ",";
        else if (line.find(" from ") == std::string::npos) exports += names + ",";
        continue;
      }
      if (line.rfind("import ", 0) == 0 || line.rfind("export ", 0) == 0)
        throw file_error(utf8_string(path), "has an import or export this tool cannot join");
      body += line;
      body += '\n';
    }
    if (exports.empty()) throw file_error(utf8_string(path), "exports nothing (not three.js?)");
    const bool core = std::strcmp(file, "three.core.js") == 0;
    out += std::string("const ") + (core ? "__core" : "__module") + " = (function () {\n" +
           (imports.empty() ? "" : "const {" + imports + "} = __core;\n") + body + "return {" + exports + "};\n})();\n";
  }
  return out + "window.THREE = Object.freeze(Object.assign({}, __core, __module));\n})();\n";
}

nlohmann::json planes_json(const DecodedPlanes& p) {
  return {{"w", p.width}, {"h", p.height}, {"iz", b64(p.iz)}, {"d", b64(p.d)}, {"ratio", b64(p.ratio)}};
}

}  // namespace

std::string find_three(std::string* searched) {
  std::vector<fs::path> where;
  if (const char* e = std::getenv("AHD_THREE_DIR"); e && *e) {
    where.push_back(fs_path(e));  // set: the only place looked at
  } else {
    where.push_back(fs_path(formats_dir()) / ".." / "three");
    where.push_back(fs_path(formats_dir()) / ".." / "tests" / "tools" / "node_modules" / "three");
  }
  std::error_code ec;
  for (const auto& w : where) {
    if (searched) *searched += (searched->empty() ? "" : ", ") + utf8_string(w.lexically_normal());
    if (fs::exists(w / "build" / "three.core.js", ec) && fs::exists(w / "build" / "three.module.js", ec))
      return utf8_string(w.lexically_normal());
  }
  return "";
}

std::string write_preview_3d(const fs::path& dir, const Preview3dInput& in) {
  const auto note = [](const std::string& why) {
    return "<p class=\"note\" id=\"view3d-note\">3D view not written: " + xml_escape(why) + ".</p>\n";
  };
  std::string searched;
  const std::string three = find_three(&searched);
  if (three.empty()) return note("three.js not found (looked in " + searched + "; set AHD_THREE_DIR to the npm package three)");
  const ConversionView v0 = read_conversion(in.manifest_path, 0);
  const Manifest& m = v0.manifest;
  if (size_t(m.width) * m.height > kMaxTexels)
    return note("the lightmap has " + std::to_string(size_t(m.width) * m.height) + " texels per page, the page holds at most " +
                std::to_string(kMaxTexels));
  const fs::path preview = fs_path(formats_dir()) / "preview";
  std::string three_js;
  try {
    three_js = classic_three(fs_path(three));
  } catch (const Error& e) {
    return note(e.what());
  }

  nlohmann::json j;
  j["name"] = utf8_string(fs_path(in.manifest_path).stem());
  j["width"] = m.width, j["height"] = m.height, j["levels"] = m.levels, j["layers"] = m.layers;
  j["dz_min"] = m.dz_min, j["directional"] = m.directional;
  j["ratio_form"] = m.ratio_form == RatioForm::Rgb ? "rgb" : "luminance";
  j["frame"] = m.direction_frame;
  j["decode_glsl"] = read_text(fs_path(formats_dir()) / "shaders" / "ahd_decode.glsl");
  double white = 0;  // the p99 of the level-0 I_z luminance, as index.html's exposure 0
  {
    std::vector<float> l;
    const auto& iz = v0.levels[0].iz;
    for (size_t i = 0; i + 2 < iz.size(); i += 3) l.push_back(0.2126f * iz[i] + 0.7152f * iz[i + 1] + 0.0722f * iz[i + 2]);
    std::sort(l.begin(), l.end());
    white = l.empty() ? 1.0 : std::max(1e-6, double(l[std::min(l.size() - 1, size_t(0.99 * double(l.size())))]));
  }
  j["white"] = white;
  nlohmann::json pages = nlohmann::json::array();
  for (uint32_t layer = 0; layer < m.layers; ++layer) {
    const ConversionView v = layer == 0 ? v0 : read_conversion(in.manifest_path, int(layer));
    nlohmann::json levels = nlohmann::json::array();
    for (const auto& p : v.levels) levels.push_back(planes_json(p));
    pages.push_back({{"levels", levels}});
  }
  j["pages"] = pages;

  const int w = int(m.width), h = int(m.height);
  const size_t n = size_t(w) * h;
  // The mesh, in the lightmap's texture coordinates (s, t) with t = 0 at row 0 (KTXorientation rd).
  MeshTriangles mesh;
  const bool placed = in.placed && !in.placed->mesh.indices.empty();
  if (placed) {
    mesh = in.placed->mesh;
    j["mesh_name"] = "the placed scene (" + std::to_string(in.placed->instances) + " instances)";
  } else if (!in.mesh_path.empty()) {
    mesh = read_mesh_lightmap(in.mesh_path, in.uv_set);
    j["mesh_name"] = utf8_string(fs_path(in.mesh_path).filename());
  } else {
    mesh.positions = {-1, 0, -1, 1, 0, -1, 1, 0, 1, -1, 0, 1};
    mesh.uv = {0, 1, 1, 1, 1, 0, 0, 0};  // OBJ convention (v up), as read_mesh_lightmap returns
    mesh.indices = {0, 2, 1, 0, 3, 2};
    j["mesh_name"] = "";
  }
  std::vector<float> st(mesh.uv.size());
  for (size_t i = 0; i + 1 < mesh.uv.size(); i += 2) st[i] = mesh.uv[i], st[i + 1] = 1.0f - mesh.uv[i + 1];
  j["mesh"] = {{"positions", b64(mesh.positions)}, {"st", b64(st)}, {"indices", b64(mesh.indices)}};
  if (placed) j["mesh"]["page"] = b64(in.placed->triangle_page);  // int32 per triangle

  // Coverage: the source's when given, else the mesh's own rasterisation, else unknown.
  std::vector<uint8_t> coverage;
  if (in.source) coverage = in.source->coverage;
  if (coverage.size() != n && (placed || !in.mesh_path.empty()))
    coverage = rasterise_lightmap_normals(mesh, w, h).coverage;
  j["coverage_from"] = coverage.size() == n ? (in.source ? "source" : "mesh") : "none";
  j["coverage"] = coverage.size() == n ? b64(coverage) : "";

  // The source SH (page 0, level 0) as irradiance polynomials of the local frame, 10 per channel
  // (e0, e_x, e_y, e_z, q_xx, q_yy, q_zz, q_xy, q_xz, q_yz; E(n) = e0 + e·n + nᵀQn), 32 floats per
  // texel in 8 layers of 4 (layer-major), and the rules the (linear) fit of each texel fires.
  if (in.source && m.layers == 1) {
    std::vector<float> poly(n * 32, 0.0f);
    std::vector<uint8_t> rules(n, 0);
    FitOptions opt;
    opt.dz_min = m.dz_min;
    for (size_t i = 0; i < n; ++i) {
      IrradiancePoly p[3];
      local_polys(*in.source, i, p);
      float f[32] = {};
      for (int c = 0; c < 3; ++c) {
        // Off-diagonal terms as the symmetric part: nᵀQn = … + 2·q_xy·xy + …
        const auto& q = p[c].q;
        const double v[10] = {p[c].e0, p[c].e[0], p[c].e[1], p[c].e[2], q[0][0], q[1][1], q[2][2],
                              0.5 * (q[0][1] + q[1][0]), 0.5 * (q[0][2] + q[2][0]), 0.5 * (q[1][2] + q[2][1])};
        for (int k = 0; k < 10; ++k) f[c * 10 + k] = float(v[k]);
      }
      for (int k = 0; k < 32; ++k) poly[(size_t(k / 4) * n + i) * 4 + k % 4] = f[k];
      rules[i] = fit_texel(p, opt).flags;
    }
    j["source"] = {{"poly", b64(poly)}, {"rules", b64(rules)}};
  } else {
    j["source"] = nullptr;
  }

  std::string html = read_text(preview / "view3d.html");
  const std::string title = "{{TITLE}}";
  for (size_t k; (k = html.find(title)) != std::string::npos;) html.replace(k, title.size(), xml_escape(j["name"].get<std::string>()));
  // New files in the preview's temporary folder, published by its rename (cmd_preview.cpp): written
  // plainly, not through write_file_atomic, whose publish takes SIGINT over (it would end the
  // process, leaving the temporary folder, instead of letting the preview clean it up).
  const auto write = [&](const char* file, const std::string& text) {
    write_new_file(utf8_string(dir / fs_path(file)), std::vector<uint8_t>(text.begin(), text.end()));
  };
  write("view3d.html", html);
  write("view3d.js", read_text(preview / "view3d.js"));
  write("three_classic.js", three_js);
  write("view3d_data.js", "window.AHD_VIEW = " + j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + ";\n");
  return "<p id=\"view3d-link\"><a href=\"view3d.html\"><b>3D view</b></a>: the lightmap on " +
         xml_escape(in.mesh_path.empty() && !placed ? std::string("the sample's plane")
                                                    : j["mesh_name"].get<std::string>()) +
         " (orbit, detail normal map, A/B against the source SH and a plain lightmap, exposure, mip, page), and the "
         "lightmap with its UV wireframe, coverage and a texel readout.</p>\n";
}

}  // namespace ahd::cli
