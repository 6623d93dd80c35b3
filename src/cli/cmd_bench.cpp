// ahdpack bench bc6h [FOLDER] [--csv OUT.csv]: speed against error for every quality level, on
// every EXR of a folder (default: the shared BC6H test images), as PEERS.md measures them.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "cli/commands.h"
#include "codecs/bc6h_codec.h"
#include "core/error.h"
#include "core/parallel.h"
#include "io/image_io.h"

namespace ahd::cli {

ImageF clamp_to_half_range(const ImageF& img);  // cmd_compress.cpp

namespace {
namespace fs = std::filesystem;

double seconds_to_encode(const ImageF& img, Bc6hOptions o, int runs) {
  std::vector<double> t;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<uint8_t> b = bc6h_encode_image(img, o);
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];  // median
}

}  // namespace

void add_bench_command(CLI::App& app) {
  struct Args {
    std::string folder = std::string(AHD_FORMATS_DIR) + "/../../shared/data/bc6h";
    std::string csv;
    std::vector<std::string> qualities = {"fast", "default", "high", "max"};
  };
  auto a = std::make_shared<Args>();
  CLI::App* b = app.add_subcommand("bench", "Benchmarks");
  add_bench_convert_command(*b);
  CLI::App* c = b->add_subcommand("bc6h", "BC6H speed and error per quality level over a folder of EXRs");
  c->add_option("folder", a->folder, "Folder of EXR images (default: ../shared/data/bc6h)");
  c->add_option("--csv", a->csv, "Also write the table as CSV");
  c->add_option("--qualities", a->qualities, "Quality levels to run");
  c->callback([a]() {
    std::vector<fs::path> files;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(a->folder, ec))
      if (e.path().extension() == ".exr") files.push_back(e.path());
    if (ec || files.empty()) throw file_error(a->folder, "no EXR images in this folder");
    std::sort(files.begin(), files.end());
    const int all = resolve_threads(0);
    std::string csv = "image,quality,mpix_s_1thread,mpix_s_all_threads,threads,log_rmse,rmse,psnr_db,max_error\n";
    std::printf("%-22s %-8s %12s %14s %10s %10s %9s %10s\n", "image", "quality", "MPix/s (1t)", "MPix/s (all)",
                "log-RMSE", "RMSE", "PSNR dB", "max err");
    for (const auto& f : files) {
      const ImageF img = clamp_to_half_range(read_image(f.string()));
      double peak = 0;
      for (float v : img.data) peak = std::max(peak, double(v));
      for (const std::string& qn : a->qualities) {
        Bc6hOptions o;
        if (!bc6h_quality_from_name(qn, &o.quality)) throw Error("unknown quality " + qn);
        const int runs = o.quality == Bc6hQuality::Max ? 1 : 3;
        o.threads = 1;
        const double t1 = seconds_to_encode(img, o, runs);
        o.threads = all;
        const double tn = seconds_to_encode(img, o, runs);
        const std::vector<uint8_t> blocks = bc6h_encode_image(img, o);
        const ImageF dec = bc6h_decode_image(blocks.data(), img.width, img.height, false);
        double sl = 0, se = 0, mx = 0;
        for (size_t i = 0; i < img.data.size(); ++i) {
          const double l = std::log2(1.0 + dec.data[i]) - std::log2(1.0 + img.data[i]);
          sl += l * l;
          se += double(dec.data[i] - img.data[i]) * (dec.data[i] - img.data[i]);
          mx = std::max(mx, double(std::fabs(dec.data[i] - img.data[i])));
        }
        const double n = double(img.data.size()), lr = std::sqrt(sl / n), rmse = std::sqrt(se / n);
        const double psnr = 20 * std::log10(peak / rmse), mp = img.texels() / 1e6;
        std::printf("%-22s %-8s %12.3f %14.3f %10.5f %10.4g %9.2f %10.4g\n", f.filename().string().c_str(), qn.c_str(),
                    mp / t1, mp / tn, lr, rmse, psnr, mx);
        char row[256];
        std::snprintf(row, sizeof row, "%s,%s,%.4f,%.4f,%d,%.6f,%.6g,%.3f,%.6g\n", f.filename().string().c_str(), qn.c_str(),
                      mp / t1, mp / tn, all, lr, rmse, psnr, mx);
        csv += row;
      }
    }
    if (!a->csv.empty()) {
      write_file_atomic(a->csv, csv);
      std::printf("CSV: %s\n", a->csv.c_str());
    }
  });
}

}  // namespace ahd::cli
