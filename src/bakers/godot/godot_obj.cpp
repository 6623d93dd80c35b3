#include "bakers/godot/godot_obj.h"

#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>

#include "core/error.h"

namespace ahd {

namespace {

std::vector<std::string> split(const std::string& s, char by, bool allow_empty) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == by) {
      if (allow_empty || !cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (allow_empty || !cur.empty()) out.push_back(cur);
  return out;
}

std::string strip(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && static_cast<unsigned char>(s[a]) <= ' ') ++a;
  while (b > a && static_cast<unsigned char>(s[b - 1]) <= ' ') --b;
  return s.substr(a, b - a);
}

double num(const std::string& s) { return std::strtod(s.c_str(), nullptr); }

}  // namespace

GodotObjMesh parse_godot_obj_mesh(const std::string& text, const std::string& source, const float scale[3],
                                  const float offset[3]) {
  GodotObjMesh out;
  std::vector<float> v, vn, vt, col;
  struct Corner {
    float key[3 + 3 + 2 + 3 + 1];
  };
  std::map<std::string, uint32_t> seen;  // the current surface's merged vertices
  float normal[3] = {0, 0, 0}, uv[2] = {0, 0};
  bool smoothing = true;
  uint32_t smooth_group = 0;
  const auto commit = [&]() {  // SurfaceTool::clear(): nothing carries over to the next surface
    seen.clear();
    normal[0] = normal[1] = normal[2] = 0, uv[0] = uv[1] = 0;
  };
  std::istringstream in(text);
  std::string raw;
  while (std::getline(in, raw)) {
    std::string l = strip(raw);
    while (!l.empty() && l.back() == '\\') {
      std::string add;
      if (!std::getline(in, add)) break;
      add = strip(add);
      l += add;
      if (add.empty()) break;
    }
    if (l.rfind("v ", 0) == 0) {
      const std::vector<std::string> t = split(l, ' ', false);
      if (t.size() < 4) throw file_error(source, "a vertex line with fewer than 3 numbers");
      for (int a = 0; a < 3; ++a) v.push_back(float(num(t[size_t(a + 1)]) * double(scale[a]) + double(offset[a])));
      if (t.size() >= 7) {
        while (col.size() < v.size() - 3) col.push_back(1.0f);
        for (int a = 0; a < 3; ++a) col.push_back(float(num(t[size_t(a + 4)])));
      } else if (!col.empty()) {
        col.insert(col.end(), {1.0f, 1.0f, 1.0f});
      }
    } else if (l.rfind("vt ", 0) == 0) {
      const std::vector<std::string> t = split(l, ' ', false);
      if (t.size() < 3) throw file_error(source, "a texture coordinate line with fewer than 2 numbers");
      vt.insert(vt.end(), {float(num(t[1])), float(1.0 - num(t[2]))});
    } else if (l.rfind("vn ", 0) == 0) {
      const std::vector<std::string> t = split(l, ' ', false);
      if (t.size() < 4) throw file_error(source, "a normal line with fewer than 3 numbers");
      vn.insert(vn.end(), {float(num(t[1])), float(num(t[2])), float(num(t[3]))});
    } else if (l.rfind("f ", 0) == 0) {
      const std::vector<std::string> t = split(l, ' ', false);
      if (t.size() < 4) throw file_error(source, "a face of fewer than 3 corners");
      std::vector<std::vector<std::string>> c;
      for (size_t k = 1; k < t.size(); ++k) c.push_back(split(t[k], '/', true));
      for (size_t i = 2; i < c.size(); ++i)
        for (const std::vector<std::string>* f : {&c[i - 1], &c[0], &c[i]}) {
          if (f->size() != c[0].size()) throw file_error(source, "a face whose corners differ in form");
          const auto index = [&](const std::string& s, size_t count, const char* what) {
            long k = std::strtol(s.c_str(), nullptr, 10) - 1;
            if (k < 0) k += long(count) + 1;
            if (k < 0 || size_t(k) >= count)
              throw file_error(source, std::string("a face's ") + what + " index out of range");
            return size_t(k);
          };
          if (f->size() >= 2 && !(*f)[1].empty()) {
            const size_t k = index((*f)[1], vt.size() / 2, "texture coordinate");
            uv[0] = vt[k * 2], uv[1] = vt[k * 2 + 1];
          }
          if (f->size() == 3) {
            const size_t k = index((*f)[2], vn.size() / 3, "normal");
            std::memcpy(normal, &vn[k * 3], sizeof normal);
          }
          const size_t p = index((*f)[0], v.size() / 3, "vertex");
          Corner corner{};
          std::memcpy(corner.key, &v[p * 3], 3 * sizeof(float));
          std::memcpy(corner.key + 3, normal, sizeof normal);
          std::memcpy(corner.key + 6, uv, sizeof uv);
          if (!col.empty() && p * 3 + 2 < col.size()) std::memcpy(corner.key + 8, &col[p * 3], 3 * sizeof(float));
          const uint32_t group = smoothing ? smooth_group : 0xffffffffu;
          std::memcpy(corner.key + 11, &group, sizeof group);
          const std::string bytes(reinterpret_cast<const char*>(corner.key), sizeof corner.key);
          auto [it, added] = seen.emplace(bytes, uint32_t(out.positions.size() / 3));
          if (added) {
            out.positions.insert(out.positions.end(), corner.key, corner.key + 3);
            out.normals.insert(out.normals.end(), corner.key + 3, corner.key + 6);
          }
          out.indices.push_back(it->second);
        }
    } else if (l.rfind("s ", 0) == 0) {
      const bool smooth = strip(l.substr(2)) != "off";
      if (smooth != smoothing) {
        smoothing = smooth;
        if (smoothing) ++smooth_group;
      }
    } else if (l.rfind("usemtl ", 0) == 0 || l.rfind("o ", 0) == 0) {
      commit();
    }
  }
  out.has_normals = !vn.empty();
  return out;
}

}  // namespace ahd
