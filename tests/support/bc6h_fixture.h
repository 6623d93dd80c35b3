// What the BC6H tests share (tests/unit and tests/accuracy bc6h_codec_test.cpp): log-RMSE, the
// clamp to the unsigned format's range and the speckle check.
#pragma once
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
#include "sanitized.h"
#include "test_data.h"

namespace ahd_fixture::bc6h_fixture {

using namespace ::ahd;

inline double log_rmse(const ImageF& a, const ImageF& b) {
  double s = 0;
  for (size_t i = 0; i < a.texels(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double d = std::log2(1 + a.data[i * a.channels + c]) - std::log2(1 + b.data[i * b.channels + c]);
      s += d * d;
    }
  return std::sqrt(s / (3.0 * a.texels()));
}

inline ImageF clamp_rgb(const ImageF& img) {
  ImageF out(img.width, img.height, 3);
  for (size_t i = 0; i < img.texels(); ++i)
    for (int c = 0; c < 3; ++c) out.data[i * 3 + c] = std::clamp(img.data[i * img.channels + c], 0.0f, 65504.0f);
  return out;
}

// The largest half-float step at or below v (the format's resolution there).
inline float half_step(float v) {
  Imath::half h(std::max(v, 0.0f));
  Imath::half up;
  up.setBits(uint16_t(h.bits() + 1));
  return float(up) - float(h);
}

inline void expect_sane(const ImageF& in, bool is_signed, Bc6hQuality q, const char* what) {
  Bc6hOptions o;
  o.is_signed = is_signed;
  o.quality = q;
  o.threads = 1;
  const std::vector<uint8_t> blocks = bc6h_encode_image(in, o);
  ASSERT_EQ(blocks.size(), size_t((in.width + 3) / 4) * ((in.height + 3) / 4) * 16) << what;
  const ImageF out = bc6h_decode_image(blocks.data(), in.width, in.height, is_signed);
  const int bw = (in.width + 3) / 4;
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x) {
      // The brightest (clamped) input of the texel's block.
      float bmax = 0;
      for (int yy = y / 4 * 4; yy < std::min(in.height, y / 4 * 4 + 4); ++yy)
        for (int xx = x / 4 * 4; xx < std::min(in.width, x / 4 * 4 + 4); ++xx)
          for (int c = 0; c < 3; ++c) {
            float v = in.at(xx, yy)[c];
            if (!std::isfinite(v)) v = std::isnan(v) ? 0.0f : 65504.0f;
            bmax = std::max(bmax, std::min(std::fabs(v), 65504.0f));
          }
      // The encoder sees its input as half floats: the brightest input is bmax rounded to half.
      const float hmax = float(Imath::half(bmax));
      for (int c = 0; c < 3; ++c) {
        const float v = out.at(x, y)[c];
        ASSERT_TRUE(std::isfinite(v)) << what << " at " << x << "," << y;
        ASSERT_LE(std::fabs(v), hmax + half_step(hmax)) << what << " at " << x << "," << y << " (no specks)";
        if (!is_signed) {
          ASSERT_GE(v, 0.0f) << what;
        }
      }
    }
  (void)bw;
}

}  // namespace ahd_fixture::bc6h_fixture
