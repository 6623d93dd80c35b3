#include "cli/preview_images.h"

#include <algorithm>
#include <cmath>

namespace ahd::cli {

namespace {
double luminance(const float* c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }
}  // namespace

double white_point(const std::vector<float>& rgb) {
  std::vector<double> l;
  for (size_t i = 0; i + 2 < rgb.size(); i += 3)
    if (const double v = luminance(&rgb[i]); v > 0 && std::isfinite(v)) l.push_back(v);
  if (l.empty()) return 1.0;
  const size_t k = std::min(l.size() - 1, size_t(0.99 * double(l.size())));
  std::nth_element(l.begin(), l.begin() + long(k), l.end());
  return l[k];
}

ImageF log_encode(const std::vector<float>& rgb, int w, int h, double white) {
  ImageF out(w, h, 3);
  for (size_t i = 0; i < out.data.size(); ++i) {
    const double x = rgb[i] / white;
    if (!(x > std::exp2(kLogLo))) continue;  // ≤ the darkest step, or NaN: black
    const double c = (std::log2(x) - kLogLo) / (kLogHi - kLogLo);
    out.data[i] = float(std::clamp(c, 1.0 / 255, 1.0));
  }
  return out;
}

ImageF direction_colours(const std::vector<float>& d, int w, int h) {
  ImageF out(w, h, 3);
  for (size_t i = 0; i < out.texels(); ++i) {
    const float* v = &d[i * 3];
    const double len = std::sqrt(double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2]);
    for (int c = 0; c < 3; ++c) out.data[i * 3 + c] = len > 0 ? float(0.5 + 0.5 * v[c] / len) : 0.5f;
  }
  return out;
}

ImageF ratio_image(const std::vector<float>& ratio, int w, int h) {
  ImageF out(w, h, 3);
  for (size_t i = 0; i < out.data.size(); ++i) out.data[i] = std::clamp(ratio[i], 0.0f, 1.0f);
  return out;
}

const std::vector<std::array<float, 3>>& heat_stops() {
  static const std::vector<std::array<float, 3>> s = {
      {0.00f, 0.00f, 0.02f}, {0.30f, 0.05f, 0.45f}, {0.75f, 0.10f, 0.25f},
      {0.95f, 0.45f, 0.05f}, {1.00f, 0.85f, 0.20f}, {1.00f, 1.00f, 1.00f}};
  return s;
}

ImageF heat_map(const std::vector<float>& err, int w, int h, double lo_exp, double hi_exp) {
  const auto& s = heat_stops();
  ImageF out(w, h, 3);
  for (size_t i = 0; i < out.texels(); ++i) {
    float* o = &out.data[i * 3];
    if (std::isnan(err[i])) {
      o[0] = 0.16f, o[1] = 0.18f, o[2] = 0.24f;
      continue;
    }
    const double e = std::log10(std::max(double(err[i]), 1e-30));
    const double t = std::clamp((e - lo_exp) / (hi_exp - lo_exp), 0.0, 1.0) * double(s.size() - 1);
    const size_t k = std::min(size_t(t), s.size() - 2);
    const double f = t - double(k);
    for (int c = 0; c < 3; ++c) o[c] = float(s[k][c] + f * (s[k + 1][c] - s[k][c]));
  }
  return out;
}

}  // namespace ahd::cli
