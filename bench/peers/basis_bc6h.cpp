// Basis Universal's real-time BC6H encoder (`fast_encode_bc6h`) at its transcoder's "HQ" defaults
// and at its best setting (9 modes, 32 two-subset patterns, exhaustive 4-bit weights), timed on
// this machine beside `ahdpack bench bc6h`: PEERS.md's figures were measured elsewhere,
// and this VM's two vCPUs do not run the same code at the same speed (docs/notes/bc6h-issue13-rounds.md
// "BC6H against issue 13's targets"), so a side-by-side run on the same CPU is the fair comparison.
//
// Not part of the build: scripts/peer-basis-bc6h.sh compiles it against a Basis Universal checkout
// the user provides (nothing of Basis Universal is in this repository). Protocol of PEERS.md:
// g++ -O2 -march=native, one thread, thread CPU time of the encode alone (blocks already in memory as
// half floats, output already allocated), median of 5 rounds (3 for the 9-mode setting); inputs clamped to [0, 65504]. The
// error is measured with ahdpack's BC6H decoder (bit-exact with Mesa's, tests/judges/gl) as log-RMSE over
// log2(1 + x), as the bench does.
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <Imath/half.h>

#include "codecs/bc6h/bc6h_codec.h"
#include "image/image_io.h"
// basisu_transcoder.h first: basisu_astc_hdr_core.h uses what it declares.
#include "transcoder/basisu_transcoder.h"
#include "transcoder/basisu_astc_hdr_core.h"

namespace {

double thread_seconds() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

}  // namespace

int main(int argc, char** argv) {
  basist::basisu_transcoder_init();
  std::printf("image                        encoder                      cpu/thr MPix/s (median of 5; 3) log-RMSE\n");
  for (int a = 1; a < argc; ++a) {
    const ahd::ImageF img = ahd::read_image(argv[a]);
    const int w = img.width, h = img.height, bw = w / 4, bh = h / 4;  // every corpus image is a multiple of 4
    auto texel = [&](int x, int y, int c) {
      const float v = img.data[(size_t(y) * w + x) * img.channels + c];
      return std::isfinite(v) ? std::clamp(v, 0.0f, 65504.0f) : 0.0f;
    };
    std::vector<basist::half_float> blocks(size_t(bw) * bh * 48);
    for (int by = 0; by < bh; ++by)
      for (int bx = 0; bx < bw; ++bx)
        for (int t = 0; t < 16; ++t)
          for (int c = 0; c < 3; ++c)
            blocks[(size_t(by) * bw + bx) * 48 + t * 3 + c] = Imath::half(texel(bx * 4 + t % 4, by * 4 + t / 4, c)).bits();
    std::vector<basist::bc6h_block> out(size_t(bw) * bh);
    const char* name = argv[a];
    for (const char* p = argv[a]; *p; ++p)
      if (*p == '/') name = p + 1;
    for (int setting = 0; setting < 2; ++setting) {
      basist::astc_6x6_hdr::fast_bc6h_params params;  // setting 0: the "HQ" defaults PEERS.md measured
      if (setting == 1) {
        params.m_num_diff_endpoint_modes_to_try = basist::astc_6x6_hdr::BC6H_NUM_DIFF_ENDPOINT_MODES_TO_TRY_9;
        params.m_max_2subset_pats_to_try = 32;
        params.m_brute_force_weight4_assignment = true;
      }
      std::vector<double> speed;
      const int rounds = setting == 0 ? 5 : 3;
      for (int r = 0; r < rounds; ++r) {
        const double t0 = thread_seconds();
        for (size_t b = 0; b < out.size(); ++b) basist::astc_6x6_hdr::fast_encode_bc6h(&blocks[b * 48], &out[b], params);
        speed.push_back(double(w) * h / (thread_seconds() - t0) / 1e6);
      }
      std::sort(speed.begin(), speed.end());
      double sum = 0;
      for (int by = 0; by < bh; ++by)
        for (int bx = 0; bx < bw; ++bx) {
          uint16_t dec[48];
          ahd::bc6h_decode_block(out[size_t(by) * bw + bx].m_bytes, false, dec);
          for (int t = 0; t < 16; ++t)
            for (int c = 0; c < 3; ++c) {
              Imath::half v;
              v.setBits(dec[t * 3 + c]);
              const double e =
                  std::log2(1.0 + double(float(v))) - std::log2(1.0 + double(texel(bx * 4 + t % 4, by * 4 + t / 4, c)));
              sum += e * e;
            }
        }
      std::printf("%-28s %-28s %8.1f                      %.5f\n", name,
                  setting == 0 ? "Basis Universal fast (HQ)" : "Basis Universal 9 modes/32 pat", speed[speed.size() / 2],
                  std::sqrt(sum / (double(w) * h * 3)));
      std::fflush(stdout);
    }
  }
}
