// ahdpack convert [IN.exr] [-o OUT.ktx2|OUT.dds]: SH lightmap → AHD planes + manifest + report.
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "cli/commands.h"
#include "cli/report.h"
#include "containers/container.h"
#include "core/error.h"
#include "io/image_io.h"
#include "io/sh_exr.h"
#include "pipeline/convert.h"
#include "pipeline/manifest.h"
#include "sample/analytic_baker.h"

namespace ahd::cli {
namespace fs = std::filesystem;

namespace {

struct ConvertArgs {
  std::string input;
  std::string output;
  std::string profile = "uncompressed";
  std::string ratio;  // empty: the profile's ratio form
  double dz_min = 0.05;
  bool open_loop = false;
  bool zstd = false;
  int threads = 0;
  int sample_size = 256;
  int sample_order = 2;
  unsigned seed = 0;
  bool quiet = false;
};

void run_convert(const ConvertArgs& a) {
  using Clock = std::chrono::steady_clock;
  const auto t_start = Clock::now();

  // Output naming: DIR/NAME.EXT → DIR/NAME.<plane>.EXT, DIR/NAME.json, DIR/NAME.report.json.
  std::string out = a.output;
  if (out.empty()) out = "ahdpack-out/" + (a.input.empty() ? std::string("sample") : fs::path(a.input).stem().string()) + ".ktx2";
  const ContainerKind kind = container_kind_from_path(out);
  const std::string ext = kind == ContainerKind::KTX2 ? "ktx2" : "dds";
  const fs::path dir = fs::path(out).parent_path();
  const std::string name = fs::path(out).stem().string();
  auto sibling = [&](const std::string& suffix) { return (dir / (name + suffix)).string(); };

  ConvertOptions opt;
  opt.threads = a.threads;
  opt.codec.threads = a.threads;
  opt.fit.dz_min = a.dz_min;
  opt.closed_loop = !a.open_loop;
  if (!(a.dz_min > 0 && a.dz_min < 1)) throw Error("--eps must be in (0, 1)");
  const Profile profile = load_profile(a.profile);
  if (profile.ratio_rgb) opt.fit.ratio_form = RatioForm::Rgb;
  if (a.ratio == "rgb") opt.fit.ratio_form = RatioForm::Rgb;
  else if (a.ratio == "luminance") opt.fit.ratio_form = RatioForm::Luminance;
  else if (!a.ratio.empty()) throw Error("--ratio must be 'luminance' or 'rgb'");

  // Input.
  auto t0 = Clock::now();
  ShImage sh;
  ReadStats rs;
  std::string source;
  if (a.input.empty()) {
    BakerOptions bo;
    bo.width = bo.height = a.sample_size;
    bo.coeffs = a.sample_order == 1 ? 4 : 9;
    bo.seed = a.seed;
    bo.threads = a.threads;
    sh = bake_analytic_scene(bo);
    source = "built-in sample (analytic scene, " + std::to_string(a.sample_size) + "x" + std::to_string(a.sample_size) +
             (bo.coeffs == 9 ? " L2" : " L1") + ", seed " + std::to_string(a.seed) + ")";
  } else {
    sh = read_canonical_sh(a.input, &rs);
    source = a.input + " (" + std::to_string(sh.width) + "x" + std::to_string(sh.height) + (sh.coeffs == 9 ? " L2" : " L1") +
             (sh.normals.empty() ? ", tangent space)" : ", world space + normals)");
  }
  const double read_seconds = std::chrono::duration<double>(Clock::now() - t0).count();

  ConvertResult r = convert(sh, profile, opt);
  r.timings.insert(r.timings.begin(), {a.input.empty() ? "bake sample" : "read", read_seconds});

  // Manifest + containers, all encoded in memory before anything is written.
  Manifest m;
  m.profile = profile.name;
  m.container = ext;
  m.width = uint32_t(sh.width);
  m.height = uint32_t(sh.height);
  m.levels = 1;
  m.ratio_form = opt.fit.ratio_form;
  m.dz_min = opt.fit.dz_min;
  for (int i = 0; i < 3; ++i) m.luma[i] = opt.fit.luma[i];
  m.direction_frame = sh.normals.empty() ? "tangent" : "normal-frame";
  t0 = Clock::now();
  std::vector<std::pair<std::string, std::vector<uint8_t>>> files;
  for (Plane& p : r.planes) {
    const std::string file = name + "." + p.name + "." + ext;
    p.texture.metadata = plane_metadata(m, p.name);
    files.emplace_back((dir / file).string(), encode_container(kind, p.texture, a.zstd));
    ManifestPlane mp;
    mp.name = p.name;
    mp.file = file;
    mp.format = p.texture.format;
    mp.width = p.texture.levels[0].width;
    mp.height = p.texture.levels[0].height;
    mp.levels = uint32_t(p.texture.levels.size());
    mp.bytes = files.back().second.size();
    m.planes.push_back(mp);
  }
  r.timings.push_back({"containers", std::chrono::duration<double>(Clock::now() - t0).count()});
  const double total = std::chrono::duration<double>(Clock::now() - t_start).count();
  const std::string manifest_text = manifest_to_json(m);
  nlohmann::json report = convert_report_json(r, total);
  report["source"] = source;
  report["profile"] = profile.name;
  report["read"] = {{"non_finite_texels", rs.non_finite_texels}, {"coverage_derived", rs.coverage_derived}};
  files.emplace_back(sibling(".json"), std::vector<uint8_t>(manifest_text.begin(), manifest_text.end()));
  const std::string report_text = report.dump(2) + "\n";
  files.emplace_back(sibling(".report.json"), std::vector<uint8_t>(report_text.begin(), report_text.end()));

  std::vector<std::string> written;
  try {
    for (const auto& [path, bytes] : files) {
      write_file_atomic(path, bytes);
      written.push_back(path);
    }
  } catch (...) {
    for (const auto& p : written) fs::remove(p);
    throw;
  }
  if (a.quiet) return;

  std::printf("ahdpack convert: %s\n", source.c_str());
  std::printf("profile %s -> %s\n", profile.name.c_str(), fs::path(sibling(".json")).string().c_str());
  for (const auto& p : m.planes)
    std::printf("  %-9s %-12s %ux%u  %8llu bytes  %s\n", p.name.c_str(), format_info(p.format).name, p.width, p.height,
                (unsigned long long)p.bytes, (dir / p.file).string().c_str());
  std::printf("  report    %s\n", sibling(".report.json").c_str());
  const FitStats& fs_ = r.fit_stats;
  std::printf("fit: %zu covered of %zu texels; rules fired: no direction %zu, horizon-tilted %zu, negative I_z %zu, black %zu",
              fs_.covered, fs_.texels, fs_.no_direction, fs_.dir_clamped, fs_.negative_iz, fs_.black);
  if (rs.non_finite_texels) std::printf(", non-finite input texels zeroed %zu", rs.non_finite_texels);
  std::printf("\n");
  if (r.codec_stats.clamped || r.codec_stats.non_finite)
    std::printf("codec: %zu values clamped to the format's range, %zu non-finite\n", r.codec_stats.clamped,
                r.codec_stats.non_finite);
  std::printf("error vs source SH irradiance (64 normals over the hemisphere, covered texels):\n");
  print_error_header(stdout);
  print_error_row(stdout, "fit: constrained AHD", r.fit_error);
  print_error_row(stdout, "fit: unconstrained LS", r.unconstrained_error);
  if (opt.closed_loop) print_error_row(stdout, "quantised, open loop", r.open_loop_error);
  print_error_row(stdout, opt.closed_loop ? "quantised, closed loop" : "quantised (open loop)", r.final_error);
  std::printf("time:");
  for (const auto& s : r.timings) std::printf(" %s %.3f s,", s.stage.c_str(), s.seconds);
  std::printf(" total %.3f s\n", total);
}

}  // namespace

void add_convert_command(CLI::App& app) {
  auto a = std::make_shared<ConvertArgs>();
  CLI::App* c = app.add_subcommand("convert", "Convert an SH lightmap (or, with no input, the built-in sample) to AHD planes");
  c->add_option("input", a->input, "Canonical SH EXR (sh0.R … sh8.B); omit for the built-in sample");
  c->add_option("-o,--output", a->output, "OUT.ktx2 or OUT.dds: writes OUT.<plane>.<ext>, OUT.json, OUT.report.json");
  c->add_option("--profile", a->profile, "Output profile name or .json file (formats/profiles)");
  c->add_option("--ratio", a->ratio, "Ratio form: luminance (one channel) or rgb (default: the profile's)");
  c->add_option("--eps", a->dz_min, "Smallest stored d_z (the horizon rule)");
  c->add_flag("--open-loop", a->open_loop, "Quantise the ratio from the unquantised fit (for comparison)");
  c->add_flag("--zstd", a->zstd, "Zstandard supercompression (KTX2)");
  c->add_option("--threads", a->threads, "Worker threads (0 = all)");
  c->add_option("--sample-size", a->sample_size, "Built-in sample: width and height")->check(CLI::Range(1, 8192));
  c->add_option("--sample-order", a->sample_order, "Built-in sample: SH order 1 (L1) or 2 (L2)")->check(CLI::IsMember({1, 2}));
  c->add_option("--seed", a->seed, "Built-in sample: scene seed (0 = canonical)");
  c->add_flag("-q,--quiet", a->quiet, "Print nothing on success");
  c->callback([a]() { run_convert(*a); });
}

}  // namespace ahd::cli
