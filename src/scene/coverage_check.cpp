#include "scene/coverage_check.h"

#include <algorithm>
#include <cstdio>

namespace ahd {

CoverageComparison compare_coverage(const std::vector<uint8_t>& covered, const ShImage& sh, int ring) {
  CoverageComparison c;
  const int w = sh.width, h = sh.height;
  const size_t n = sh.texels(), per = size_t(sh.coeffs) * 3;
  if (covered.size() != n) return c;
  std::vector<uint8_t> lit(n, 0);
  for (size_t i = 0; i < n; ++i) {
    const float* t = sh.texel(i);
    for (size_t k = 0; k < per && !lit[i]; ++k) lit[i] = t[k] != 0.0f;
    c.covered += covered[i] != 0;
    c.lit += lit[i];
    c.both += covered[i] && lit[i];
  }
  // Lit texels outside the coverage: the baker's ring, or light where the mesh puts nothing.
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      if (!lit[i] || covered[i]) continue;
      bool near = false;
      for (int dy = -ring; dy <= ring && !near; ++dy)
        for (int dx = -ring; dx <= ring && !near; ++dx) {
          const int xx = x + dx, yy = y + dy;
          near = xx >= 0 && yy >= 0 && xx < w && yy < h && covered[size_t(yy) * w + xx];
        }
      (near ? c.ring : c.lit_outside) += 1;
    }
  // Black covered regions (4-connected): part of a lit chart when they touch a lit covered texel.
  std::vector<uint8_t> seen(n, 0);
  std::vector<size_t> stack, region;
  for (size_t s = 0; s < n; ++s) {
    if (!covered[s] || lit[s] || seen[s]) continue;
    bool touches = false;
    region.clear();
    stack.assign(1, s);
    seen[s] = 1;
    while (!stack.empty()) {
      const size_t i = stack.back();
      stack.pop_back();
      region.push_back(i);
      const int x = int(i % size_t(w)), y = int(i / size_t(w));
      const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
      for (int k = 0; k < 4; ++k) {
        if (nx[k] < 0 || ny[k] < 0 || nx[k] >= w || ny[k] >= h) continue;
        const size_t j = size_t(ny[k]) * w + nx[k];
        if (!covered[j]) continue;
        if (lit[j]) touches = true;
        else if (!seen[j]) seen[j] = 1, stack.push_back(j);
      }
    }
    (touches ? c.dark_in_chart : c.covered_black) += region.size();
  }
  const size_t uni = c.covered - c.covered_black + c.lit_outside;
  c.iou = uni ? double(c.both + c.dark_in_chart) / double(uni) : 1.0;
  return c;
}

namespace {
double pct(size_t a, size_t b) { return b ? 100.0 * double(a) / double(b) : 0.0; }
}  // namespace

std::string describe_coverage(const CoverageComparison& c) {
  char buf[300];
  std::snprintf(buf, sizeof buf,
                "mesh covers %zu texels, lightmap lit %zu: IoU of the lit charts %.3f (lit far outside the mesh %zu = %.1f %%, "
                "baker's ring %zu, covered in black regions %zu = %.1f %%, dark parts of lit charts %zu)",
                c.covered, c.lit, c.iou, c.lit_outside, pct(c.lit_outside, c.lit), c.ring, c.covered_black,
                pct(c.covered_black, c.covered), c.dark_in_chart);
  return buf;
}

std::string coverage_mismatch(const CoverageComparison& c) {
  if (c.iou >= 0.9 && pct(c.lit_outside, c.lit) <= 5 && pct(c.covered_black, c.covered) <= 10) return "";
  char buf[200];
  std::snprintf(buf, sizeof buf, "IoU %.2f with the lit charts, %.0f %% of the lit texels far outside it, %.0f %% of its texels in black regions",
                c.iou, pct(c.lit_outside, c.lit), pct(c.covered_black, c.covered));
  return buf;
}

}  // namespace ahd
