// Colour spaces as files declare them, and their conversion to the working space through
// OpenColorIO. ahdpack works in linear Rec.709 / sRGB primaries with a D65 white (kWorkingSpace,
// recorded in the report). An input declaring another linear working space — ACEScg (AP1),
// ACES2065-1 (AP0), Rec.2020, P3-D65, by EXR `chromaticities` or by a colour-space name — is
// converted by one 3x3 matrix that OpenColorIO builds (docs/colour.md "Which transform OpenColorIO
// runs"); an sRGB-encoded colour plane is decoded to linear with OpenColorIO's sRGB curve. A file
// declaring the working space (or nothing) is read untouched: no matrix is applied at all.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "image/image_io.h"
#include "sh/sh_image.h"

namespace ahd {

constexpr const char* kWorkingSpace = "linear Rec.709 (sRGB primaries, D65), scene-referred";

// A source colour space: its primaries (linear) and whether its values are sRGB-encoded.
struct SourceSpace {
  // "linear-rec709" (the working space), "acescg", "aces2065-1", "rec2020", "p3-d65", "srgb", or
  // "chromaticities" (other primaries, given in `chromaticities`).
  std::string name = "linear-rec709";
  std::vector<float> chromaticities;  // R, G, B, white (x, y) each; only for name "chromaticities"
  bool srgb_encoded() const { return name == "srgb"; }
  // Same primaries and white as the working space (linear-rec709 or srgb): no matrix.
  bool working_primaries() const { return name == "linear-rec709" || name == "srgb"; }
  // How the report and the summary name it ("ACEScg (AP1, ACES white)", …).
  std::string describe() const;
};

// The names --input-space takes, in the order they are listed.
const std::vector<std::string>& input_space_names();

// The space named by --input-space. Throws ahd::Error naming the known names for any other.
SourceSpace parse_input_space(const std::string& name);

// What a file declares: EXR chromaticities (matched to a named space within 1e-3, else kept as
// "chromaticities"), else OpenImageIO's `oiio:ColorSpace` name (linear Rec.709 names, "sRGB",
// ACEScg / ACES2065-1 / Rec.2020 / P3-D65 spellings of OpenColorIO's and OpenImageIO's configs).
// Nothing declared = the working space. 8-bit files' oiio:ColorSpace is ignored (OpenImageIO
// labels every PNG "sRGB" whether or not it is; baker presets say which 8-bit planes are encoded).
// Throws ahd::Error("<path>: <cause>") for a declaration that cannot be converted (an unknown
// name, degenerate chromaticities), naming --input-space as the way to override it.
SourceSpace declared_space(const ImageFileInfo& info, const std::string& path);

// The 3x3 matrix (row-major: out[r] = Σ m[r][c]·in[c]) that OpenColorIO gives for linear `from`
// → the working space; identity for working_primaries(). Throws ahd::Error("<path>: <cause>") when
// OpenColorIO cannot build it or its transform is not a matrix.
using Matrix3 = std::array<std::array<double, 3>, 3>;
Matrix3 working_space_matrix(const SourceSpace& from, const std::string& path);

// Applies `m` to every coefficient's RGB of every texel (all bands, L0..L2), in place. Exact: the
// SH coefficients are linear in radiance, and a change of primaries is linear in radiance, so it
// commutes with the projection onto each basis function. Normals and coverage are untouched.
void apply_matrix(ShImage& sh, const Matrix3& m);


// Decodes sRGB-encoded values (IEC 61966-2-1 EOTF, OpenColorIO's ExponentWithLinearTransform
// gamma 2.4 offset 0.055) to linear, in place: `n` values `stride` floats apart.
void srgb_decode(float* values, size_t n, size_t stride);

}  // namespace ahd
