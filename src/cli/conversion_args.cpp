#include "cli/conversion_args.h"

#include <limits>

#include "codecs/bc6h/bc6h_codec.h"
#include "core/error.h"
#include "fit/direction_refine.h"

namespace ahd::cli {

void add_input_options(CLI::App* c, BakeInput* a) {
  for (const BakeInputOption& o : bake_input_options()) {
    if (auto s = std::get_if<std::string BakeInput::*>(&o.field)) {
      c->add_option(o.flag, a->**s, o.help);
    } else if (auto i = std::get_if<int BakeInput::*>(&o.field)) {
      c->add_option(o.flag, a->**i, o.help)->check(CLI::Range(o.min_value, std::numeric_limits<int>::max()));
    } else {
      c->add_flag(o.flag, a->*std::get<bool BakeInput::*>(o.field), o.help);
    }
  }
}

void add_conversion_options(CLI::App* c, ConversionArgs* a, bool fit) {
  ConversionOptions& o = a->options;
  c->add_option("--profile", a->profile, "Output profile name or .json file (formats/profiles)");
  if (fit) {
    c->add_option("--ratio", a->ratio, "Ratio form: luminance (one channel) or rgb (default: the profile's)");
    c->add_option("--eps", o.eps, "Smallest stored d_z (the horizon rule)");
    c->add_option("--direction-fit", a->direction_fit,
                  "d and luminance ratio: refined (default: lowest hemisphere error on a 3x3 window) or linear (the paper's)")
        ->check(CLI::IsMember({"linear", "refined"}));
    c->add_option("--levels", o.levels, "Mip levels to write (0 = full chain)")->check(CLI::NonNegativeNumber);
    c->add_flag("--coverage-plane", o.coverage_plane,
                "Also write OUT.coverage.<ext>: R8, 255 where a chart covers the texel");
  }
  c->add_option("--quality", a->quality, "BC6H encoder effort: fast, default, high or max");
  c->add_flag("--open-loop", a->open_loop, "Quantise the ratio from the unquantised fit (for comparison)");
  c->add_flag("--zstd", o.zstd, "Zstandard supercompression (KTX2)");
  c->add_flag("--strict-ktx", a->strict_ktx,
              "No ahd.* key/values in KTX2 planes (the manifest has them), so `ktx validate -e` passes");
  c->add_option("--direction", a->direction,
                "Direction and ratio planes: auto (drop them when I_z alone is within --ambient-threshold of the SH), "
                "keep, drop")
      ->check(CLI::IsMember({"auto", "keep", "drop"}));
  c->add_option("--ambient-threshold", o.ambient_threshold,
                "auto: largest relative RMSE p99 of I_z alone vs the SH that drops the direction planes")
      ->check(CLI::NonNegativeNumber);
  c->add_option("--measure", a->measure,
                "Error diagnostics: off, estimate (a fixed sample of texels; default) or full (every texel, every "
                "level, the unconstrained and open-loop baselines)")
      ->check(CLI::IsMember({"off", "estimate", "full"}));
  c->add_option("--threads", o.threads, "Worker threads (0 = all)");
  c->add_flag("-q,--quiet", a->quiet, "Print nothing on success");
}

ConversionOptions conversion_options(const ConversionArgs& a) {
  ConversionOptions o = a.options;
  o.profile = a.profile;
  if (a.ratio == "rgb") o.ratio = RatioForm::Rgb;
  else if (a.ratio == "luminance") o.ratio = RatioForm::Luminance;
  else if (!a.ratio.empty()) throw Error("--ratio must be 'luminance' or 'rgb'");
  if (!parse_direction_fit(a.direction_fit, &o.direction_fit))
    throw Error("--direction-fit must be 'linear' or 'refined'");
  o.direction = a.direction == "keep" ? DirectionPlanes::Keep : a.direction == "drop" ? DirectionPlanes::Drop : DirectionPlanes::Auto;
  if (!bc6h_quality_from_name(a.quality, &o.bc6h_quality)) throw Error("--quality must be fast, default, high or max");
  o.measure = a.measure == "off" ? Measure::Off : a.measure == "full" ? Measure::Full : Measure::Estimate;
  o.closed_loop = !a.open_loop;
  o.plane_metadata = !a.strict_ktx;
  return o;
}

}  // namespace ahd::cli
