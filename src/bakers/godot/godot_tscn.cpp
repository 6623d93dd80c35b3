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

namespace {

// Whether the quotes of `line` leave a string open (escapes honoured), starting `open`.
bool string_open_after(const std::string& line, bool open) {
  for (size_t i = 0; i < line.size(); ++i) {
    if (open && line[i] == '\\') ++i;
    else if (line[i] == '"') open = !open;
  }
  return open;
}

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

// ExtResource("1_a") → 1_a ("" when not that form).
std::string ext_ref(const std::string& v) {
  const std::string head = "ExtResource(\"";
  if (v.rfind(head, 0) != 0) return "";
  const size_t end = v.find('"', head.size());
  return end == std::string::npos ? "" : v.substr(head.size(), end - head.size());
}

}  // namespace

GodotTscn parse_godot_tscn(const std::string& text, const std::string& source) {
  GodotTscn out;
  std::istringstream in(text);
  std::string line, section;
  bool open = false;  // inside a multi-line string value
  size_t n = 0;
  const auto fail = [&](const std::string& why) { return file_error(source, "line " + std::to_string(n) + ": " + why); };
  while (std::getline(in, line)) {
    ++n;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (open) {
      open = string_open_after(line, true);
      continue;
    }
    if (!line.empty() && line[0] == '[') {
      std::string tag;
      std::map<std::string, std::string> a;
      if (!parse_header(line, &tag, &a)) throw fail("malformed section header");
      section = tag;
      if (tag == "ext_resource") {
        out.ext.push_back({a["id"], a["type"], a["path"]});
      } else if (tag == "node") {
        GodotTscnNode node;
        node.name = a["name"];
        node.type = a["type"];
        node.has_parent = a.count("parent") != 0;
        node.parent = a["parent"];
        if (a.count("instance")) {
          node.instance = ext_ref(a["instance"]);
          if (node.instance.empty()) throw fail("instance is not ExtResource(\"id\")");
        }
        if (node.name.empty()) throw fail("node without a name");
        out.nodes.push_back(node);
      }
      continue;
    }
    open = string_open_after(line, false);
    if (section != "node" || out.nodes.empty()) continue;
    const size_t eq = line.find(" = ");
    if (eq == std::string::npos) continue;
    const std::string key = line.substr(0, eq), value = line.substr(eq + 3);
    GodotTscnNode& node = out.nodes.back();
    if (key == "transform") {
      const std::string head = "Transform3D(";
      if (value.rfind(head, 0) != 0 || value.back() != ')') throw fail("transform is not Transform3D(…)");
      std::string body = value.substr(head.size(), value.size() - head.size() - 1);
      std::istringstream nums(body);
      std::string tok;
      int k = 0;
      while (std::getline(nums, tok, ',')) {
        if (k >= 12) throw fail("Transform3D takes 12 numbers");
        char* end = nullptr;
        const double v = std::strtod(tok.c_str(), &end);
        while (end && *end == ' ') ++end;
        if (!end || *end != '\0' || !std::isfinite(v)) throw fail("Transform3D number '" + tok + "'");
        node.transform[k++] = v;
      }
      if (k != 12) throw fail("Transform3D takes 12 numbers, found " + std::to_string(k));
      node.has_transform = true;
    } else if (key == "light_data") {
      node.light_data = ext_ref(value);
    }
  }
  if (out.nodes.empty()) throw file_error(source, "no node (not a Godot scene)");
  return out;
}

}  // namespace ahd
