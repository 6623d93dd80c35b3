#include "cli/direction_options.h"

#include "core/error.h"

namespace ahd::cli {

void add_direction_options(CLI::App* c, DirectionArgs* a) {
  c->add_option("--direction", a->mode,
                "Direction and ratio planes: auto (drop them when I_z alone is within --ambient-threshold of the SH), "
                "keep, drop")
      ->check(CLI::IsMember({"auto", "keep", "drop"}));
  c->add_option("--ambient-threshold", a->threshold,
                "auto: largest relative RMSE p99 of I_z alone vs the SH that drops the direction planes")
      ->check(CLI::NonNegativeNumber);
}

void apply_direction_options(const DirectionArgs& a, ConvertOptions* opt) {
  if (a.mode == "auto") opt->direction = DirectionPlanes::Auto;
  else if (a.mode == "keep") opt->direction = DirectionPlanes::Keep;
  else if (a.mode == "drop") opt->direction = DirectionPlanes::Drop;
  else throw Error("--direction must be auto, keep or drop");
  opt->ambient_threshold = a.threshold;
}

}  // namespace ahd::cli
