// The stages of a plain lightmap's conversion (issue 28) on the real 2048² Godot ragdoll bake
// (tests/data/bakes/godot-ragdoll-plain), one thread each: the CPU column is what a change to one
// stage moves, load-independent. `ahdpack bench convert --plain-file …` times the whole process.
#include <benchmark/benchmark.h>

#include <string>

#include "fit/fit_image.h"
#include "bakers/baker_layout.h"
#include "files/profile_file.h"
#include "mips/dilate.h"
#include "mips/mips.h"
#include "pipeline/convert.h"

using namespace ahd;

namespace {

const std::string kRagdoll = std::string(AHD_SOURCE_DIR) + "/tests/data/bakes/godot-ragdoll-plain/ragdoll_physics";

ShImage read_ragdoll() { return read_layout(load_layout("plain"), kRagdoll, std::string()); }

const ShImage& ragdoll() {
  static const ShImage sh = read_ragdoll();
  return sh;
}

void BM_PlainRead(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(read_ragdoll());
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(ragdoll().texels()));
}
BENCHMARK(BM_PlainRead)->Unit(benchmark::kMillisecond);

void BM_PlainFitStats(benchmark::State& state) {
  const ShImage& sh = ragdoll();
  for (auto _ : state) benchmark::DoNotOptimize(ambient_fit_stats(sh, FitOptions{}, 1));
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(sh.texels()));
}
BENCHMARK(BM_PlainFitStats)->Unit(benchmark::kMillisecond);

// Level 0's dilation (the copy it works on is made outside the timed part).
void BM_PlainDilate(benchmark::State& state) {
  for (auto _ : state) {
    state.PauseTiming();
    ShImage sh = ragdoll();
    state.ResumeTiming();
    dilate_ambient(sh, 1);
    benchmark::DoNotOptimize(sh.data.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(ragdoll().texels()));
}
BENCHMARK(BM_PlainDilate)->Unit(benchmark::kMillisecond);

void BM_PlainDownsample(benchmark::State& state) {
  ShImage sh = ragdoll();
  dilate_ambient(sh, 1);
  for (auto _ : state) benchmark::DoNotOptimize(downsample_sh(sh, 1));
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(sh.texels()));
}
BENCHMARK(BM_PlainDownsample)->Unit(benchmark::kMillisecond);

// Everything after the read: mips, dilation, the I_z planes in BC6H (pc-bc), the error estimate.
void BM_PlainConvert(benchmark::State& state) {
  const Profile p = load_profile("pc-bc");
  PipelineOptions opt;
  opt.threads = 1;
  opt.measure = state.range(0) ? Measure::Estimate : Measure::Off;
  for (auto _ : state) {
    state.PauseTiming();
    ShImage sh = ragdoll();
    state.ResumeTiming();
    benchmark::DoNotOptimize(run_conversion(std::move(sh), p, opt));
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(ragdoll().texels()));
}
BENCHMARK(BM_PlainConvert)->Arg(0)->Arg(1)->ArgName("estimate")->Unit(benchmark::kMillisecond);

}  // namespace
