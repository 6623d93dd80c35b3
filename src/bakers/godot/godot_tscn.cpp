#include "bakers/godot/godot_tscn.h"

#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>

#include "core/error.h"

namespace ahd {

const GodotTscnExt* GodotTscn::find_ext(const std::string& id) const {
  for (const GodotTscnExt& e : ext)
    if (e.id == id) return &e;
  return nullptr;
}

const GodotTscnSub* GodotTscn::find_sub(const std::string& id) const {
  for (const GodotTscnSub& e : sub)
    if (e.id == id) return &e;
  return nullptr;
}

namespace {

// "[node name="X" parent="." instance=ExtResource("1_a")]" → {name: X, parent: ., instance: ExtResource("1_a")}.
bool parse_header(const std::string& h, std::string* tag, std::map<std::string, std::string>* attrs) {
  size_t i = 1;
  while (i < h.size() && h[i] != ' ' && h[i] != ']') *tag += h[i++];
  while (i < h.size()) {
    while (i < h.size() && h[i] == ' ') ++i;
    if (i >= h.size() || h[i] == ']') return true;
    std::string key;
    while (i < h.size() && h[i] != '=' && h[i] != ' ' && h[i] != ']') key += h[i++];
    if (i >= h.size() || h[i] != '=') return false;
    ++i;
    std::string value;
    if (i < h.size() && h[i] == '"') {
      for (++i; i < h.size() && h[i] != '"'; ++i) {
        if (h[i] == '\\' && i + 1 < h.size()) ++i;
        value += h[i];
      }
      if (i >= h.size()) return false;
      ++i;
    } else {
      int depth = 0;
      bool quoted = false;
      for (; i < h.size(); ++i) {
        const char c = h[i];
        if (quoted) {
          if (c == '\\') value += h[i++];
          else if (c == '"') quoted = false;
        } else if (c == '"') quoted = true;
        else if (c == '(') ++depth;
        else if (c == ')') --depth;
        else if (depth == 0 && (c == ' ' || c == ']')) break;
        value += c;
      }
    }
    (*attrs)[key] = value;
  }
  return false;
}

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t");
  const size_t b = s.find_last_not_of(" \t");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

// The bracket depth `line` leaves, starting at `depth` with a string open or not (escapes honoured).
int depth_after(const std::string& line, int depth, bool* open) {
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (*open) {
      if (c == '\\') ++i;
      else if (c == '"') *open = false;
    } else if (c == '"') *open = true;
    else if (c == '(' || c == '[' || c == '{') ++depth;
    else if (c == ')' || c == ']' || c == '}') --depth;
  }
  return depth;
}

}  // namespace

std::string godot_resource_ref(const std::string& value, const std::string& name) {
  const std::string v = trim(value);
  if (v.rfind(name, 0) != 0) return "";
  size_t i = name.size();
  const auto spaces = [&] {
    while (i < v.size() && (v[i] == ' ' || v[i] == '\t')) ++i;
  };
  spaces();
  if (i >= v.size() || v[i] != '(') return "";
  ++i;
  spaces();
  std::string id;
  if (i < v.size() && v[i] == '"') {
    for (++i; i < v.size() && v[i] != '"'; ++i) {
      if (v[i] == '\\' && i + 1 < v.size()) ++i;
      id += v[i];
    }
    if (i >= v.size()) return "";
    ++i;
  } else {
    while (i < v.size() && v[i] != ')' && v[i] != ' ' && v[i] != '\t') id += v[i++];
  }
  spaces();
  if (i + 1 != v.size() || v[i] != ')') return "";
  return id;
}

GodotTscn parse_godot_tscn(const std::string& text, const std::string& source) {
  GodotTscn out;
  std::istringstream in(text);
  std::string line, section;
  size_t n = 0;
  // A cause may quote the file's text (a token of a multi-line value): ahd::Error escapes its
  // control characters, so the error stays one line (found by fuzz_godot_scene).
  const auto fail = [&](const std::string& why) {
    return file_error(source, "line " + std::to_string(n) + ": " + why);
  };
  const size_t kMaxValue = size_t(64) << 20;
  while (std::getline(in, line)) {
    ++n;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty() && line[0] == '[') {
      std::string tag;
      std::map<std::string, std::string> a;
      if (!parse_header(line, &tag, &a)) throw fail("malformed section header");
      section = tag;
      if (tag == "gd_scene" || tag == "gd_resource") {
        out.format = std::atoi(a["format"].c_str());
      } else if (tag == "ext_resource") {
        out.ext.push_back({a["id"], a["type"], a["path"]});
      } else if (tag == "sub_resource") {
        GodotTscnSub sub;
        sub.id = a["id"], sub.type = a["type"], sub.line = int(n);
        out.sub.push_back(std::move(sub));
      } else if (tag == "node") {
        GodotTscnNode node;
        node.name = a["name"];
        node.type = a["type"];
        node.has_parent = a.count("parent") != 0;
        node.parent = a["parent"];
        if (a.count("instance")) {
          node.instance = godot_resource_ref(a["instance"], "ExtResource");
          if (node.instance.empty()) throw fail("instance is not ExtResource(\"id\") but '" + a["instance"] + "'");
        }
        if (node.name.empty()) throw fail("node without a name");
        out.nodes.push_back(node);
      }
      continue;
    }
    // A property `key = value`; the value runs on while a string or a bracket is open.
    const size_t eq = line.find(" = ");
    std::string key, value;
    if (eq != std::string::npos) key = line.substr(0, eq), value = line.substr(eq + 3);
    else value = line;
    bool open = false;
    int depth = depth_after(value, 0, &open);
    const size_t first = n;
    while ((open || depth > 0) && std::getline(in, line)) {
      ++n;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      value += "\n" + line;
      if (value.size() > kMaxValue) throw fail("a value longer than 64 MiB");
      depth = depth_after(line, depth, &open);
    }
    if (open || depth > 0) {
      n = first;
      throw fail(open ? "a string left open at the end of the file" : "a bracket left open at the end of the file");
    }
    if (key.empty()) continue;
    if (section == "sub_resource" && !out.sub.empty()) {
      out.sub.back().props[key] = value;
      continue;
    }
    if (section != "node" || out.nodes.empty()) continue;
    GodotTscnNode& node = out.nodes.back();
    if (key == "transform") {
      const std::string v = trim(value);
      size_t at = v.rfind("Transform3D", 0) == 0 ? 11 : v.rfind("Transform", 0) == 0 ? 9 : std::string::npos;
      while (at != std::string::npos && at < v.size() && v[at] == ' ') ++at;
      if (at == std::string::npos || at >= v.size() || v[at] != '(' || v.back() != ')')
        throw fail("transform is not Transform3D(…)");
      std::string body = v.substr(at + 1, v.size() - at - 2);
      std::istringstream nums(body);
      std::string tok;
      int k = 0;
      while (std::getline(nums, tok, ',')) {
        if (k >= 12) throw fail("Transform3D takes 12 numbers");
        char* end = nullptr;
        const double x = std::strtod(tok.c_str(), &end);
        while (end && (*end == ' ' || *end == '\t')) ++end;
        if (!end || end == tok.c_str() || *end != '\0' || !std::isfinite(x))
          throw fail("Transform3D number '" + (tok.size() > 64 ? tok.substr(0, 64) + "…" : tok) + "'");
        node.transform[k++] = x;
      }
      if (k != 12) throw fail("Transform3D takes 12 numbers, found " + std::to_string(k));
      node.has_transform = true;
    } else if (key == "light_data") {
      node.light_data = godot_resource_ref(value, "ExtResource");
    } else if (key == "mesh") {
      node.mesh_ext = godot_resource_ref(value, "ExtResource");
      node.mesh_sub = godot_resource_ref(value, "SubResource");
    }
  }
  if (out.nodes.empty()) throw file_error(source, "no node (not a Godot scene)");
  return out;
}

}  // namespace ahd
