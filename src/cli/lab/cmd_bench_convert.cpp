// ahdpack bench convert: the whole pipeline (read → mips, fit, dilate → direction decision →
// quantise + encode → write), pc-bc, default options, full mip chain, on generated L2 inputs and a
// plain lightmap written as EXR files first; beside it, the time OpenImageIO alone takes to read the
// same file, and the conversion's peak resident memory above the process's idle baseline.
//
// How memory is measured: each conversion (and each OIIO-only read) runs in a fresh process, this
// same binary re-executed (`--child`; a plain fork() would inherit OpenEXR's thread pool without its
// threads). The child resets its high-water mark (/proc/self/clear_refs "5"), reads VmRSS as its idle
// baseline (libraries loaded, nothing read), runs, and prints VmHWM − baseline. So nothing a
// previous case allocated or freed can hide or inflate a figure.
// POSIX only (fork, execv, getrusage, /proc): on Windows lab/cmd_bench_convert_win32.cpp.
#ifndef _WIN32
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

#include "core/option_enums.h"
#include "cli/commands.h"
#include "api/options.h"
#include "cli/output.h"
#include "core/error.h"
#include "core/parallel.h"
#include "fit/direction_refine.h"
#include "fit/hemisphere_error.h"
#include "bakers/baker_layout.h"
#include "image/image_io.h"
#include "image/oiio_module.h"
#include "image/sh_exr.h"
#include "pipeline/run.h"
#include "sample/analytic_baker.h"
#include "files/utf8_path.h"

namespace ahd::cli {
namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// kB from a "Name:   123 kB" line of /proc/self/status (0 when absent).
long status_kb(const char* name) {
  std::ifstream f("/proc/self/status");
  std::string line;
  const size_t n = std::strlen(name);
  while (std::getline(f, line))
    if (line.compare(0, n, name) == 0 && line.size() > n && line[n] == ':') return std::atol(line.c_str() + n + 1);
  return 0;
}

// CPU seconds (user + system, every thread) this process has used so far: unlike wall time, not
// inflated by other processes sharing the machine.
double seconds_of(const rusage& u) {
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}
double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return seconds_of(u);
}

void reset_peak_rss() {
  std::ofstream f("/proc/self/clear_refs");
  if (f) f << "5";
}

// Starts this executable again with argv_s (argv_s[0] is its name); with `pipe_fds`, its standard
// output goes to pipe_fds[1] (both ends closed in the child). Returns the child's pid.
// default_malloc: the child leaves glibc's allocator as it is (AHD_MALLOC_DEFAULTS, src/cli/main.cpp),
// as an application that reads with OpenImageIO would.
pid_t exec_self(std::vector<std::string> argv_s, const int* pipe_fds = nullptr, bool default_malloc = false) {
  std::vector<char*> argv;
  for (std::string& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::fflush(stdout);
  const pid_t pid = fork();
  if (pid < 0) throw Error("bench convert: fork() failed");
  if (pid == 0) {
    if (pipe_fds) {
      dup2(pipe_fds[1], 1);
      close(pipe_fds[0]);
      close(pipe_fds[1]);
    }
    if (default_malloc) setenv("AHD_MALLOC_DEFAULTS", "1", 1);
    execv("/proc/self/exe", argv.data());
    _exit(127);
  }
  return pid;
}

// Runs `ahdpack bench convert --child MODE FILE OUTDIR --threads N [--full-measure]` and parses the
// "key=value" lines it prints.
std::map<std::string, std::string> run_child(const std::vector<std::string>& args) {
  int fd[2];
  if (pipe(fd) != 0) throw Error("bench convert: pipe() failed");
  std::vector<std::string> argv_s = {"ahdpack", "bench", "convert"};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  // OpenImageIO's own read (the baseline) runs with the allocator an application has.
  const pid_t pid = exec_self(argv_s, fd, args.size() > 1 && args[1] == "read");
  close(fd[1]);
  std::string text;
  char buf[4096];
  for (ssize_t r; (r = read(fd[0], buf, sizeof buf)) > 0;) text.append(buf, size_t(r));
  close(fd[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  std::map<std::string, std::string> kv;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    const size_t eq = line.find('=');
    if (eq != std::string::npos) kv[line.substr(0, eq)] = line.substr(eq + 1);
  }
  if (kv.count("error")) throw Error("bench convert: " + kv["error"]);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !kv.count("peak_rss_kb"))
    throw Error("bench convert: the measuring child process failed (killed or out of memory?)");
  return kv;
}

// A generated L2 input of any size: the analytic scene baked at up to 256² (its charts, shadows and
// coloured lights), bilinearly enlarged (SH is linear, so every texel is still a valid SH) with
// nearest-texel coverage. Baking 4096² directly would take longer than what it measures.
ShImage generated_l2(int size, int threads) {
  BakerOptions bo;
  bo.width = bo.height = std::min(size, 256);
  bo.coeffs = 9;
  bo.threads = threads;
  const ShImage src = bake_analytic_scene(bo);
  if (src.width == size) return src;
  ShImage dst = make_sh_image(size, size, 9);
  const int nv = 27;
  const double scale = double(src.width) / size;
  parallel_for(size_t(size), threads, 1, [&](size_t y) {
    const double v = (double(y) + 0.5) * scale - 0.5;
    const int y0 = std::clamp(int(std::floor(v)), 0, src.height - 1), y1 = std::min(y0 + 1, src.height - 1);
    const double fy = std::clamp(v - y0, 0.0, 1.0);
    const int yn = std::min(src.height - 1, int((double(y) + 0.5) * scale));
    for (int x = 0; x < size; ++x) {
      const double u = (double(x) + 0.5) * scale - 0.5;
      const int x0 = std::clamp(int(std::floor(u)), 0, src.width - 1), x1 = std::min(x0 + 1, src.width - 1);
      const double fx = std::clamp(u - x0, 0.0, 1.0);
      const int xn = std::min(src.width - 1, int((double(x) + 0.5) * scale));
      const size_t o = size_t(y) * size + x;
      dst.coverage[o] = src.coverage[size_t(yn) * src.width + xn];
      float* t = dst.texel(o);
      const float *a = src.texel(size_t(y0) * src.width + x0), *b = src.texel(size_t(y0) * src.width + x1),
                  *c = src.texel(size_t(y1) * src.width + x0), *d = src.texel(size_t(y1) * src.width + x1);
      for (int k = 0; k < nv; ++k)
        t[k] = dst.coverage[o] ? float((a[k] * (1 - fx) + b[k] * fx) * (1 - fy) + (c[k] * (1 - fx) + d[k] * fx) * fy)
                               : 0.0f;
    }
  });
  return dst;
}

// A plain lightmap (3 half channels, E/π along the normal, 0 outside the charts) of the same scene.
void write_plain(const std::string& path, const ShImage& sh) {
  ImageF img(sh.width, sh.height, 3);
  const double z[3] = {0, 0, 1};
  for (size_t i = 0; i < sh.texels(); ++i) {
    if (!sh.coverage[i]) continue;
    IrradiancePoly p[3];
    local_polys(sh, i, p);
    for (int c = 0; c < 3; ++c) img.data[i * 3 + c] = float(std::max(0.0, eval_irradiance(p[c], z)) / kPi);
  }
  write_image(path, img, true, {"R", "G", "B"});
}

struct Case {
  std::string label;
  std::string file;  // what OIIO reads
  std::string base;  // what ahdpack reads (the file, or the layout's base path)
  bool plain = false;
  int size = 0;  // width and height of a generated input; 0 for a given file (width × height below)
  int width = 0, height = 0;
  int coeffs = 9;  // of the SH input (plain: 1)
};

// The L1 part of an L2 image (the first 4 coefficients of every texel).
ShImage l1_of(const ShImage& l2) {
  ShImage l1 = make_sh_image(l2.width, l2.height, 4);
  l1.coverage = l2.coverage;
  for (size_t i = 0; i < l2.texels(); ++i) std::copy_n(l2.texel(i), 12, l1.texel(i));
  return l1;
}

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

// The middle value of v (the upper one of an even count), which it reorders; v not empty.
double median(std::vector<double>& v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// `ahdpack convert` itself, as a user runs it: a new process each time, its start included (the
// dynamic loader, the command line, the thread pool, the files written). Median of `runs` runs of
// CPU (user + system, from wait4) and wall seconds.
struct ProcessCost {
  double cpu = 0, wall = 0;
};
ProcessCost convert_process(const Case& c, const fs::path& out_dir, int threads, const std::string& direction_fit,
                            int runs) {
  std::vector<double> cpu, wall;
  for (int r = 0; r < runs; ++r) {
    std::error_code ec;
    fs::remove_all(out_dir, ec);  // a fresh folder each run: no previous output set to replace
    std::vector<std::string> argv_s = {"ahdpack", "convert", c.file, "-o", utf8_string(out_dir / "x.ktx2"),
                                       "-q", "--profile", "pc-bc", "--threads", std::to_string(threads)};
    if (!direction_fit.empty()) argv_s.insert(argv_s.end(), {"--direction-fit", direction_fit});
    const auto t0 = Clock::now();
    const pid_t pid = exec_self(argv_s);
    int status = 0;
    rusage u{};
    wait4(pid, &status, 0, &u);
    wall.push_back(since(t0));
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
      throw Error("bench convert: `ahdpack convert " + argv_s[2] + "` failed");
    cpu.push_back(seconds_of(u));
  }
  return {median(cpu), median(wall)};
}

// OpenImageIO's read of one file, `runs` times (each in a fresh child): the median of its CPU and of
// its wall seconds, the rest (peak, channels) of the first run. One read of a small file varies by
// ±50 % on a shared VM, and every ratio below is divided by it.
std::map<std::string, std::string> median_read(const std::string& child, const std::string& file, int runs) {
  std::map<std::string, std::string> first = run_child({"--child", child, "--child-file", file});
  std::vector<double> cpu = {std::stod(first.at("cpu"))}, wall = {std::stod(first.at("seconds"))};
  for (int r = 1; r < runs; ++r) {
    const auto more = run_child({"--child", child, "--child-file", file});
    cpu.push_back(std::stod(more.at("cpu")));
    wall.push_back(std::stod(more.at("seconds")));
  }
  first["cpu"] = std::to_string(median(cpu));
  first["seconds"] = std::to_string(median(wall));
  return first;
}

// The conversion of one case, in the child: what `ahdpack convert IN -o OUT --profile pc-bc` runs.
// direction_fit: "linear" or "refined"; empty keeps the conversion's default.
std::string convert_case(const Case& c, const std::string& out_dir, int threads, bool full_measure,
                         const std::string& direction_fit) {
  reset_peak_rss();
  const long baseline_kb = status_kb("VmRSS");
  std::ostringstream o;
  const double cpu0 = cpu_seconds();
  // Exactly what `ahdpack convert IN -o OUT.ktx2 --profile pc-bc` runs: the library's options and
  // run, with the input moved in (it becomes mip level 0, no copy).
  ConversionOptions co;
  co.profile = "pc-bc";
  co.threads = threads;
  co.measure = full_measure ? Measure::Full : Measure::Estimate;
  if (!direction_fit.empty() && !parse_direction_fit(direction_fit, &co.direction_fit))
    throw Error("--direction-fit must be 'linear' or 'refined'");
  const OutputPaths out = output_paths(out_dir + "/" + utf8_string(fs_path(c.file).stem()) + ".ktx2");
  ResolvedOptions ro = resolve_options(co, out.name);
  auto t_start = Clock::now();
  auto t0 = Clock::now();
  ReadStats rs;
  ShImage sh = c.plain ? read_layout(load_layout("plain"), c.base, std::string(), &rs) : read_canonical_sh(c.base, &rs);
  ro.package.world_frame = !sh.normals.empty();
  const double read_s = since(t0);
  const long read_peak_kb = status_kb("VmHWM") - baseline_kb;
  ConversionRun run = run_conversion(std::move(sh), ro.profile, ro.convert, ro.package, {{"read", read_s}});
  t0 = Clock::now();
  publish_conversion(out, std::move(run.output.files));  // the summary needs the manifest, not the bytes
  run.result.timings.push_back({"write", since(t0)});
  const double total = since(t_start);
  o << "peak_rss_kb=" << (status_kb("VmHWM") - baseline_kb) << "\nread_peak_kb=" << read_peak_kb << "\n";
  o << "total=" << total << "\ncpu=" << cpu_seconds() - cpu0 << "\n";
  std::string stages;
  double estimate = 0;  // the error estimate's stages (with --full-measure: the full measurement)
  for (const StageCost& st : run.result.timings) {
    stages += st.stage + ": " + fmt("%.2f", st.seconds) + " | ";
    if (st.stage.rfind("measure", 0) == 0) estimate += st.seconds;
  }
  o << "stages=" << stages.substr(0, stages.size() - 3) << "\n";
  o << "estimate=" << estimate << "\n";
  return o.str();
}

// OpenImageIO alone reading the file into a float buffer. huge_pages = false: a std::vector, as
// an application would (the issue's baseline); true: the buffer ahdpack's own reader uses, advised
// for 2 MB pages (core/large_buffer.h), printed beside it so the gain of that advice is visible.
std::string oiio_read_case(const Case& c, bool huge_pages) {
  // OpenImageIO is loaded before the clock starts: its read is measured, not its start-up.
  const OiioModule& oiio = oiio_module(c.file);
  reset_peak_rss();
  const long baseline_kb = status_kb("VmRSS");
  const auto t0 = Clock::now();
  const double cpu0 = cpu_seconds();
  int channels = 0;
  if (huge_pages) {
    channels = read_image(c.file).channels;
  } else {
    std::vector<float> px;
    std::string why;
    channels = oiio.read_file(c.file, &px, &why);
    if (channels == 0) throw Error(c.file + ": cannot read (" + why + ")");
  }
  const double s = since(t0);
  std::ostringstream o;
  o << "cpu=" << cpu_seconds() - cpu0 << "\nseconds=" << s << "\npeak_rss_kb=" << (status_kb("VmHWM") - baseline_kb) << "\nchannels=" << channels << "\n";
  return o.str();
}

}  // namespace

void add_bench_convert_command(CLI::App& bench) {
  struct Args {
    std::vector<int> sizes = {1024, 2048};
    std::vector<int> plain = {2048};
    std::vector<int> l1;
    std::vector<std::string> plain_files;  // real plain lightmaps (any RGB EXR the plain layout reads)
    int threads = 0;
    std::string dir;
    bool full_measure = false;
    int process_runs = 5;  // whole `ahdpack convert` processes per case (0: none)
    std::vector<std::string> direction_fit;  // empty: the conversion's default only
    std::string child;  // internal: "read", "l2" or "plain" — measure one case in this process
    std::string child_file, child_out;
  };
  auto a = std::make_shared<Args>();
  CLI::App* c = bench.add_subcommand("convert", "Whole-pipeline time, OIIO read time and peak memory on generated inputs");
  c->add_option("--sizes", a->sizes, "Sizes of the generated L2 inputs (default 1024 2048; add 4096, slow; 0 = none)")
      ->check(CLI::IsMember({0}) | CLI::Range(4, 16384));
  c->add_option("--l1", a->l1, "Sizes of generated L1 inputs (the L2 inputs' first band; default none)")
      ->check(CLI::Range(4, 16384));
  c->add_option("--plain", a->plain, "Sizes of the generated plain lightmaps (default 2048; 0 = none)")
      ->check(CLI::Range(0, 16384));
  c->add_option("--plain-file", a->plain_files,
                "Real plain lightmaps (RGB EXRs, e.g. the plain bake in tests/data/bakes), "
                "converted with the plain layout beside the generated inputs")
      ->check(CLI::ExistingFile);
  c->add_option("--threads", a->threads, "Worker threads (0 = all)");
  c->add_option("--dir", a->dir, "Folder for the generated inputs and outputs (default: a fresh temp folder, removed after)");
  c->add_option("--process-runs", a->process_runs,
                 "Whole `ahdpack convert` processes timed per input, start included (median; 0 = none); as many OpenImageIO reads (at least one)")
      ->check(CLI::Range(0, 100));
  c->add_flag("--full-measure", a->full_measure, "Measure every texel (--measure full) instead of the default estimate");
  c->add_option("--direction-fit", a->direction_fit,
                "Direction fits to convert each input with, one row each (the --direction-fit values; default: the "
                "conversion's default only), e.g. --direction-fit linear refined to compare them")
      ->check(CLI::IsMember([] {
        std::vector<std::string> names;
        for (const auto& f : kDirectionFits) names.push_back(f.name);  // the strategy table (core/option_enums.h)
        return names;
      }()));
  c->add_option("--child", a->child)->group("");  // hidden: the measuring child process
  c->add_option("--child-file", a->child_file)->group("");
  c->add_option("--child-out", a->child_out)->group("");
  c->callback([a]() {
    if (!a->child.empty()) {
      Case cs{"", a->child_file, a->child_file, a->child == "plain", 0};
      if (cs.plain) cs.base = cs.file.substr(0, cs.file.size() - 4);  // the layout's base: FILE without ".exr"
      try {
        std::fputs((a->child == "read" || a->child == "read-huge" ? oiio_read_case(cs, a->child == "read-huge")
                                       : convert_case(cs, a->child_out, resolve_threads(a->threads), a->full_measure,
                                                      a->direction_fit.empty() ? std::string() : a->direction_fit[0]))
                       .c_str(),
                   stdout);
      } catch (const std::exception& e) {
        std::printf("error=%s\n", e.what());
      }
      return;
    }
    const bool own_dir = a->dir.empty();
    const fs::path dir = own_dir ? fs::temp_directory_path() / ("ahdpack-bench-convert-" + std::to_string(getpid()))
                                 : fs_path(a->dir);
    fs::create_directories(dir);
    const int threads = resolve_threads(a->threads);
    std::vector<Case> cases;
    for (int s : a->sizes) {
      if (s == 0) continue;
      const std::string f = utf8_string(dir / ("l2_" + std::to_string(s) + ".exr"));
      write_canonical_sh(f, generated_l2(s, threads));
      cases.push_back({"L2 " + std::to_string(s) + "²", f, f, false, s});
    }
    for (int s : a->l1) {
      const std::string f = utf8_string(dir / ("l1_" + std::to_string(s) + ".exr"));
      write_canonical_sh(f, l1_of(generated_l2(s, threads)));
      cases.push_back({"L1 " + std::to_string(s) + "²", f, f, false, s, 4});
    }
    for (int s : a->plain) {
      if (s == 0) continue;
      const std::string base = utf8_string(dir / ("plain_" + std::to_string(s)));
      write_plain(base + ".exr", generated_l2(s, threads));
      cases.push_back({"plain " + std::to_string(s) + "²", base + ".exr", base, true, s, 1});
    }
    for (const std::string& f : a->plain_files) {
      const ImageFileInfo info = read_image_info(f);
      Case cs{utf8_string(fs_path(f).stem()).substr(0, 12), f, f.substr(0, f.size() - utf8_string(fs_path(f).extension()).size()),
              true, 0, 1};
      cs.width = info.width, cs.height = info.height;
      cases.push_back(cs);
    }
    std::printf("ahdpack bench convert: pc-bc, default options, full mips, %d thread(s)%s\n", threads,
                a->full_measure ? ", full error measurement" : ", error estimate (the default)");
    std::printf("%-12s %8s %9s %9s %7s %9s %10s %8s %9s %10s\n", "input", "MTexels", "total s", "OIIO s", "ratio",
                "MTexel/s", "peak MB", "B/texel", "x input", "estimate");
    // OpenImageIO's read of each input (the median of --process-runs reads, at least one), then one
    // conversion per requested direction fit (the rows of one input share the read they are divided by).
    std::vector<std::string> fits = a->direction_fit;
    if (fits.empty()) fits.push_back("");
    for (const Case& cs : cases) {
      const int read_runs = std::max(1, a->process_runs);
      const auto rd = median_read("read", cs.file, read_runs);
      const auto rh = median_read("read-huge", cs.file, read_runs);
      for (const std::string& fit : fits) {
        std::vector<std::string> args = {"--child", cs.plain ? "plain" : "l2", "--child-file", cs.file, "--child-out",
                                         utf8_string(dir / "out"), "--threads", std::to_string(threads)};
        if (a->full_measure) args.push_back("--full-measure");
        if (!fit.empty()) args.insert(args.end(), {"--direction-fit", fit});
        const auto cv = run_child(args);
        const std::string label = fit.empty() ? cs.label : cs.label + " " + fit;
        const double texels = cs.size ? double(cs.size) * cs.size : double(cs.width) * cs.height,
                     total = std::stod(cv.at("total"));
        const double oiio = std::stod(rd.at("seconds")), est = std::stod(cv.at("estimate"));
        const double peak = std::stod(cv.at("peak_rss_kb")) * 1024.0;
        const double decoded = texels * (cs.plain ? 3 : cs.coeffs * 3) * 4.0;  // the input as float: RGB, or the SH
        std::printf("%-12s %8.2f %9.2f %9.2f %7.2f %9.2f %10.1f %8.1f %9.2f %5.2fs %.1f%%\n", label.c_str(),
                    texels / 1e6, total, oiio, total / oiio, texels / 1e6 / total, peak / 1048576.0, peak / texels,
                    peak / decoded, est, 100.0 * est / total);
        std::printf("    stages: %s\n", cv.at("stages").c_str());
        std::printf("    peak while reading: %.1f B/texel (x%.2f input)\n",
                    std::stod(cv.at("read_peak_kb")) * 1024.0 / texels, std::stod(cv.at("read_peak_kb")) * 1024.0 / decoded);
        std::printf("    CPU seconds (all threads, load-independent): conversion %.2f, OIIO read %.2f, ratio %.2f\n",
                    std::stod(cv.at("cpu")), std::stod(rd.at("cpu")), std::stod(cv.at("cpu")) / std::stod(rd.at("cpu")));
        std::printf("    peak / decoded input: %.2f (%.1f MB above baseline, decoded %.1f MB)\n", peak / decoded,
                    peak / 1048576.0, decoded / 1048576.0);
        std::printf("    OIIO read alone: peak %.1f MB above baseline (%.1f B/texel)\n",
                    std::stod(rd.at("peak_rss_kb")) / 1024.0, std::stod(rd.at("peak_rss_kb")) * 1024.0 / texels);
        std::printf("    OIIO read into a buffer advised for huge pages (as ahdpack reads): %.2f s, total / that %.2f\n",
                    std::stod(rh.at("seconds")), total / std::stod(rh.at("seconds")));
        if (a->process_runs > 0) {
          const ProcessCost pc = convert_process(cs, dir / "process", threads, fit, a->process_runs);
          std::printf("    whole process (`ahdpack convert`, its start included; median of %d): CPU %.3f s, wall %.3f s; "
                      "/ OIIO read: CPU %.2f, wall %.2f\n",
                      a->process_runs, pc.cpu, pc.wall, pc.cpu / std::stod(rd.at("cpu")), pc.wall / oiio);
        }
      }
    }
    if (own_dir) fs::remove_all(dir);
  });
}

}  // namespace ahd::cli
#endif  // !_WIN32
