#include "pipeline/sh_input_check.h"

#include <algorithm>
#include <cstdio>

namespace ahd {

namespace {

const char* const kLayer[3] = {"L1y", "L1z", "L1x"};

std::string percent(double f) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f %%", 100.0 * f);
  return b;
}

}  // namespace

L1Figures& L1Figures::operator+=(const L1Figures& o) {
  for (int k = 0; k < 3; ++k) values[k] += o.values[k], negative[k] += o.negative[k], zero[k] += o.zero[k];
  return *this;
}

L1Figures measure_l1(const ShImage& sh) {
  L1Figures f;
  if (sh.coeffs < 4) return f;
  for (size_t i = 0; i < sh.texels(); ++i) {
    if (!sh.coverage[i]) continue;
    const float* t = sh.texel(i);  // coefficient-major: t[k * 3 + colour]
    for (int c = 0; c < 3; ++c) {
      if (!(t[c] > 0)) continue;
      for (int k = 0; k < 3; ++k) {
        const float v = t[(k + 1) * 3 + c];
        ++f.values[k];
        f.negative[k] += v < 0;
        f.zero[k] += v == 0;
      }
    }
  }
  return f;
}

double rules_share(const FitStats& s) {
  return s.covered ? double(s.dir_clamped + s.negative_iz) / double(s.covered) : 0.0;
}

std::vector<std::string> sh_input_warnings(const L1Figures& l1, const FitStats& fit, int coeffs) {
  std::vector<std::string> w;
  if (coeffs < 4) return w;
  // Denoiser damage: Godot before godotengine/godot#109972 denoised raw signed L1 as a colour, and
  // the denoiser clamps it at 0 (godotengine/godot#82655; RenderKit/oidn#191). Undamaged L1 of a lit
  // scene has both signs in every layer and almost no exact zero off black texels.
  size_t negative = 0, nonzero = 0;
  int worst = 0;
  for (int k = 0; k < 3; ++k) {
    negative += l1.negative[k], nonzero += l1.values[k] - l1.zero[k];
    if (double(l1.zero[k]) * double(l1.values[worst]) > double(l1.zero[worst]) * double(l1.values[k])) worst = k;
  }
  const double zero_share = l1.values[worst] ? double(l1.zero[worst]) / double(l1.values[worst]) : 0.0;
  if (l1.values[0] >= 3 * kFewestTexelsJudged && negative == 0 && nonzero > 0 && zero_share >= kL1ZeroShareDamaged)
    w.push_back("L1 has no negative value in any layer and " + percent(zero_share) + " exact zeros in " + kLayer[worst] +
                ": L1 clamped at 0, as Godot's denoiser does to directional bakes (godotengine/godot#82655); the "
                "direction planes cannot be right: rebake with LightmapGI's denoiser off (use_denoiser = false), or "
                "with a Godot that packs L1 before denoising (godotengine/godot#109972)");
  const double rules = rules_share(fit);
  if (fit.covered >= kFewestTexelsJudged && rules > kRulesShareWarned)
    w.push_back("the fit's horizon-tilted and negative-I_z rules fired on " + percent(rules) + " of covered texels (" +
                std::to_string(fit.dir_clamped) + " + " + std::to_string(fit.negative_iz) + " of " +
                std::to_string(fit.covered) + "; sound bakes stay under " + percent(kRulesShareWarned) +
                "): the SH's L1 points below the surface, so the normals are not the bake's (wrong mesh, UV set, "
                "placement or axes) or the L1 is damaged, as by Godot's denoiser (godotengine/godot#82655)");
  return w;
}

}  // namespace ahd
