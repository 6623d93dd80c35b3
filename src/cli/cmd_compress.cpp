// ahdpack compress IN.exr -o OUT.{dds,ktx2} --format bc6h|bc6h-signed [--quality Q]
// ahdpack decompress IN.{dds,ktx2} -o OUT.exr
// The BC6H codec on its own, for any HDR image (a texconv-like use).
#include <chrono>
#include <cmath>
#include <cstdio>

#include "cli/commands.h"
#include "codecs/bc6h/bc6h_codec.h"
#include "files/container_file.h"
#include "core/error.h"
#include "image/image_io.h"

namespace ahd::cli {

namespace {

struct Errors {
  double log_rmse = 0, rmse = 0, psnr = 0, max_err = 0;
};

// The figures of PEERS.md: log2(1+x) RMSE, RMSE, PSNR against the image's peak, max abs error.
Errors measure(const ImageF& ref, const ImageF& got) {
  double sl = 0, se = 0, peak = 0, mx = 0;
  const size_t n = ref.texels() * 3;
  for (size_t i = 0; i < ref.texels(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double a = ref.data[i * ref.channels + c], b = got.data[i * got.channels + c];
      const double l = std::log2(1 + std::max(0.0, b)) - std::log2(1 + std::max(0.0, a));
      sl += l * l;
      se += (a - b) * (a - b);
      peak = std::max(peak, a);
      mx = std::max(mx, std::fabs(a - b));
    }
  Errors e;
  e.log_rmse = std::sqrt(sl / double(n));
  e.rmse = std::sqrt(se / double(n));
  e.psnr = e.rmse > 0 ? 20 * std::log10(peak / e.rmse) : INFINITY;
  e.max_err = mx;
  return e;
}

}  // namespace

ImageF clamp_to_half_range(const ImageF& img) {
  ImageF out(img.width, img.height, 3);
  for (size_t i = 0; i < img.texels(); ++i)
    for (int c = 0; c < 3; ++c) {
      const float v = c < img.channels ? img.data[i * img.channels + c] : 0.0f;
      out.data[i * 3 + c] = std::isfinite(v) ? std::clamp(v, 0.0f, 65504.0f) : 0.0f;
    }
  return out;
}

void add_compress_commands(CLI::App& app) {
  struct Args {
    std::string input, output, format = "bc6h", quality = "default";
    int threads = 0;
    bool zstd = false;
  };
  auto a = std::make_shared<Args>();
  CLI::App* c = app.add_subcommand("compress", "Compress an HDR image to BC6H in a DDS or KTX2 file");
  c->add_option("input", a->input, "HDR image (EXR, HDR)")->required();
  c->add_option("-o,--output", a->output, "OUT.dds or OUT.ktx2")->required();
  c->add_option("--format", a->format, "bc6h (UF16) or bc6h-signed (SF16)");
  c->add_option("--quality", a->quality, "fast, default, high or max");
  c->add_option("--threads", a->threads, "Worker threads (0 = all)");
  c->add_flag("--zstd", a->zstd, "Zstandard supercompression (KTX2)");
  c->callback([a]() {
    Bc6hOptions o;
    if (a->format == "bc6h-signed") o.is_signed = true;
    else if (a->format != "bc6h") throw Error("--format must be bc6h or bc6h-signed");
    if (!bc6h_quality_from_name(a->quality, &o.quality)) throw Error("--quality must be fast, default, high or max");
    o.threads = a->threads;
    container_kind_from_path(a->output);  // refuse a bad extension before any work
    const ImageF img = read_image(a->input);
    const auto t0 = std::chrono::steady_clock::now();
    Bc6hStats st;
    Texture tex;
    tex.format = o.is_signed ? PixelFormat::BC6H_SFLOAT : PixelFormat::BC6H_UFLOAT;
    tex.levels.push_back({uint32_t(img.width), uint32_t(img.height), bc6h_encode_image(img, o, &st)});
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    write_container_file(a->output, tex, a->zstd);
    const ImageF dec = bc6h_decode_image(tex.levels[0].data.data(), img.width, img.height, o.is_signed);
    const Errors e = measure(o.is_signed ? img : clamp_to_half_range(img), dec);
    std::printf("ahdpack compress: %s (%dx%d) -> %s, %s %s, %.3f s (%.2f MPix/s)\n", a->input.c_str(), img.width,
                img.height, a->output.c_str(), a->format.c_str(), bc6h_quality_name(o.quality), s,
                img.texels() / s / 1e6);
    std::printf("  inputs changed: NaN %zu, Inf %zu, above 65504 %zu, negative %zu\n", st.nan, st.inf, st.too_large,
                st.negative);
    std::printf("  error: log-RMSE %.5f, RMSE %.4g, PSNR %.2f dB, max %.4g\n", e.log_rmse, e.rmse, e.psnr, e.max_err);
  });

  auto d = std::make_shared<Args>();
  CLI::App* x = app.add_subcommand("decompress", "Decode a BC6H DDS/KTX2 file (level 0) to EXR");
  x->add_option("input", d->input, "IN.dds or IN.ktx2")->required();
  x->add_option("-o,--output", d->output, "OUT.exr")->required();
  x->callback([d]() {
    const Texture t = read_container_file(d->input);
    if (t.format != PixelFormat::BC6H_UFLOAT && t.format != PixelFormat::BC6H_SFLOAT)
      throw file_error(d->input, std::string("holds ") + format_info(t.format).name + ", not BC6H");
    const TextureLevel& l = t.levels[0];
    write_image(d->output, bc6h_decode_image(l.data.data(), int(l.width), int(l.height), t.format == PixelFormat::BC6H_SFLOAT),
                false, {"R", "G", "B"});
    std::printf("ahdpack decompress: %s (%ux%u) -> %s\n", d->input.c_str(), l.width, l.height, d->output.c_str());
  });
}

}  // namespace ahd::cli
