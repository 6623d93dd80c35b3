#include "scene/coverage_check.h"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <cstring>

namespace ahd {

size_t fill_background(const ShImage& sh, std::vector<uint8_t>* is_fill) {
  const size_t n = sh.texels(), per = size_t(sh.coeffs) * 3;
  is_fill->assign(n, 0);
  if (n == 0) return 0;
  // FNV-1a of each non-zero texel's stored floats, sorted: the longest run is the most frequent value.
  std::vector<std::pair<uint64_t, size_t>> hashes;
  hashes.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    const float* t = sh.texel(i);
    bool zero = true;
    uint64_t hsh = 1469598103934665603ull;
    for (size_t k = 0; k < per; ++k) {
      zero = zero && t[k] == 0.0f;
      uint32_t b;
      std::memcpy(&b, &t[k], 4);
      for (int s = 0; s < 32; s += 8) hsh = (hsh ^ ((b >> s) & 0xff)) * 1099511628211ull;
    }
    if (!zero) hashes.push_back({hsh, i});
  }
  std::sort(hashes.begin(), hashes.end());
  size_t best = 0, second = 0, best_at = 0;
  for (size_t s = 0; s < hashes.size();) {
    size_t e = s;
    while (e < hashes.size() && hashes[e].first == hashes[s].first) ++e;
    const size_t run = e - s;
    if (run > best) second = best, best = run, best_at = hashes[s].second;
    else if (run > second) second = run;
    s = e;
  }
  // A fill lies beside lit charts: an image of one value throughout (a test's constant light) has none.
  const double others = double(hashes.size() - best);
  if (double(best) < kFillShare * double(n) || double(best) < kFillRatio * double(second) || others < kFillShare * double(n))
    return 0;
  const float* ref = sh.texel(best_at);
  size_t marked = 0;
  for (size_t i = 0; i < n; ++i)  // exact equality: a hash collision marks nothing it should not
    if (std::memcmp(sh.texel(i), ref, per * sizeof(float)) == 0) (*is_fill)[i] = 1, ++marked;
  return marked;
}

CoverageComparison compare_coverage(const std::vector<uint8_t>& covered, const ShImage& sh, int ring, bool find_fill) {
  CoverageComparison c;
  const int w = sh.width, h = sh.height;
  const size_t n = sh.texels(), per = size_t(sh.coeffs) * 3;
  if (covered.size() != n) return c;
  std::vector<uint8_t> lit(n, 0), fill;
  if (find_fill) c.fill = fill_background(sh, &fill);
  else fill.assign(n, 0);
  // With a fill, the background is the fill and whatever is no brighter (Bevy's unused space holds
  // values around it, 0.003–0.01 beside charts of 0.1–1): lit is brighter than the fill in L0.
  float fill_level = 0;
  for (size_t i = 0; i < n && c.fill; ++i)
    if (fill[i]) {
      for (int ch = 0; ch < 3; ++ch) fill_level = std::max(fill_level, std::fabs(sh.texel(i)[ch]));
      break;
    }
  for (size_t i = 0; i < n; ++i) {
    const float* t = sh.texel(i);
    for (size_t k = 0; k < per && !lit[i] && !fill[i]; ++k) lit[i] = t[k] != 0.0f;
    if (lit[i] && c.fill) lit[i] = std::max({std::fabs(t[0]), std::fabs(t[1]), std::fabs(t[2])}) > fill_level;
    c.covered += covered[i] != 0;
    c.covered_fill += covered[i] && fill[i];
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
    if (!covered[s] || lit[s] || fill[s] || seen[s]) continue;
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
        if (!covered[j] || fill[j]) continue;
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
std::string fill_text(const CoverageComparison& c) {
  if (!c.fill) return "";
  char buf[120];
  std::snprintf(buf, sizeof buf, ", atlas fill %zu texels, covered %zu = %.1f %%", c.fill, c.covered_fill,
                pct(c.covered_fill, c.covered));
  return buf;
}
}  // namespace

std::string describe_coverage(const CoverageComparison& c) {
  char buf[300];
  std::snprintf(buf, sizeof buf,
                "mesh covers %zu texels, lightmap lit %zu: IoU of the lit charts %.3f (lit far outside the mesh %zu = %.1f %%, "
                "baker's ring %zu, covered in black regions %zu = %.1f %%, dark parts of lit charts %zu%s)",
                c.covered, c.lit, c.iou, c.lit_outside, pct(c.lit_outside, c.lit), c.ring, c.covered_black,
                pct(c.covered_black, c.covered), c.dark_in_chart, fill_text(c).c_str());
  return buf;
}

std::string coverage_mismatch(const CoverageComparison& c) {
  if (c.iou >= 0.9 && pct(c.lit_outside, c.lit) <= 5 && pct(c.covered_black, c.covered) <= 10 &&
      pct(c.covered_fill, c.covered) <= 10)
    return "";
  char buf[260];
  std::snprintf(buf, sizeof buf, "IoU %.2f with the lit charts, %.0f %% of the lit texels far outside it, %.0f %% of its texels in black regions",
                c.iou, pct(c.lit_outside, c.lit), pct(c.covered_black, c.covered));
  std::string why = buf;
  if (c.fill) {
    std::snprintf(buf, sizeof buf, ", %.0f %% on the atlas's fill", pct(c.covered_fill, c.covered));
    why += buf;
  }
  return why;
}

}  // namespace ahd
