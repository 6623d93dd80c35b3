#include "bakers/godot/godot_unplaced.h"

#include <algorithm>
#include <cmath>

#include "bakers/godot/godot_scene.h"

namespace ahd {

// One line: the users that cannot be placed (grouped by cause, the first three causes and three
// users of each named), why, and what the user can do.
std::string godot_unplaced_refusal(const GodotSceneMeshes& g) {
  const size_t n = g.unplaced.size(), kListed = 3;
  std::vector<std::pair<std::string, std::vector<std::string>>> causes;  // in order of first appearance
  for (const GodotUnplacedUser& u : g.unplaced) {
    auto it = std::find_if(causes.begin(), causes.end(), [&](const auto& c) { return c.first == u.why; });
    if (it == causes.end()) it = causes.insert(causes.end(), {u.why, {}});
    it->second.push_back(u.node);
  }
  std::string m = std::to_string(n) + " of " + std::to_string(g.users) +
                  " lightmap users cannot be placed from the project, so their lighting would be lost: ";
  for (size_t k = 0; k < causes.size() && k < kListed; ++k) {
    const std::vector<std::string>& users = causes[k].second;
    m += k ? "; " : "";
    for (size_t j = 0; j < users.size() && j < kListed; ++j) m += (j ? ", " : "") + users[j];
    if (users.size() > kListed) m += " and " + std::to_string(users.size() - kListed) + " more";
    m += " (" + causes[k].first + ")";
  }
  if (causes.size() > kListed) m += "; and " + std::to_string(causes.size() - kListed) + " more cause(s)";
  return m + ". --allow-unplaced converts the other " + std::to_string(size_t(g.users) - n) +
         " and keeps the unplaced users' texels with normals from the SH itself (docs/godot.md \"Users that "
         "cannot be placed\")";
}

// The texels of page `page` inside the atlas rectangles of the Godot users that were not placed
// (a->godot->unplaced, only there with --allow-unplaced) and not covered by a placed mesh.
std::vector<uint8_t> godot_unplaced_texels(const GodotSceneMeshes& g, int page, const std::vector<uint8_t>& covered,
                                           int w, int h) {
  if (g.unplaced.empty()) return {};
  std::vector<uint8_t> m(size_t(w) * size_t(h), 0);
  for (const GodotUnplacedUser& u : g.unplaced) {
    if (u.page != page) continue;
    const auto span = [](double at, double size, int n, int* lo, int* hi) {
      *lo = std::clamp(int(std::floor(at * n)), 0, n);
      *hi = std::clamp(int(std::ceil((at + size) * n)), 0, n);
    };
    int x0, x1, y0, y1;
    span(u.rect[0], u.rect[2], w, &x0, &x1);
    span(u.rect[1], u.rect[3], h, &y0, &y1);  // v down: row 0 is v = 0
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const size_t i = size_t(y) * size_t(w) + size_t(x);
        if (!covered[i]) m[i] = 1;
      }
  }
  return m;
}

// The fallback for unplaced users' texels: each lit one keeps its SH, fitted about the direction its
// own L1 band points to (the luminance-weighted irradiance gradient: the light's mean direction,
// the best guess of the surface normal the SH alone gives); unlit ones are left uncovered. The kept
// texels count as covered in the coverage comparison. Returns how many were kept.
size_t keep_godot_unplaced_texels(const std::vector<uint8_t>& fallback, ShImage* sh,
                                  std::vector<uint8_t>* mesh_coverage) {
  size_t kept = 0;
  const size_t per = size_t(sh->coeffs) * 3;
  for (size_t i = 0; i < fallback.size() && i < sh->texels(); ++i) {
    if (!fallback[i]) continue;
    const float* t = sh->texel(i);
    bool lit = false;
    for (size_t k = 0; k < per && !lit; ++k) lit = t[k] != 0.0f;
    if (!lit || !sh->coverage[i]) {
      sh->coverage[i] = 0;
      continue;
    }
    double d[3] = {0, 0, 1};
    if (sh->coeffs >= 4) {
      const double lum[3] = {0.2126, 0.7152, 0.0722};
      double v[3] = {0, 0, 0};  // SH order Y00, y, z, x: world x from coefficient 3, y from 1, z from 2
      for (int c = 0; c < 3; ++c)
        v[0] += lum[c] * t[3 * 3 + c], v[1] += lum[c] * t[1 * 3 + c], v[2] += lum[c] * t[2 * 3 + c];
      const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      if (len > 0 && std::isfinite(len)) d[0] = v[0] / len, d[1] = v[1] / len, d[2] = v[2] / len;
    }
    if (sh->normals.size() == sh->texels() * 3)
      for (int k = 0; k < 3; ++k) sh->normals[i * 3 + size_t(k)] = float(d[k]);
    (*mesh_coverage)[i] = 1;
    ++kept;
  }
  return kept;
}

}  // namespace ahd
