// Fit throughput (texels/s on one core) for L1 and L2 input, and the whole in-memory conversion.
#include <benchmark/benchmark.h>

#include <random>
#include <string>

#include "files/profile_file.h"
#include "fit/ahd_fit.h"
#include "fit/fit_image.h"
#include "fit/hemisphere_sums.h"
#include "core/cpu.h"
#include "pipeline/convert.h"
#include "sample/analytic_baker.h"
#include "lab/hard_cases.h"

using namespace ahd;

namespace {

std::vector<IrradiancePoly> random_polys(int coeffs, size_t n) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g;
  std::vector<IrradiancePoly> out(n * 3);
  for (size_t i = 0; i < n; ++i) {
    float sh[27] = {};
    for (int l = 0; l < 3; ++l) {
      double d[3] = {g(rng), g(rng), g(rng)};
      const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      for (double& v : d) v /= len;
      const double rgb[3] = {u(rng), u(rng), u(rng)};
      add_directional_light(sh, coeffs, d, rgb);
    }
    for (int c = 0; c < 3; ++c) out[i * 3 + c] = irradiance_poly(sh + c, coeffs, 3);
  }
  return out;
}

// Args: SH coefficients (4, 9), direction fit (0 linear, 1 refined), ratio form (0 luminance, 1 RGB).
// The CPU column is the benchmark thread's own CPU time: the figure to compare on a shared machine.
void BM_FitTexel(benchmark::State& state) {
  const int coeffs = int(state.range(0));
  const size_t n = 4096;
  const auto polys = random_polys(coeffs, n);
  FitOptions opt;
  opt.direction_fit = state.range(1) ? DirectionFit::Refined : DirectionFit::Linear;
  opt.ratio_form = state.range(2) ? RatioForm::Rgb : RatioForm::Luminance;
  size_t i = 0;
  for (auto _ : state) {
    AhdFit f = fit_texel(&polys[(i % n) * 3], opt);
    benchmark::DoNotOptimize(f);
    ++i;
  }
  state.SetItemsProcessed(int64_t(state.iterations()));
  state.SetLabel(std::string(coeffs == 4 ? "L1" : "L2") + (state.range(1) ? " refined" : " linear") +
                 (state.range(2) ? " rgb" : " luminance"));
}
BENCHMARK(BM_FitTexel)
    ->ArgsProduct({{4, 9}, {0, 1}, {0, 1}})
    ->ArgNames({"coeffs", "refined", "rgb"});

// One texel's error terms over the estimate's 64 hemisphere directions, with the log figure, by
// path (0 plain, 1 AVX2, 2 AVX-512; a path the CPU lacks is skipped): fit/hemisphere_sums.h.
void BM_HemisphereSums(benchmark::State& state) {
  const int path = int(state.range(0));
  if ((path == 1 && !cpu::has(cpu::kAvx2)) || (path == 2 && !cpu::has(cpu::kAvx2 | cpu::kAvx512))) {
    state.SkipWithError("this CPU lacks the path's instructions");
    return;
  }
  const size_t n = 1024;
  const auto polys = random_polys(4, n);
  std::vector<AhdLobe> lobes(n);
  for (size_t i = 0; i < n; ++i) {
    const AhdFit f = fit_texel(&polys[i * 3], FitOptions{});
    for (int c = 0; c < 3; ++c) lobes[i].ca[c] = fitted_ca(f, c), lobes[i].cd[c] = fitted_cd(f, c), lobes[i].d[c] = f.d[c];
  }
  const std::vector<double> dirs = hemisphere_directions(64);
  size_t i = 0;
  for (auto _ : state) {
    const IrradiancePoly* p = &polys[(i % n) * 3];
    const AhdLobe& l = lobes[i % n];
    const HemisphereSums h = path == 0   ? hemisphere_sums_plain(p, l, dirs.data(), 64, true)
                             : path == 1 ? hemisphere_sums_avx2(p, l, dirs.data(), 64, true)
                                         : hemisphere_sums_avx512(p, l, dirs.data(), 64, true);
    benchmark::DoNotOptimize(h);
    ++i;
  }
  state.SetItemsProcessed(int64_t(state.iterations()));
  state.SetLabel(path == 0 ? "plain" : path == 1 ? "AVX2" : "AVX-512");
}
BENCHMARK(BM_HemisphereSums)->DenseRange(0, 2)->ArgName("path");

// BM_FitTexel's texels through fit_texels in groups of 4, as fit_image hands them (the refined
// searches run in lockstep; the same bytes as fit_texel one at a time). Time per texel.
void BM_FitTexels(benchmark::State& state) {
  const int coeffs = int(state.range(0));
  const size_t n = 4096, group = 4;
  const auto polys = random_polys(coeffs, n);
  FitOptions opt;
  opt.direction_fit = state.range(1) ? DirectionFit::Refined : DirectionFit::Linear;
  opt.ratio_form = state.range(2) ? RatioForm::Rgb : RatioForm::Luminance;
  size_t i = 0;
  AhdFit f[group];
  for (auto _ : state) {
    fit_texels(&polys[(i % n) * 3], int(group), opt, f, nullptr);
    benchmark::DoNotOptimize(f);
    i += group;
  }
  state.SetItemsProcessed(int64_t(state.iterations() * group));
  state.SetLabel(std::string(coeffs == 4 ? "L1" : "L2") + (state.range(1) ? " refined" : " linear") +
                 (state.range(2) ? " rgb" : " luminance"));
}
BENCHMARK(BM_FitTexels)
    ->ArgsProduct({{4, 9}, {0, 1}, {0, 1}})
    ->ArgNames({"coeffs", "refined", "rgb"});

// A whole image on one thread: the per-texel fit plus, for refined, the coherence pass
// (fit/direction_coherence.h) and the pair guard (fit/direction_guard.h), which BM_FitTexel does
// not see. Args: direction fit (0 linear, 1 refined), ratio form (0 luminance, 1 RGB), pair guard
// (1 on, the default; 0 off: what the guard costs). Analytic scene 128², L2; time per texel.
void BM_FitImage(benchmark::State& state) {
  BakerOptions bo;
  bo.width = bo.height = 128;
  const ShImage sh = bake_analytic_scene(bo);
  FitOptions opt;
  opt.direction_fit = state.range(0) ? DirectionFit::Refined : DirectionFit::Linear;
  opt.ratio_form = state.range(1) ? RatioForm::Rgb : RatioForm::Luminance;
  if (!state.range(2)) opt.pair_guard_deg = 0;
  for (auto _ : state) benchmark::DoNotOptimize(fit_image(sh, opt, 1));
  state.SetItemsProcessed(int64_t(state.iterations()) * bo.width * bo.height);
}
BENCHMARK(BM_FitImage)
    ->ArgsProduct({{0, 1}, {0, 1}, {1}})
    ->Args({1, 0, 0})
    ->Args({1, 1, 0})
    ->ArgNames({"refined", "rgb", "guard"})
    ->Unit(benchmark::kMillisecond);

void BM_ConvertUncompressed(benchmark::State& state) {
  BakerOptions bo;
  bo.width = bo.height = int(state.range(0));
  const ShImage sh = bake_analytic_scene(bo);
  const Profile p = load_profile("uncompressed");
  PipelineOptions opt;
  opt.threads = 1;
  opt.measure = Measure::Off;
  opt.direction = state.range(1) ? DirectionPlanes::Auto : DirectionPlanes::Keep;
  for (auto _ : state) benchmark::DoNotOptimize(run_conversion(sh, p, opt));
  state.SetItemsProcessed(int64_t(state.iterations()) * bo.width * bo.height);
}
BENCHMARK(BM_ConvertUncompressed)->Args({256, 0})->Args({256, 1})->ArgNames({"size", "auto_direction"})->Unit(benchmark::kMillisecond);

}  // namespace
