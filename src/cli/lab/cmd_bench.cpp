// ahdpack bench bc6h [FOLDER ...] [--csv OUT.csv]: speed against error for every quality level, on
// every EXR of the folders (default: the shared synthetic BC6H test images, then the real-lightmap
// corpus of bench/data/real), as PEERS.md measures them; then BC4 and BC5 on LDR planes derived
// from the same images.
//
// Speed is reported three ways, because the machine is shared and wall time alone says little:
//   cpu/thr  MPix/s of one thread's CPU time (CLOCK_THREAD_CPUTIME_ID), the PEERS.md figure
//   wall 1t  MPix/s of wall time with one thread
//   wall all MPix/s of wall time with every hardware thread
//   cpu all  MPix/s per CPU-second of the process with every thread (CLOCK_PROCESS_CPUTIME_ID)
// Each is the median of 3 runs after one untimed run (1 run for BC6H max, none untimed). A run
// times one whole encode call as a caller makes it: the encoder's setup, its output vector
// (allocated and filled inside the call) and the encoding; the previous run's output is released
// before the clock starts, because freeing it is not part of this call (inside the timer, the old
// and new outputs alternated between two heap areas and about half the runs paid fresh-page
// faults for the new one: 64 faults, ≈ 7 % of a 512² BC6H default encode on this VM).
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>

#include "cli/commands.h"
#include "lab/peers_bc6h.h"
#include "cli/lab/svg_plot.h"
#include "codecs/bc4.h"
#include "codecs/bc5.h"
#include "codecs/bc6h/bc6h_codec.h"
#include "core/error.h"
#include "core/parallel.h"
#include "image/image_io.h"
#include "files/output_set.h"
#include "files/utf8_path.h"

namespace ahd::cli {

ImageF clamp_to_half_range(const ImageF& img);  // cmd_compress.cpp

namespace {
namespace fs = std::filesystem;

double clock_seconds(clockid_t id) {
  timespec ts{};
  clock_gettime(id, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

struct Timing {
  double wall = 0, cpu = 0;  // seconds (median of the runs, each taken separately)
};

// Runs `encode` `runs` times, each after an untimed `release` (which frees the previous run's
// output); cpu is the calling thread's CPU time when threads == 1 (the encoder then runs on the
// calling thread), else the whole process's CPU time.
Timing time_runs(const std::function<void()>& encode, const std::function<void()>& release, int runs,
                 bool one_thread) {
  std::vector<double> wall, cpu;
  const clockid_t id = one_thread ? CLOCK_THREAD_CPUTIME_ID : CLOCK_PROCESS_CPUTIME_ID;
  // One untimed run first when there are several: the process's first two allocations of an
  // output buffer of a given size fault its pages in (glibc maps the first one, then grows the
  // heap for the second; ≈ 16 µs per 4 KiB page on this VM, ≈ 1 ms for a 512² BC6H output, a
  // third of `fast`'s encode), so two of three runs were cold and the median was a cold run.
  // PEERS.md times the peers' encoding only, into memory already there.
  if (runs > 1) encode();
  for (int r = 0; r < runs; ++r) {
    release();
    const double c0 = clock_seconds(id);
    const auto t0 = std::chrono::steady_clock::now();
    encode();
    wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    cpu.push_back(clock_seconds(id) - c0);
  }
  std::sort(wall.begin(), wall.end());
  std::sort(cpu.begin(), cpu.end());
  return {wall[wall.size() / 2], cpu[cpu.size() / 2]};
}

struct Errors {
  double log_rmse = 0, rmse = 0, psnr = 0, max = 0;
};

// log-RMSE over log2(1 + x), RMSE, PSNR with peak = `peak`, max |error|, over the first
// `channels` channels of both images.
Errors measure(const ImageF& src, const ImageF& dec, int channels, double peak) {
  double sl = 0, se = 0, mx = 0;
  for (size_t i = 0; i < src.texels(); ++i)
    for (int c = 0; c < channels; ++c) {
      const double a = src.data[i * src.channels + c], b = dec.data[i * dec.channels + c];
      const double l = std::log2(1.0 + b) - std::log2(1.0 + a);
      sl += l * l;
      se += (b - a) * (b - a);
      mx = std::max(mx, std::fabs(b - a));
    }
  const double n = double(src.texels()) * channels;
  Errors e;
  e.log_rmse = std::sqrt(sl / n);
  e.rmse = std::sqrt(se / n);
  e.psnr = 20 * std::log10(peak / e.rmse);
  e.max = mx;
  return e;
}

// An LDR plane from an HDR image, as the pipeline's direction and ratio planes are: x/(1+x) per
// channel (a smooth map of [0, 65504] onto [0, 1)).
ImageF ldr_plane(const ImageF& img, int channels) {
  ImageF out(img.width, img.height, channels);
  for (size_t i = 0; i < img.texels(); ++i)
    for (int c = 0; c < channels; ++c) {
      const float v = img.data[i * img.channels + c];
      out.data[i * channels + c] = v / (1.0f + v);
    }
  return out;
}

struct Row {
  std::string image, codec, quality;
  Timing one, all;
  Errors err;
  double mp = 0;  // megapixels of the image
};

// The speed–error plot: one point per BC6H (image, quality) row, and PEERS.md's figures for the
// images that were measured, as labelled reference points.
std::string bc6h_plot(const std::vector<Row>& rows) {
  static const char* kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};
  static const char* kPeerColours[] = {"#bbbbbb", "#999999", "#f2c14e", "#e0a030", "#17becf", "#7fbf7f", "#4c9a4c", "#e377c2"};
  Plot p;
  p.title = "BC6H: speed against error (ahdpack bench bc6h)";
  p.x_label = "MPix/s, one thread's CPU time";
  p.y_label = "log-RMSE, log2(1+x)";
  p.note = std::string("peers: tests/data/bc6h/PEERS.md, measured ") + kPeersBc6hDate + "; labels: quality or image";
  std::vector<std::string> images;
  for (const Row& r : rows)
    if (std::find(images.begin(), images.end(), r.image) == images.end()) images.push_back(r.image);
  for (size_t i = 0; i < images.size(); ++i) {
    PlotSeries s{"ahdpack, " + images[i], "point ours", kColours[i % 6], 'o', {}};
    for (const Row& r : rows)
      if (r.image == images[i]) s.points.push_back({double(r.one.cpu > 0 ? r.mp / r.one.cpu : 0), r.err.log_rmse, r.quality});
    p.series.push_back(s);
  }
  std::vector<PlotSeries> peers;
  for (const PeerFigure& f : peers_bc6h()) {
    if (std::find(images.begin(), images.end(), f.image) == images.end()) continue;
    auto it = std::find_if(peers.begin(), peers.end(), [&](const PlotSeries& s) { return s.name == f.encoder; });
    if (it == peers.end()) {
      peers.push_back({f.encoder, "point peer", kPeerColours[peers.size() % 8], 'd', {}});
      it = peers.end() - 1;
    }
    const std::string img = f.image.substr(f.image.find('_') == std::string::npos ? 0 : f.image.find('_') + 1);
    it->points.push_back({f.mpix_per_s, f.log_rmse, img.substr(0, img.rfind('.'))});
  }
  p.series.insert(p.series.end(), peers.begin(), peers.end());
  return plot_svg(p);
}

}  // namespace

void add_bench_command(CLI::App& app) {
  struct Args {
    std::vector<std::string> folders;  // empty: the default corpus (kDefaultFolders)
    std::string csv, plot;
    std::vector<std::string> qualities = {"fast", "default", "high", "max"};
    std::vector<std::string> codecs = {"bc6h", "bc4", "bc5"};
  };
  auto a = std::make_shared<Args>();
  CLI::App* b = app.add_subcommand("bench", "Benchmarks");
  add_bench_convert_command(*b);
  CLI::App* c = b->add_subcommand(
      "bc6h", "BC6H speed and error per quality level over a folder of EXRs; BC4/BC5 on x/(1+x) planes of the same images");
  c->add_option("folder", a->folders,
                "Folders of EXR images (default: tests/data/bc6h, the synthetic images, and bench/data/real, the real "
                "lightmaps' I_z planes; a default folder that is absent is left out)");
  c->add_option("--csv", a->csv, "Also write the table as CSV");
  c->add_option("--plot", a->plot, "Also write the BC6H speed-error plot as SVG, with the peers of PEERS.md");
  c->add_option("--qualities", a->qualities, "BC6H quality levels to run (fast default high max)");
  c->add_option("--codecs", a->codecs, "Codecs to run (bc6h bc4 bc5)");
  c->callback([a]() {
    const bool defaults = a->folders.empty();
    const std::vector<std::string> folders =
        defaults ? std::vector<std::string>{std::string(AHD_FORMATS_DIR) + "/../tests/data/bc6h",
                                            std::string(AHD_FORMATS_DIR) + "/../bench/data/real"}
                 : a->folders;
    std::vector<fs::path> files;
    for (const std::string& folder : folders) {
      std::vector<fs::path> in_folder;
      std::error_code ec;
      for (const auto& e : fs::directory_iterator(fs_path(folder), ec))
        if (e.path().extension() == ".exr") in_folder.push_back(e.path());
      if (defaults && (ec || in_folder.empty())) continue;  // e.g. a checkout without bench/data
      if (ec || in_folder.empty()) throw file_error(folder, "no EXR images in this folder");
      std::sort(in_folder.begin(), in_folder.end());
      files.insert(files.end(), in_folder.begin(), in_folder.end());
    }
    if (files.empty()) throw file_error(folders.back(), "no EXR images in the default folders");
    for (const std::string& codec : a->codecs)
      if (codec != "bc6h" && codec != "bc4" && codec != "bc5") throw Error("unknown codec " + codec);
    const int all = resolve_threads(0);
    std::string csv =
        "image,codec,quality,mpix_s_thread_cpu,mpix_s_wall_1thread,mpix_s_wall_all_threads,mpix_s_cpu_all_threads,threads,"
        "log_rmse,rmse,psnr_db,max_error\n";
    std::printf("speed: MPix/s; cpu/thr = one thread's CPU time (CLOCK_THREAD_CPUTIME_ID), wall 1t / wall %dt = wall time,\n"
                "cpu %dt = per CPU-second of the process with %d threads; median of 3 runs after an untimed one (BC6H max: 1)\n",
                all, all, all);
    std::printf("%-28s %-5s %-8s %8s %8s %8s %8s %10s %10s %8s %10s\n", "image", "codec", "quality", "cpu/thr", "wall 1t",
                "wall all", "cpu all", "log-RMSE", "RMSE", "PSNR dB", "max err");
    std::vector<Row> bc6h_rows;
    auto emit = [&](const Row& r, double mp) {
      if (r.codec == "bc6h") bc6h_rows.push_back(r), bc6h_rows.back().mp = mp;
      std::printf("%-28s %-5s %-8s %8.3f %8.3f %8.3f %8.3f %10.5f %10.4g %8.2f %10.4g\n", r.image.c_str(), r.codec.c_str(),
                  r.quality.c_str(), mp / r.one.cpu, mp / r.one.wall, mp / r.all.wall, mp / r.all.cpu, r.err.log_rmse,
                  r.err.rmse, r.err.psnr, r.err.max);
      std::fflush(stdout);
      char row[320];
      std::snprintf(row, sizeof row, "%s,%s,%s,%.4f,%.4f,%.4f,%.4f,%d,%.6f,%.6g,%.3f,%.6g\n", r.image.c_str(),
                    r.codec.c_str(), r.quality.c_str(), mp / r.one.cpu, mp / r.one.wall, mp / r.all.wall,
                    mp / r.all.cpu, all, r.err.log_rmse, r.err.rmse, r.err.psnr, r.err.max);
      csv += row;
    };
    const bool want_bc6h = std::count(a->codecs.begin(), a->codecs.end(), "bc6h") > 0;
    if (want_bc6h)
      for (const std::string& qn : a->qualities) {
        Bc6hQuality q;
        if (!bc6h_quality_from_name(qn, &q)) throw Error("unknown quality " + qn);
      }
    for (const auto& f : files) {
      const ImageF img = clamp_to_half_range(read_image(utf8_string(f)));
      const std::string name = utf8_string(f.filename());
      const double mp = img.texels() / 1e6;
      double peak = 0;
      for (size_t i = 0; i < img.texels(); ++i)
        for (int ch = 0; ch < std::min(3, img.channels); ++ch) peak = std::max(peak, double(img.data[i * img.channels + ch]));
      if (want_bc6h)
        for (const std::string& qn : a->qualities) {
          Bc6hOptions o;
          bc6h_quality_from_name(qn, &o.quality);
          const int runs = o.quality == Bc6hQuality::Max ? 1 : 3;
          std::vector<uint8_t> blocks;
          Row r{name, "bc6h", qn, {}, {}, {}};
          const auto release = [&] { std::vector<uint8_t>().swap(blocks); };
          o.threads = 1;
          r.one = time_runs([&] { blocks = bc6h_encode_image(img, o); }, release, runs, true);
          o.threads = all;
          r.all = time_runs([&] { blocks = bc6h_encode_image(img, o); }, release, runs, false);
          r.err = measure(img, bc6h_decode_image(blocks.data(), img.width, img.height, false), 3, peak);
          emit(r, mp);
        }
      for (const std::string& codec : a->codecs) {
        if (codec == "bc6h") continue;
        const int channels = codec == "bc4" ? 1 : 2;
        const ImageF plane = ldr_plane(img, channels);
        static const char* efforts[] = {"fast", "default", "high"};
        for (int effort = 0; effort < 3; ++effort) {
          std::vector<uint8_t> blocks;
          auto run = [&](int threads) {
            blocks = channels == 1 ? bc4_encode_image(plane, 0, threads, effort) : bc5_encode_image(plane, threads, effort);
          };
          Row r{name, codec, efforts[effort], {}, {}, {}};
          const auto release = [&] { std::vector<uint8_t>().swap(blocks); };
          r.one = time_runs([&] { run(1); }, release, 3, true);
          r.all = time_runs([&] { run(all); }, release, 3, false);
          ImageF dec(img.width, img.height, channels);
          if (channels == 1) bc4_decode_image(blocks.data(), img.width, img.height, 8, 0, dec, 0);
          else dec = bc5_decode_image(blocks.data(), img.width, img.height);
          r.err = measure(plane, dec, channels, 1.0);
          emit(r, mp);
        }
      }
    }
    if (!a->csv.empty()) {
      write_file_atomic(a->csv, csv);
      std::printf("CSV: %s\n", a->csv.c_str());
    }
    if (!a->plot.empty()) {
      write_file_atomic(a->plot, bc6h_plot(bc6h_rows));
      std::printf("plot: %s\n", a->plot.c_str());
    }
  });
}

}  // namespace ahd::cli
