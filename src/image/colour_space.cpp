#include "image/colour_space.h"

// AHD_NO_OCIO (CMake AHD_OCIO=OFF, for platforms without an OpenColorIO build): inputs in the
// working space convert as always; a conversion from another space, or an sRGB decode, is refused
// with one error line naming the option (docs/platforms.md "Windows").
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <memory>

#include "core/error.h"
#include "core/parallel.h"
#include "image/ocio_module.h"

namespace ahd {

namespace {

// Primaries and white (x, y): R, G, B, W. ACES' white is (0.32168, 0.33767), not D65.
constexpr float kRec709[8] = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
constexpr float kAp1[8] = {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
constexpr float kAp0[8] = {0.7347f, 0.2653f, 0.0f, 1.0f, 0.0001f, -0.0770f, 0.32168f, 0.33767f};
constexpr float kRec2020[8] = {0.708f, 0.292f, 0.170f, 0.797f, 0.131f, 0.046f, 0.3127f, 0.3290f};
constexpr float kP3D65[8] = {0.680f, 0.320f, 0.265f, 0.690f, 0.150f, 0.060f, 0.3127f, 0.3290f};

struct Named {
  const char* name;
  const float* chroma;
  const char* description;
};
constexpr Named kNamed[] = {
    {"linear-rec709", kRec709, "linear Rec.709 (the working space)"},
    {"acescg", kAp1, "ACEScg (linear, ACES AP1 primaries, ACES white)"},
    {"aces2065-1", kAp0, "ACES2065-1 (linear, ACES AP0 primaries, ACES white)"},
    {"rec2020", kRec2020, "linear Rec.2020 (D65)"},
    {"p3-d65", kP3D65, "linear P3-D65"},
    {"srgb", kRec709, "sRGB-encoded Rec.709 (decoded with the sRGB EOTF)"},
};

bool near(const float* a, const std::vector<float>& b) {
  for (int i = 0; i < 8; ++i)
    if (!(std::fabs(a[i] - b[size_t(i)]) <= 1e-3f)) return false;
  return true;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

std::string known_names() {
  std::string k;
  for (const std::string& n : input_space_names()) k += (k.empty() ? "" : ", ") + n;
  return k;
}

// oiio:ColorSpace spellings (OpenImageIO's own, OpenColorIO's ACES and built-in configs) → our
// names; "" when unknown.
std::string name_of_declared(const std::string& declared) {
  const std::string cs = lower(declared);
  static const std::pair<const char*, const char*> kSpellings[] = {{"linear", "linear-rec709"},
                                                                   {"lin_srgb", "linear-rec709"},
                                                                   {"lin_rec709", "linear-rec709"},
                                                                   {"scene_linear", "linear-rec709"},
                                                                   {"linear rec.709 (srgb)", "linear-rec709"},
                                                                   {"srgb-linear", "linear-rec709"},
                                                                   {"linear-rec709", "linear-rec709"},
                                                                   {"utility - linear - srgb", "linear-rec709"},
                                                                   {"srgb", "srgb"},
                                                                   {"srgb - texture", "srgb"},
                                                                   {"utility - srgb - texture", "srgb"},
                                                                   {"acescg", "acescg"},
                                                                   {"aces - acescg", "acescg"},
                                                                   {"lin_ap1", "acescg"},
                                                                   {"aces2065-1", "aces2065-1"},
                                                                   {"aces - aces2065-1", "aces2065-1"},
                                                                   {"lin_ap0", "aces2065-1"},
                                                                   {"rec2020", "rec2020"},
                                                                   {"lin_rec2020", "rec2020"},
                                                                   {"linear rec.2020", "rec2020"},
                                                                   {"utility - linear - rec.2020", "rec2020"},
                                                                   {"p3-d65", "p3-d65"},
                                                                   {"lin_p3d65", "p3-d65"},
                                                                   {"linear p3-d65", "p3-d65"},
                                                                   {"utility - linear - p3-d65", "p3-d65"}};
  for (const auto& [spelling, name] : kSpellings)
    if (cs == spelling) return name;
  return "";
}

const Named* find_named(const std::string& name) {
  for (const Named& n : kNamed)
    if (name == n.name) return &n;
  return nullptr;
}

using M3 = Matrix3;

[[maybe_unused]] M3 mul(const M3& a, const M3& b) {
  M3 r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) r[i][j] += a[i][k] * b[k][j];
  return r;
}

double det(const M3& m) {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

M3 inverse(const M3& m) {
  const double d = det(m);
  M3 r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int a = (j + 1) % 3, b = (j + 2) % 3, c = (i + 1) % 3, e = (i + 2) % 3;
      r[i][j] = (m[a][c] * m[b][e] - m[a][e] * m[b][c]) / d;
    }
  return r;
}

std::array<double, 3> xyz_of(double x, double y) { return {x / y, 1.0, (1.0 - x - y) / y}; }

// RGB → XYZ of primaries and white `c` (x, y of R, G, B, W), white mapped to Y = 1. Throws when
// the primaries are degenerate (collinear, y = 0): no matrix converts them.
M3 rgb_to_xyz(const float* c, const std::string& path) {
  M3 p{};
  for (int i = 0; i < 3; ++i) {
    if (!(std::fabs(double(c[2 * i + 1])) > 1e-9))
      throw file_error(path, "declares chromaticities with a primary at y = 0: no matrix converts them");
    const auto v = xyz_of(c[2 * i], c[2 * i + 1]);
    for (int r = 0; r < 3; ++r) p[r][i] = v[size_t(r)];
  }
  if (!(c[7] > 1e-9f) || !(std::fabs(det(p)) > 1e-9))
    throw file_error(
        path, "declares degenerate chromaticities (collinear primaries or a white at y = 0): no matrix converts them");
  // Nearly collinear primaries pass a determinant test yet give a matrix float arithmetic cannot
  // apply (OpenColorIO's result then failed the 3x3 check with a misleading message): the gamut
  // triangle must have some area in xy (Rec. 709's is 0.112; 1e-4 is 0.1 % of it).
  const double area = 0.5 * std::fabs(double(c[0]) * (double(c[3]) - double(c[5])) +
                                       double(c[2]) * (double(c[5]) - double(c[1])) +
                                       double(c[4]) * (double(c[1]) - double(c[3])));
  if (!(area >= 1e-4))
    throw file_error(path, "declares nearly collinear primaries (gamut triangle area " + std::to_string(area) +
                               " in xy): no matrix converts them; give the space with --input-space");
  const auto w = xyz_of(c[6], c[7]);
  const M3 inv = inverse(p);
  for (int i = 0; i < 3; ++i) {
    const double s = inv[i][0] * w[0] + inv[i][1] * w[1] + inv[i][2] * w[2];
    for (int r = 0; r < 3; ++r) p[r][i] *= s;
  }
  return p;
}

// Bradford chromatic adaptation from white `src` to white `dst` (x, y). The linear Bradford cone
// matrix, as the ACES and OpenColorIO's _BFD builtins use it.
[[maybe_unused]] M3 bradford(double sx, double sy, double dx, double dy) {
  const M3 b = {{{0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}}};
  const auto s = xyz_of(sx, sy), d = xyz_of(dx, dy);
  M3 scale{};
  for (int i = 0; i < 3; ++i)
    scale[i][i] =
        (b[i][0] * d[0] + b[i][1] * d[1] + b[i][2] * d[2]) / (b[i][0] * s[0] + b[i][1] * s[1] + b[i][2] * s[2]);
  return mul(inverse(b), mul(scale, b));
}

#ifndef AHD_NO_OCIO
OcioStep matrix_transform(const M3& m) {
  OcioStep t;
  t.kind = OcioStep::kMatrix;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) t.matrix[r * 4 + c] = m[r][c];
  t.matrix[15] = 1;
  return t;
}

OcioStep builtin(const char* style) {
  OcioStep t;
  t.kind = OcioStep::kBuiltin;
  t.style = style;
  return t;
}

// The transform OpenColorIO runs, on its raw config (no file, no environment variable read):
//   acescg      its builtin "UTILITY - ACES-AP1_to_LINEAR-REC709_BFD" (Bradford, ACES white → D65);
//   aces2065-1  its builtin "UTILITY - ACES-AP0_to_CIE-XYZ-D65_BFD" (Bradford), then XYZ → Rec.709;
//   others      a MatrixTransform built from the declared chromaticities (RGB → XYZ, Bradford from
//               the declared white to D65 when it differs), then XYZ → Rec.709.
// Rec.2020 and P3-D65 share D65 with the working space: no adaptation for them.
std::vector<OcioStep> to_working(const SourceSpace& from, const std::string& path) {
  const M3 xyz_to_709 = inverse(rgb_to_xyz(kRec709, path));
  if (from.name == "acescg") return {builtin("UTILITY - ACES-AP1_to_LINEAR-REC709_BFD")};
  std::vector<OcioStep> g;
  if (from.name == "aces2065-1") {
    g.push_back(builtin("UTILITY - ACES-AP0_to_CIE-XYZ-D65_BFD"));
  } else {
    const Named* n = find_named(from.name);
    const float* c = n ? n->chroma : from.chromaticities.data();
    if (!n && from.chromaticities.size() != 8)
      throw file_error(path, "colour space '" + from.name + "' has no chromaticities");
    M3 m = rgb_to_xyz(c, path);
    if (std::fabs(c[6] - kRec709[6]) > 1e-6f || std::fabs(c[7] - kRec709[7]) > 1e-6f)
      m = mul(bradford(c[6], c[7], kRec709[6], kRec709[7]), m);
    g.push_back(matrix_transform(m));
  }
  g.push_back(matrix_transform(xyz_to_709));
  return g;
}
#else
[[noreturn]] void no_ocio(const std::string& path, const std::string& what) {
  const std::string why = what + " needs OpenColorIO, and this ahdpack was built without it (AHD_OCIO=OFF)";
  if (path.empty()) throw Error(why);
  throw file_error(path, why);
}
#endif

}  // namespace

std::string SourceSpace::describe() const {
  if (const Named* n = find_named(name)) return n->description;
  char b[200];
  const std::vector<float>& c = chromaticities;
  if (c.size() != 8) return name;
  std::snprintf(b, sizeof b, "linear, chromaticities R(%.4g, %.4g) G(%.4g, %.4g) B(%.4g, %.4g) W(%.4g, %.4g)", c[0],
                c[1], c[2], c[3], c[4], c[5], c[6], c[7]);
  return b;
}

const std::vector<std::string>& input_space_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const Named& n : kNamed) v.push_back(n.name);
    return v;
  }();
  return names;
}

SourceSpace parse_input_space(const std::string& name) {
  if (!find_named(name)) throw Error("--input-space: unknown space '" + name + "' (known: " + known_names() + ")");
  SourceSpace s;
  s.name = name;
  return s;
}

SourceSpace declared_space(const ImageFileInfo& info, const std::string& path) {
  SourceSpace s;
  if (!info.is_float) return s;  // 8-bit planes: the preset says which are colour and how encoded
  if (info.chromaticities.size() == 8 && !near(kRec709, info.chromaticities)) {
    for (const Named& n : kNamed)
      if (near(n.chroma, info.chromaticities)) return parse_input_space(n.name);
    s.name = "chromaticities";
    s.chromaticities = info.chromaticities;
    rgb_to_xyz(s.chromaticities.data(), path);  // degenerate ones are refused here, before any pixel is read
    return s;
  }
  if (info.color_space.empty()) return s;
  const std::string name = name_of_declared(info.color_space);
  if (name.empty())
    throw file_error(path, "declares colour space '" + info.color_space +
                               "', which ahdpack cannot convert through "
                               "OpenColorIO: give the space it is in with --input-space (" +
                               known_names() + ")");
  s.name = name;
  return s;
}

Matrix3 working_space_matrix(const SourceSpace& from, const std::string& path) {
  M3 m{};
  for (int i = 0; i < 3; ++i) m[i][i] = 1;
  if (from.working_primaries()) return m;
#ifdef AHD_NO_OCIO
  no_ocio(path, "converting from " + from.describe());
#else
  const OcioModule& ocio = ocio_module(path);
  std::string why;
  const void* cpu = ocio.processor(to_working(from, path), &why);
  if (!cpu)
    throw file_error(path, "OpenColorIO cannot convert " + from.describe() + " to the working space (" + why + ")");
  const std::unique_ptr<const void, void (*)(const void*)> owned(cpu, ocio.release);
  // The matrix's columns are the images of the unit primaries; a fourth triple checks it is one: a
  // transform with an offset or a curve is no 3x3 matrix and cannot be applied to SH.
  float v[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.25f, -1.5f, 3.0f}};
  ocio.apply_rgb(cpu, v[0], 4);
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) m[r][c] = double(v[c][r]);
  for (int r = 0; r < 3; ++r) {
    const double want = m[r][0] * 0.25 - m[r][1] * 1.5 + m[r][2] * 3.0;
    if (!(std::fabs(double(v[3][r]) - want) <= 1e-5 * (1 + std::fabs(want))))
      throw file_error(path, "OpenColorIO's transform from " + from.describe() + " is not a 3x3 matrix");
  }
  return m;
#endif
}

void apply_matrix(ShImage& sh, const Matrix3& m) {
  const size_t per_texel = size_t(sh.coeffs);
  parallel_for(size_t(sh.height), 0, 16, [&](size_t y) {
    for (size_t x = 0; x < size_t(sh.width); ++x) {
      float* t = sh.texel(y * size_t(sh.width) + x);
      // Every coefficient (L0, L1, L2): each is a linear functional of the radiance.
      for (size_t k = 0; k < per_texel; ++k) {
        float* rgb = t + k * 3;
        const double in[3] = {rgb[0], rgb[1], rgb[2]};
        for (int r = 0; r < 3; ++r) rgb[r] = float(m[r][0] * in[0] + m[r][1] * in[1] + m[r][2] * in[2]);
      }
    }
  });
}

void srgb_decode(float* values, size_t n, size_t stride) {
#ifdef AHD_NO_OCIO
  (void)values, (void)n, (void)stride;
  no_ocio("", "decoding an sRGB-encoded plane");
#else
  // The processor is built once; OpenColorIO's CPU processors are safe to share between threads.
  const OcioModule& ocio = ocio_module("decoding an sRGB-encoded plane");
  static const void* cpu = [&ocio] {
    OcioStep t;
    t.kind = OcioStep::kExponentWithLinear;
    const double gamma[4] = {2.4, 2.4, 2.4, 1}, offset[4] = {0.055, 0.055, 0.055, 0};
    std::copy_n(gamma, 4, t.gamma);
    std::copy_n(offset, 4, t.offset);  // forward = encoded → linear
    std::string why;
    const void* p = ocio.processor({t}, &why);
    if (!p) throw Error("OpenColorIO cannot build the sRGB decode (" + why + ")");
    return p;
  }();
  for (size_t i = 0; i < n; i += 3) {
    float v[3] = {0, 0, 0};
    const size_t m = std::min<size_t>(3, n - i);
    for (size_t j = 0; j < m; ++j) v[j] = values[(i + j) * stride];
    ocio.apply_rgb(cpu, v, 1);
    for (size_t j = 0; j < m; ++j) values[(i + j) * stride] = v[j];
  }
#endif
}

}  // namespace ahd
