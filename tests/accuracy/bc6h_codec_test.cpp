// BC6H on the shared HDR images (tests/data/bc6h, PEERS.md): default, max on crops and fast
// against the public encoders' error. The codec's unit tests: tests/unit/bc6h_codec_test.cpp.
#include <gtest/gtest.h>

#include <Imath/half.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <set>

#include "codecs/bc6h/bc6h_codec.h"
#include "codecs/bc6h/bc6h_fast.h"
#include "codecs/bc6h/bc6h_search_avx2.h"
#include "codecs/bc6h/bc6h_tables.h"
#include "core/cpu.h"
#include "image/image_io.h"
#include "lab/truth_file.h"
#include "sanitized.h"
#include "test_data.h"
#include "bc6h_fixture.h"

using namespace ahd;
using namespace ahd_fixture::bc6h_fixture;


TEST(Bc6h, SharedImagesBeatTheFastestPublicEncoder) {
  // PEERS.md: CVTT fastest setting reaches log-RMSE 0.00965 / 0.01501 / 0.1030. `default` must
  // also stay at or below issue 13's bounds: the full search it replaced on smooth and hard
  // (0.00864 / 0.00795; smooth measured 0.00831 since the fourth round's skips, bound 0.00840;
  // hard 0.0079432) and Basis Universal's best setting on noisy (0.04606; measured 0.04573).
  const struct {
    const char* file;
    double cvtt_fastest, bound, max_slack;
  } images[] = {{"lightmap_smooth.exr", 0.00965, 0.00840, 1.0001},
                {"hdr_hard.exr", 0.01501, 0.00795, 1.0001},
                {"lightmap_noisy.exr", 0.1030, 0.04606, 1.0001}};
  for (const auto& im : images) {
    const std::filesystem::path path = ahd_test::test_data("bc6h") / im.file;
    AHD_REQUIRE_DATA(path);
    const ImageF src = clamp_rgb(read_image(path.string()));
    Bc6hOptions o;
    const std::vector<uint8_t> b = bc6h_encode_image(src, o);
    const double e = log_rmse(src, bc6h_decode_image(b.data(), src.width, src.height, false));
    std::printf("%s: default log-RMSE %.5f (CVTT fastest %.5f)\n", im.file, e, im.cvtt_fastest);
    EXPECT_LT(e, im.cvtt_fastest) << im.file;
    EXPECT_LE(e, im.bound) << im.file;
    // max on a crop: not worse than default there (within max_slack).
    ImageF crop(64, 64, 3);
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x)
        for (int c = 0; c < 3; ++c) crop.at(x, y)[c] = src.at(x + 96, y + 96)[c];
    Bc6hOptions mx;
    mx.quality = Bc6hQuality::Max;
    const std::vector<uint8_t> bm = bc6h_encode_image(crop, mx), bd = bc6h_encode_image(crop, o);
    EXPECT_LE(log_rmse(crop, bc6h_decode_image(bm.data(), 64, 64, false)),
              log_rmse(crop, bc6h_decode_image(bd.data(), 64, 64, false)) * im.max_slack)
        << im.file;
  }
}

TEST(Bc6h, MaxOnCropsOfTheSharedImages) {
  // Issue 13: `max` polishes its best candidates on the quantised lattice (search_max). On the
  // whole images it measured log-RMSE 0.00507 / 0.00706 / 0.04297, below every encoder of
  // PEERS.md (DirectXTex 0.00651 on smooth, CVTT 0.01501 on hard, Basis Universal 0.04606 on
  // noisy); the full images take minutes here, so this checks the 128² crop at (128, 128) of
  // each against what it measured there (+1 %), against `default` on the same crop, and for
  // specks.
  const struct {
    const char* file;
    double measured;
  } images[] = {{"lightmap_smooth.exr", 0.009842}, {"hdr_hard.exr", 0.002005}, {"lightmap_noisy.exr", 0.045290}};
  for (const auto& im : images) {
    const std::filesystem::path path = ahd_test::test_data("bc6h") / im.file;
    AHD_REQUIRE_DATA(path);
    const ImageF src = clamp_rgb(read_image(path.string()));
    ImageF crop(128, 128, 3);
    for (int y = 0; y < 128; ++y)
      for (int x = 0; x < 128; ++x)
        for (int c = 0; c < 3; ++c) crop.at(x, y)[c] = src.at(x + 128, y + 128)[c];
    Bc6hOptions mx, df;
    mx.quality = Bc6hQuality::Max;
    const std::vector<uint8_t> bm = bc6h_encode_image(crop, mx), bd = bc6h_encode_image(crop, df);
    const double em = log_rmse(crop, bc6h_decode_image(bm.data(), 128, 128, false));
    const double ed = log_rmse(crop, bc6h_decode_image(bd.data(), 128, 128, false));
    std::printf("%s crop: max log-RMSE %.6f, default %.6f\n", im.file, em, ed);
    EXPECT_LE(em, im.measured * 1.01) << im.file;
    EXPECT_LT(em, ed) << im.file;
    expect_sane(crop, false, Bc6hQuality::Max, im.file);
  }
}

TEST(Bc6h, FastBeatsTheRealTimePeerOnTheSharedImages) {
  // PEERS.md (2026-12-01): Basis Universal's real-time encoder, log-RMSE 0.01247 / 0.02072 /
  // 0.04633. Its speed is compared by `ahdpack bench bc6h`, not here (no timed assertions).
  // On the noisy image one region does not reach it (0.04687); the two-region candidate for the
  // blocks one region fits poorly (bc6h_fast_two_region.cpp) brings it to 0.04629.
  const struct {
    const char* file;
    double basis, bound;
  } images[] = {{"lightmap_smooth.exr", 0.01247, 0.01247}, {"hdr_hard.exr", 0.02072, 0.02072},
                {"lightmap_noisy.exr", 0.04633, 0.04633}};
  for (const auto& im : images) {
    const std::filesystem::path path = ahd_test::test_data("bc6h") / im.file;
    AHD_REQUIRE_DATA(path);
    const ImageF src = clamp_rgb(read_image(path.string()));
    Bc6hOptions o;
    o.quality = Bc6hQuality::Fast;
    const std::vector<uint8_t> b = bc6h_encode_image(src, o);
    const double e = log_rmse(src, bc6h_decode_image(b.data(), src.width, src.height, false));
    std::printf("%s: fast log-RMSE %.5f (Basis Universal real-time %.5f)\n", im.file, e, im.basis);
    EXPECT_LE(e, im.bound) << im.file;
  }
}

TEST(Bc6h, FastBeatsBasisHqOnThePathTracedBakes) {
  // Issue 45's wider corpus (docs/bc6h-real.md "A wider real corpus: the path-traced bakes' I_z"):
  // the irradiance along the normal of the nine Cycles bakes of tests/data/truth, uncovered texels
  // 0 (as scripts/truth-iz-exr.py writes them). Basis Universal HQ's log-RMSE on each, measured
  // side by side (scripts/peer-basis-bc6h.sh, Basis Universal 9bebe16). `fast` must stay below it;
  // `default` keeps `fast`'s block where it decodes closer, so it is not worse than `fast`; the
  // SIMD and scalar paths write the same bytes (the colour-noise and edge routes of
  // bc6h_fast_two_region.cpp run on nearly every block here).
  const struct {
    const char* bake;
    double basis_hq;
  } bakes[] = {{"area", 0.06498},          {"cornell_area", 0.03570}, {"cornell_sun_256", 0.02386},
               {"cornell_sun", 0.02589},   {"cornell_tight", 0.04952}, {"emissive", 0.06460},
               {"lamps_256", 0.08810},     {"lamps", 0.07849},        {"sun", 0.02671}};
  for (const auto& bk : bakes) {
    const std::filesystem::path dir = ahd_test::test_data("truth") / bk.bake;
    AHD_REQUIRE_DATA(dir / "truth.json");
    const TruthSet t = load_truth_set(dir.string());
    ImageF iz(t.width, t.height, 3);
    for (size_t i = 0; i < t.texels(); ++i)
      for (int c = 0; c < 3; ++c) iz.data[i * 3 + c] = t.coverage[i] ? t.e[0][i * 3 + c] : 0.0f;
    const ImageF src = clamp_rgb(iz);
    Bc6hOptions o;
    o.quality = Bc6hQuality::Fast;
    const std::vector<uint8_t> fb = bc6h_encode_image(src, o);
    const double fast = log_rmse(src, bc6h_decode_image(fb.data(), src.width, src.height, false));
    o.quality = Bc6hQuality::Default;
    const std::vector<uint8_t> db = bc6h_encode_image(src, o);
    const double def = log_rmse(src, bc6h_decode_image(db.data(), src.width, src.height, false));
    std::printf("%s: fast %.5f, default %.5f (Basis HQ %.5f)\n", bk.bake, fast, def, bk.basis_hq);
    EXPECT_LE(fast, bk.basis_hq) << bk.bake;
    EXPECT_LE(def, fast) << bk.bake;
    for (Bc6hQuality q : {Bc6hQuality::Fast, Bc6hQuality::Default}) {
      Bc6hOptions oq;
      oq.quality = q;
      cpu::disable_for_tests(cpu::kAllSimd);
      const std::vector<uint8_t> scalar = bc6h_encode_image(src, oq);
      cpu::disable_for_tests(cpu::kAboveAvx2);
      const std::vector<uint8_t> avx2 = bc6h_encode_image(src, oq);
      cpu::disable_for_tests(0);
      EXPECT_EQ(scalar, q == Bc6hQuality::Fast ? fb : db) << bk.bake << " " << bc6h_quality_name(q);
      EXPECT_EQ(scalar, avx2) << bk.bake << " " << bc6h_quality_name(q) << " AVX2";
    }
  }
}
