#include "scene/placement_io.h"

#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.h"
#include "files/file_io.h"
#include "core/json_number.h"

namespace ahd {

namespace {

std::vector<Placement> read_json(const std::string& path, const std::string& text) {
  std::vector<Placement> out;
  try {
    const nlohmann::json j = nlohmann::json::parse(text);
    for (const auto& e : j.at("placements")) {
      Placement p;
      p.node = e.at("node").get<std::string>();
      p.page = int(json_whole_or(e, "page", 0, 0, 2047, path));
      const auto s = e.at("scale").get<std::vector<double>>(), o = e.at("offset").get<std::vector<double>>();
      if (s.size() != 2 || o.size() != 2) throw file_error(path, "scale and offset take 2 numbers (u, v)");
      p.scale[0] = s[0], p.scale[1] = s[1], p.offset[0] = o[0], p.offset[1] = o[1];
      if (p.page < 0) throw file_error(path, "page must be ≥ 0 ('" + p.node + "')");
      out.push_back(p);
    }
  } catch (const nlohmann::json::exception& e) {
    throw file_error(path, std::string("malformed placement JSON (") + e.what() + ")");
  }
  return out;
}

std::string after(const std::string& line, const std::string& key) {
  const size_t at = line.find(key);
  return at == std::string::npos ? "" : line.substr(at + key.size());
}

// "{x: 0.5, y: 0.25, z: 0, w: 0.5}" → the four numbers.
bool parse_xyzw(const std::string& s, double v[4]) {
  const char* keys[4] = {"x:", "y:", "z:", "w:"};
  for (int i = 0; i < 4; ++i) {
    const size_t at = s.find(keys[i]);
    if (at == std::string::npos) return false;
    try {
      v[i] = std::stod(s.substr(at + 2));
    } catch (const std::exception&) {
      return false;
    }
  }
  return true;
}

// Unity's scene YAML, read block by block ("--- !u!CLASS &FILEID"): GameObjects (class 1) give
// names, MeshRenderers (class 23) their lightmap index and tiling/offset.
std::vector<Placement> read_unity(const std::string& path, std::istream& in) {
  struct Renderer {
    std::string game_object;
    long index = -1;
    bool has_index = false;
    double st[4] = {1, 1, 0, 0};
    bool has_st = false;
  };
  std::map<std::string, std::string> names;
  std::vector<Renderer> renderers;
  std::string line, cls, id;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();  // CRLF line ends (a scene saved on Windows)
    if (line.rfind("--- !u!", 0) == 0) {
      std::istringstream h(line.substr(7));
      h >> cls >> id;
      if (!id.empty() && id[0] == '&') id = id.substr(1);
      if (cls == "23") renderers.emplace_back();
      continue;
    }
    if (cls == "1" && line.find("m_Name:") != std::string::npos) {
      std::string n = after(line, "m_Name:");
      n.erase(0, n.find_first_not_of(' '));
      names[id] = n;
    } else if (cls == "23") {
      Renderer& r = renderers.back();
      if (line.find("m_GameObject:") != std::string::npos) {
        std::string g = after(line, "fileID:");
        g.erase(0, g.find_first_not_of(' '));
        r.game_object = g.substr(0, g.find_first_of("},"));
      } else if (line.find("m_LightmapIndex:") != std::string::npos) {
        r.index = std::stol(after(line, "m_LightmapIndex:"));
        r.has_index = true;
      } else if (line.find("m_LightmapTilingOffset:") != std::string::npos) {
        if (!parse_xyzw(after(line, "m_LightmapTilingOffset:"), r.st))
          throw file_error(path, "malformed m_LightmapTilingOffset: " + line);
        r.has_st = true;
      }
    }
  }
  std::vector<Placement> out;
  size_t with_index = 0;
  for (const Renderer& r : renderers) with_index += r.has_index;
  if (with_index == 0)
    throw file_error(path, std::to_string(renderers.size()) +
                               " MeshRenderer(s) and none records m_LightmapIndex / m_LightmapTilingOffset (a DOTS sub-scene, "
                               "or a scene whose lightmapping lives in LightingData.asset, which is binary): give ahdpack's "
                               "placement JSON ({\"placements\": [{\"node\", \"page\", \"scale\", \"offset\"}]}) from the "
                               "renderers' lightmapScaleOffset, or meshes whose UV2 is already in atlas space (no --placement)");
  for (const Renderer& r : renderers) {
    // Unity reserves 65533..65535 (0xFFFD..0xFFFF) and −1 for renderers without a baked lightmap
    // (65534: realtime only, 65535: none); they are no page to place on.
    if (r.index < 0 || r.index >= 65533 || !r.has_st) continue;
    const auto it = names.find(r.game_object);
    if (it == names.end()) throw file_error(path, "MeshRenderer's GameObject " + r.game_object + " is not in the scene file");
    Placement p;
    p.node = it->second;
    p.page = int(r.index);
    p.scale[0] = r.st[0], p.scale[1] = r.st[1], p.offset[0] = r.st[2], p.offset[1] = r.st[3];
    out.push_back(p);
  }
  return out;
}

}  // namespace

std::vector<Placement> read_placements(const std::string& path) {
  // Bounded, regular files only: --placement /dev/zero read 2.2 GB before (issue 26).
  const std::string text = read_text_file(path);
  std::vector<Placement> out;
  if (text.rfind("%YAML", 0) == 0) {
    std::istringstream in(text);
    try {
      out = read_unity(path, in);
    } catch (const std::logic_error& e) {  // std::stol on a malformed number
      throw file_error(path, std::string("malformed Unity scene (") + e.what() + ")");
    }
  } else {
    out = read_json(path, text);
  }
  if (out.empty())
    throw file_error(path, "no lightmapped instance placed (m_LightmapIndex -1 and 65533..65535 mean not lightmapped)");
  return out;
}

}  // namespace ahd
