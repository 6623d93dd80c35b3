#include "image/ahd_intermediate.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>

#include "containers/limits.h"
#include "core/error.h"
#include "fit/ahd_decode.h"
#include "fit/direction_refine.h"
#include "image/image_file.h"
#include "image/image_io.h"
#include "files/file_io.h"
#include "files/input_file.h"
#include "files/output_set.h"
#include "pipeline/manifest.h"

namespace ahd {
namespace fs = std::filesystem;

namespace {

const char* kRgb[3] = {"R", "G", "B"};
const char* kXyz[3] = {"X", "Y", "Z"};

std::vector<std::string> channel_names(int coeffs, bool normals) {
  std::vector<std::string> n;
  for (int k = 0; k < coeffs; ++k)
    for (int c = 0; c < 3; ++c) n.push_back("sh" + std::to_string(k) + "." + kRgb[c]);
  n.push_back("coverage");
  if (normals)
    for (int c = 0; c < 3; ++c) n.push_back(std::string("normal.") + kXyz[c]);
  for (int c = 0; c < 3; ++c) n.push_back(std::string("ahd.iz.") + kRgb[c]);
  for (int c = 0; c < 3; ++c) n.push_back(std::string("ahd.d.") + kXyz[c]);
  for (int c = 0; c < 3; ++c) n.push_back(std::string("ahd.ratio.") + kRgb[c]);
  n.push_back("ahd.flags");
  return n;
}

std::vector<float> pack_level(const FittedLevel& l, int nch) {
  const ShImage& sh = l.sh;
  std::vector<float> px(sh.texels() * size_t(nch));
  const bool normals = !sh.normals.empty();
  for (size_t i = 0; i < sh.texels(); ++i) {
    float* o = &px[i * nch];
    const float* t = sh.texel(i);
    int k = 0;
    for (int j = 0; j < sh.coeffs * 3; ++j) o[k++] = t[j];
    o[k++] = sh.coverage[i] ? 1.0f : 0.0f;
    if (normals)
      for (int c = 0; c < 3; ++c) o[k++] = sh.normals[i * 3 + c];
    const AhdFit f = l.ahd.texel(i);
    for (int c = 0; c < 3; ++c) o[k++] = f.iz[c];
    for (int c = 0; c < 3; ++c) o[k++] = f.d[c];
    for (int c = 0; c < 3; ++c) o[k++] = f.ratio[c];
    o[k++] = float(f.flags);
  }
  return px;
}

}  // namespace

std::vector<uint8_t> encode_intermediate(const std::string& path, const std::vector<FittedLevel>& levels,
                                         const FitOptions& fit) {
  if (levels.empty()) throw Error("write_intermediate: no levels");
  const int coeffs = levels[0].sh.coeffs;
  const bool normals = !levels[0].sh.normals.empty();
  const std::vector<std::string> names = channel_names(coeffs, normals);
  const int nch = int(names.size());
  // Every level's texels are packed before the write: the module writes the chain in one call.
  std::vector<std::vector<float>> px(levels.size());
  std::vector<OiioEncodeLevel> out(levels.size());
  for (size_t l = 0; l < levels.size(); ++l) {
    const ShImage& sh = levels[l].sh;
    px[l] = pack_level(levels[l], nch);
    OiioEncodeLevel& o = out[l];
    o.width = sh.width, o.height = sh.height, o.channels = nch, o.px = px[l].data();
    o.channel_names = names;
    o.format = 0;
    o.tile = 64;
    o.string_attrs.push_back({"compression", "zip"});
    o.int_attrs.push_back({"openexr:roundingmode", 0});  // ROUND_DOWN: the max(1, floor(n/2)) chain
    o.int_attrs.push_back({"ahd:intermediate_version", kIntermediateVersion});
    // Doubles as text (%.17g): the fit parameters must come back bit for bit.
    char num[128];
    std::snprintf(num, sizeof num, "%.17g", fit.dz_min);
    o.string_attrs.push_back({"ahd:dz_min", num});
    o.string_attrs.push_back({"ahd:ratio_form", fit.ratio_form == RatioForm::Rgb ? "rgb" : "luminance"});
    // The closed-loop refit of a transcode must choose the luminance ratio the same way.
    o.string_attrs.push_back({"ahd:direction_fit", direction_fit_name(fit.direction_fit)});
    std::snprintf(num, sizeof num, "%.17g %.17g %.17g", fit.luma[0], fit.luma[1], fit.luma[2]);
    o.string_attrs.push_back({"ahd:luma", num});
  }
  std::vector<uint8_t> bytes;
  std::string why;
  if (!oiio_module(path).encode("x.exr", temp_path_for(path), out, &bytes, &why))
    throw file_error(path, "cannot write intermediate (" + why + ")");
  return bytes;
}

void write_intermediate(const std::string& path, const std::vector<FittedLevel>& levels, const FitOptions& fit) {
  publish_file(path, encode_intermediate(path, levels, fit));
}

std::vector<FittedLevel> read_intermediate(const std::string& path, FitOptions* fit) {
  // input_exists, not fs::exists: a symlink loop is one error line ("symbolic links loop"), where
  // std::filesystem threw and the command ended in "internal error" (issue 44). A symlink leading
  // elsewhere is followed (the user named it); a FIFO, device or folder at its end is refused
  // unread by the opener (read_input_bytes: "not a regular file").
  if (!input_exists(path)) throw file_error(path, "file not found");
  // Read once into memory (a file replaced while it is read cannot mix two headers).
  OpenedImage file = open_image_file(path);
  const OiioSpec spec0 = file.spec;
  auto str_attr = [&](const char* name, const char* fallback = "") {
    return file.oiio->string_attr(file.handle, name, fallback);
  };
  if (file.oiio->int_attr(file.handle, "ahd:intermediate_version", -1) != kIntermediateVersion)
    throw file_error(path, "not an ahdpack intermediate of version " + std::to_string(kIntermediateVersion));
  std::map<std::string, int> index;
  for (int c = 0; c < spec0.nchannels; ++c) index[spec0.channel_names[size_t(c)]] = c;
  const int coeffs = index.count("sh8.B") ? 9 : index.count("sh3.B") ? 4 : 1;
  const bool normals = index.count("normal.X") != 0;
  const std::vector<std::string> names = channel_names(coeffs, normals);
  std::vector<int> src;  // file channel of each name
  for (const auto& n : names) {
    if (!index.count(n)) throw file_error(path, "missing channel " + n);
    src.push_back(index[n]);
  }
  if (fit) {
    const std::string dz = str_attr("ahd:dz_min");
    fit->dz_min = std::strtod(dz.c_str(), nullptr);
    if (!(fit->dz_min > 0 && fit->dz_min < 1)) throw file_error(path, "invalid ahd:dz_min '" + dz + "'");
    fit->ratio_form = str_attr("ahd:ratio_form") == "rgb" ? RatioForm::Rgb : RatioForm::Luminance;
    // Intermediates written before the attribute existed were fitted the paper's way.
    const std::string dir_fit = str_attr("ahd:direction_fit", "linear");
    if (!parse_direction_fit(dir_fit, &fit->direction_fit))
      throw file_error(path, "invalid ahd:direction_fit '" + dir_fit + "'");
    const std::string luma = str_attr("ahd:luma");
    char end = 0;
    if (std::sscanf(luma.c_str(), "%lf %lf %lf %c", &fit->luma[0], &fit->luma[1], &fit->luma[2], &end) != 3)
      throw file_error(path, "invalid ahd:luma '" + luma + "'");
    // The manifest's rule (fit_parameters_problem): transcode must not write a set decode refuses.
    const std::string why = fit_parameters_problem(fit->dz_min, fit->luma);
    if (!why.empty()) throw file_error(path, "ahd:dz_min/ahd:luma: " + why);
  }
  std::vector<FittedLevel> levels;
  for (int mip = 0; file.seek(0, mip); ++mip) {
    const OiioSpec spec = file.spec;
    // The size limit and the file's real size before anything is allocated (issues 15, 26); later
    // levels are checked smaller than this one below.
    if (levels.empty()) check_image_spec(file, spec);
    const int expect_w = levels.empty() ? spec.width : std::max(1, levels.back().sh.width / 2);
    const int expect_h = levels.empty() ? spec.height : std::max(1, levels.back().sh.height / 2);
    if (spec.width != expect_w || spec.height != expect_h || spec.nchannels != spec0.nchannels)
      throw file_error(path, "mip level " + std::to_string(mip) + " has an unexpected size");
    std::vector<float> px(size_t(spec.width) * spec.height * spec.nchannels);
    std::string why;
    if (!file.oiio->read_image(file.handle, 0, mip, px.data(), &why))
      throw file_error(path, "cannot read mip level " + std::to_string(mip));
    FittedLevel l;
    l.sh = make_sh_image(spec.width, spec.height, coeffs);
    if (normals) l.sh.normals.resize(l.sh.texels() * 3);
    // Three ratios a texel whatever the form: the file's are kept as written.
    l.ahd = make_ahd_image(spec.width, spec.height, false);
    for (size_t i = 0; i < l.sh.texels(); ++i) {
      const float* p = &px[i * spec.nchannels];
      size_t k = 0;  // walks `names` in the order channel_names() lists them
      auto next = [&]() { return p[src[k++]]; };
      float* t = l.sh.texel(i);
      for (int j = 0; j < coeffs * 3; ++j) t[j] = next();
      l.sh.coverage[i] = next() > 0.5f;
      if (normals)
        for (int c = 0; c < 3; ++c) l.sh.normals[i * 3 + c] = next();
      AhdFit f;
      for (int c = 0; c < 3; ++c) f.iz[c] = next();
      for (int c = 0; c < 3; ++c) f.d[c] = next();
      for (int c = 0; c < 3; ++c) f.ratio[c] = next();
      const float flags = next();  // a float in the file: a whole number of FitFlag bits, or refused
      if (!(flags >= 0 && flags <= 31 && flags == std::floor(flags)))
        throw file_error(path, "ahd.flags of texel (" + std::to_string(i % size_t(spec.width)) + ", " +
                                   std::to_string(i / size_t(spec.width)) + ") in mip level " + std::to_string(mip) +
                                   " is " + std::to_string(flags) + ", not a whole number 0..31");
      f.flags = uint8_t(flags);
      l.ahd.set_texel(i, f);
    }
    l.ahd.coverage = l.sh.coverage;
    levels.push_back(std::move(l));
  }
  if (levels.empty()) throw file_error(path, "no levels");
  return levels;
}

}  // namespace ahd
