// ahdpack's public data types: the error it throws, the SH lightmap it reads, and the enums its
// options use. Plain data, no dependencies beyond the standard library.
//
// Conventions (docs/conventions.md "Canonical SH and conventions"): real SH in the order Y00, y, z, x (L1), then
// xy, yz, 3z²−1, xz, x²−y² (L2), no Condon–Shortley sign; coefficients are the projection of incident
// RADIANCE; the frame is tangent space (z = surface normal) unless `normals` is given.
#pragma once
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <ahd/export.h>

namespace ahd {

// Every failure the library reports is an ahd::Error whose what() is one line fit for a terminal:
// "<file>: <cause>" when a file is involved, otherwise the cause. The constructors write control
// characters of the text (a newline in a name a file gave) as \n, \r, \t or \xNN, so the line
// stays one whatever a message quotes.
struct AHD_API Error : std::runtime_error {
  explicit Error(const std::string& what);
  explicit Error(const char* what);
};

// Thrown (an ahd::Error) when a conversion stops because its cancel flag was raised.
struct AHD_API Cancelled : Error {
  Cancelled() : Error("cancelled") {}
};

// w×h texels of `coeffs` (1 = L0: a plain lightmap, 4 = L1, 9 = L2) radiance-SH coefficients × RGB, linear.
// Layout: data[((y*w + x)*coeffs + k)*3 + c], rows top first. Owned by the caller.
struct ShImage {
  int width = 0;
  int height = 0;
  int coeffs = 9;
  std::vector<float> data;
  // 1 where a chart covers the texel, 0 in gutters / empty space. Always width*height entries.
  std::vector<uint8_t> coverage;
  // Empty: the SH is in tangent space (z = surface normal). Otherwise width*height*3 unit WORLD-space
  // normals, and the SH is in world space; the fit rotates it into the texel's normal frame.
  std::vector<float> normals;

  size_t texels() const { return size_t(width) * height; }
  float* texel(size_t i) { return data.data() + i * size_t(coeffs) * 3; }
  const float* texel(size_t i) const { return data.data() + i * size_t(coeffs) * 3; }
};

// The ratio plane: one luminance ratio L(C_a)/L(I_z), or C_a/I_z per colour channel.
enum class RatioForm : uint8_t { Luminance, Rgb };

// How the fit chooses d (and, in the luminance form, the ratio): Linear — the optimal linear
// direction of the luminance L1 band (the paper's choice); Refined — the direction and the one ratio
// that minimise the constrained fit's hemisphere error, texel by texel (the default: more accurate
// against path-traced lighting, about 3× the linear fit's time; docs/accuracy-real-lighting.md).
enum class DirectionFit : uint8_t { Linear, Refined };

// Whether the direction and ratio planes are written. Auto drops them when decoding I_z alone stays
// within the ambient threshold of the SH (a plain lightmap, or SH with a negligible L1/L2 part).
enum class DirectionPlanes { Auto, Keep, Drop };

// BC6H encoder effort (speed against error: docs/bc6h.md "BC6H").
enum class Bc6hQuality : uint8_t { Fast, Default, High, Max };

// The container every plane is written in.
enum class ContainerKind { KTX2, DDS };

// How much the conversion measures its own error (against the source SH, 64 normals per texel):
// Off — nothing (fastest); Estimate — a fixed deterministic sample of texels; Full — every texel,
// every level, plus the unconstrained and open-loop baselines (what `ahdpack report` prints).
enum class Measure { Off, Estimate, Full };

}  // namespace ahd
