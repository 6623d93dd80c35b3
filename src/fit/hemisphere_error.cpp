#include "fit/hemisphere_error.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>

#include "core/parallel.h"
#include "fit/covered_slots.h"
#include "fit/hemisphere_sums.h"

namespace ahd {
namespace {

// Mean, max and p99 (the value at sorted index ceil(0.99·n) − 1) of v, which it may reorder: a
// selection, not a sort (a conversion summarises four figures of every level). The p99 is the m-th
// largest value, m = n − that index (41 of a 4096-texel sample): kept in a min-heap of m in one
// pass, where nth_element made several over the whole sample. With a NaN among the values (no
// order to rank them by), nth_element as before.
ErrorStat summarise(std::vector<double>& v) {
  ErrorStat s;
  if (v.empty()) return s;
  double sum = 0;
  bool nan = false;
  for (double x : v) sum += x, nan |= x != x;
  s.mean = sum / double(v.size());
  s.max = *std::max_element(v.begin(), v.end());
  const size_t k = std::min(v.size() - 1, size_t(std::ceil(0.99 * double(v.size()))) - 1);
  const size_t m = v.size() - k;
  if (nan || m > 256) {
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
    s.p99 = v[k];
    return s;
  }
  // heap[0..m): the m largest so far, smallest on top (std::greater: a min-heap).
  std::vector<double> heap(v.begin(), v.begin() + std::ptrdiff_t(m));
  std::make_heap(heap.begin(), heap.end(), std::greater<double>());
  for (size_t i = m; i < v.size(); ++i)
    if (v[i] > heap.front()) {
      std::pop_heap(heap.begin(), heap.end(), std::greater<double>());
      heap.back() = v[i];
      std::push_heap(heap.begin(), heap.end(), std::greater<double>());
    }
  s.p99 = heap.front();
  return s;
}

// The `relative` figure of one texel: RMS over directions and channels / mean luminance irradiance.
double texel_relative(double se, double mean_lum_sum, int directions) {
  const double mean_lum = mean_lum_sum / directions;
  const double rmse = std::sqrt(se / (3.0 * directions));
  return mean_lum > 0 ? rmse / mean_lum : 0.0;
}

// The report over measured texels; `population` = the covered texels they stand for.
ErrorReport summarise_texels(const std::vector<TexelError>& e, size_t population) {
  ErrorReport r;
  r.texels = e.size();
  r.population = population;
  std::vector<double> v(e.size());
  auto stat = [&](double TexelError::*m) {
    for (size_t i = 0; i < e.size(); ++i) v[i] = e[i].*m;
    return summarise(v);
  };
  for (const TexelError& t : e) r.negative += t.negative;
  r.rmse = stat(&TexelError::rmse);
  r.relative = stat(&TexelError::rel);
  r.log2 = stat(&TexelError::lg);
  r.normal_rel = stat(&TexelError::nrel);
  return r;
}

// splitmix64: a fixed hash for the sample's offsets within strata (no global random state).
uint64_t mix(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

}  // namespace

namespace {

// Texel i's sums over the directions (fit/hemisphere_sums.h), its polynomials into p. An L0 texel
// (plain lightmaps) against a pure ambient lobe: both are the same for every direction, so one
// direction stands for all and its terms are counted `directions` times.
HemisphereSums texel_sums(const ShImage& sh, size_t i, const AhdLobe& l, const double* dirs, int directions,
                          bool with_log, IrradiancePoly p[3]) {
  local_polys(sh, i, p);
  const bool constant = sh.coeffs == 1 && l.cd[0] == 0 && l.cd[1] == 0 && l.cd[2] == 0;
  HemisphereSums h = hemisphere_sums(p, l, dirs, constant ? 1 : directions, with_log);
  if (constant) h.se *= directions, h.sl *= directions, h.lum *= directions;
  return h;
}

}  // namespace

TexelError texel_error(const ShImage& sh, size_t i, const AhdLobe& l, const double* dirs, int directions) {
  IrradiancePoly p[3];
  const HemisphereSums h = texel_sums(sh, i, l, dirs, directions, true, p);
  const double se = h.se, sl = h.sl, lum_sum = h.lum;
  TexelError e;
  e.rmse = std::sqrt(se / (3.0 * directions));
  e.rel = texel_relative(se, lum_sum, directions);
  e.lg = std::sqrt(sl / (3.0 * directions));
  const double z[3] = {0, 0, 1};
  double ez_lum = 0, ez_err = 0;
  for (int c = 0; c < 3; ++c) {
    const double ref = std::max(0.0, eval_irradiance(p[c], z));
    const double got = l.ca[c] + std::max(0.0, l.d[2]) * l.cd[c];
    ez_lum += kLumaWeights[c] * ref;
    ez_err = std::max(ez_err, std::fabs(got - ref));
  }
  e.nrel = ez_lum > 0 ? ez_err / ez_lum : 0.0;
  e.negative = false;
  for (int c = 0; c < 3; ++c) e.negative |= (l.ca[c] < 0 || l.cd[c] < 0);
  return e;
}

std::vector<double> hemisphere_directions(int count) {
  std::vector<double> dirs(size_t(count) * 3);
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - (i + 0.5) / count;  // uniform in z = uniform in solid angle
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    dirs[size_t(i) * 3 + 0] = r * std::cos(golden * i);
    dirs[size_t(i) * 3 + 1] = r * std::sin(golden * i);
    dirs[size_t(i) * 3 + 2] = z;
  }
  return dirs;
}

ErrorReport measure_error(const ShImage& sh, const std::vector<AhdLobe>& lobes, int threads,
                          int directions) {
  return measure_error(sh, [&](size_t i) { return lobes[i]; }, threads, directions);
}

ErrorReport measure_error(const ShImage& sh, const LobeAt& lobe, int threads, int directions) {
  const std::vector<double> dirs = hemisphere_directions(directions);
  const size_t n = sh.texels();
  // Covered texels only, in raster order (their rank is their slot).
  size_t covered = 0;
  const std::vector<size_t> slot = covered_slots(sh, &covered);
  std::vector<TexelError> e(covered);
  parallel_for(n, threads, 512, [&](size_t i) {
    if (sh.coverage[i]) e[slot[i]] = texel_error(sh, i, lobe(i), dirs.data(), directions);
  });
  return summarise_texels(e, covered);
}

bool relative_p99_exceeds(const ShImage& sh, const std::vector<AhdLobe>& lobes, double threshold, int directions) {
  size_t covered = 0;
  for (uint8_t c : sh.coverage) covered += c != 0;
  if (covered == 0) return false;
  // summarise(): p99 is the value at sorted index ceil(0.99·n) − 1, so it exceeds the threshold
  // exactly when at least n − that index texels do. Stop as soon as that many are found.
  const size_t needed = covered - (size_t(std::ceil(0.99 * double(covered))) - 1);
  const std::vector<double> dirs = hemisphere_directions(directions);
  size_t above = 0;
  for (size_t i = 0; i < sh.texels(); ++i) {
    if (!sh.coverage[i]) continue;
    IrradiancePoly p[3];
    local_polys(sh, i, p);
    const HemisphereSums h = hemisphere_sums(p, lobes[i], dirs.data(), directions, false);
    const double se = h.se, lum_sum = h.lum;
    if (texel_relative(se, lum_sum, directions) > threshold && ++above >= needed) return true;
  }
  return false;
}

namespace {

// How many of the eight bytes of w are nonzero: each one's flag in the low bit of its byte, the
// flags summed by one multiply (the baseline x86-64 build has no popcount instruction, and the
// library call was most of the sample's cost).
inline size_t nonzero_bytes(uint64_t w) {
  constexpr uint64_t low7 = 0x7f7f7f7f7f7f7f7full;
  const uint64_t flags = ((((w & low7) + low7) | w) & ~low7) >> 7;
  return size_t((flags * 0x0101010101010101ull) >> 56);
}

// Covered texels among n coverage bytes, eight a word (the sample is drawn at every level of
// every conversion, and level 0 of a 2048² map is 4 M bytes).
size_t count_covered(const uint8_t* c, size_t n) {
  size_t k = 0, i = 0;
  for (; i + 8 <= n; i += 8) {
    uint64_t w;
    std::memcpy(&w, c + i, 8);
    k += nonzero_bytes(w);
  }
  for (; i < n; ++i) k += c[i] != 0;
  return k;
}

// error_sample, with the covered count it found (*covered_out).
std::vector<size_t> error_sample_counted(const std::vector<uint8_t>& coverage, int sample, size_t* covered_out) {
  const size_t n = coverage.size();
  const uint8_t* c = coverage.data();
  // Runs of kRun texels: their counts, kept for the walk below (one pass over the bytes, not two).
  constexpr size_t kRun = 256;
  std::vector<uint16_t> run_count((n + kRun - 1) / kRun);
  size_t covered = 0;
  for (size_t r = 0; r < run_count.size(); ++r) {
    run_count[r] = uint16_t(count_covered(c + r * kRun, std::min(kRun, n - r * kRun)));
    covered += run_count[r];
  }
  *covered_out = covered;
  std::vector<size_t> out;
  const size_t k = size_t(std::max(1, sample));
  if (covered <= k) {
    out.reserve(covered);
    for (size_t i = 0; i < n; ++i)
      if (c[i]) out.push_back(i);
    return out;
  }
  // Stratum s holds covered ranks [s·N/k, (s+1)·N/k); its pick is rank start + hash(s) mod length.
  out.reserve(k);
  size_t s = 0, rank = 0;
  auto target = [&](size_t st) {
    const size_t a = st * covered / k, b = (st + 1) * covered / k;
    return a + size_t(mix(st) % uint64_t(b - a));
  };
  size_t want = target(0);
  // Runs of 256 texels that hold no wanted rank are skipped by their count alone; in a run that
  // holds one, words of eight coverage bytes are skipped by their count, and only the word that
  // holds the wanted rank is read byte by byte (strata are hundreds of covered texels apart in a
  // large map: the byte-by-byte walk of whole runs was 5 ms a call at 2048²).
  for (size_t i = 0; i < n && s < k;) {
    const size_t end = std::min(n, i + kRun);
    const size_t in_run = run_count[i / kRun];
    if (rank + in_run <= want) {
      rank += in_run;
      i = end;
      continue;
    }
    for (; i < end && s < k;) {
      if (i + 8 <= end) {
        uint64_t w;
        std::memcpy(&w, c + i, 8);
        const size_t in_word = nonzero_bytes(w);
        if (rank + in_word <= want) {
          rank += in_word;
          i += 8;
          continue;
        }
      }
      if (c[i] && rank++ == want) {
        out.push_back(i);
        if (++s < k) want = target(s);
      }
      ++i;
    }
  }
  return out;
}

}  // namespace

std::vector<size_t> error_sample(const std::vector<uint8_t>& coverage, int sample) {
  size_t covered = 0;
  return error_sample_counted(coverage, sample, &covered);
}

ErrorReport estimate_error(const ShImage& sh, const LobeAt& lobe, int threads, int sample, int directions) {
  const std::vector<double> dirs = hemisphere_directions(directions);
  size_t covered = 0;
  const std::vector<size_t> idx = error_sample_counted(sh.coverage, sample, &covered);
  std::vector<TexelError> e(idx.size());
  parallel_for(idx.size(), threads, 64,
               [&](size_t j) { e[j] = texel_error(sh, idx[j], lobe(idx[j]), dirs.data(), directions); });
  return summarise_texels(e, covered);
}

ErrorReport estimate_error(const ShImage& sh, const std::vector<AhdLobe>& lobes, int threads, int sample,
                           int directions) {
  return estimate_error(sh, [&](size_t i) { return lobes[i]; }, threads, sample, directions);
}

bool sampled_relative_p99_exceeds(const ShImage& sh, const LobeAt& lobe, double threshold, int sample,
                                  int directions) {
  const std::vector<size_t> idx = error_sample(sh.coverage, sample);
  if (idx.empty()) return false;
  const size_t needed = idx.size() - (size_t(std::ceil(0.99 * double(idx.size()))) - 1);
  const std::vector<double> dirs = hemisphere_directions(directions);
  size_t above = 0;
  for (size_t i : idx) {
    // texel_error's `rel` without the log figure it does not need (the same bits: rel is se and lum's).
    IrradiancePoly p[3];
    const HemisphereSums h = texel_sums(sh, i, lobe(i), dirs.data(), directions, false, p);
    if (texel_relative(h.se, h.lum, directions) > threshold && ++above >= needed) return true;
  }
  return false;
}

bool sh_is_constant(const ShImage& sh) {
  if (sh.coeffs == 1) return true;  // L0 (plain lightmaps): nothing but coefficient 0 to look at
  const size_t per = size_t(sh.coeffs) * 3;
  for (size_t i = 0; i < sh.texels(); ++i) {
    if (!sh.coverage[i]) continue;
    const float* t = sh.texel(i);
    for (size_t k = 3; k < per; ++k)
      if (t[k] != 0.0f) return false;
  }
  return true;
}

}  // namespace ahd
