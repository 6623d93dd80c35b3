// ahdpack transcode NAME.ahd.exr -o OUT.ktx2|OUT.dds --profile P: re-emit a conversion for another
// profile or container from the lossless intermediate (`convert --keep-intermediate`), without
// reading the baker files or fitting directions and I_z again. The closed loop still refits each
// texel's ratio against its decoded direction and I_z, which is what closed-loop quantisation is.
#include <chrono>

#include "cli/commands.h"
#include "cli/direction_options.h"
#include "cli/output.h"
#include "core/error.h"
#include "io/ahd_intermediate.h"

namespace ahd::cli {

void add_transcode_command(CLI::App& app) {
  struct Args {
    std::string input, output, profile = "uncompressed";
    bool zstd = false, open_loop = false, quiet = false;
    int threads = 0;
    DirectionArgs direction;
  };
  auto a = std::make_shared<Args>();
  CLI::App* c = app.add_subcommand("transcode", "Re-emit a conversion for another profile/container from NAME.ahd.exr");
  c->add_option("input", a->input, "NAME.ahd.exr written by convert --keep-intermediate")->required();
  c->add_option("-o,--output", a->output, "OUT.ktx2 or OUT.dds")->required();
  c->add_option("--profile", a->profile, "Output profile");
  c->add_flag("--zstd", a->zstd, "Zstandard supercompression (KTX2)");
  c->add_flag("--open-loop", a->open_loop, "Quantise the ratio from the stored fit");
  c->add_option("--threads", a->threads, "Worker threads (0 = all)");
  add_direction_options(c, &a->direction);
  c->add_flag("-q,--quiet", a->quiet, "Print nothing on success");
  c->callback([a]() {
    const auto t_start = std::chrono::steady_clock::now();
    const OutputPaths out = output_paths(a->output);
    ConvertOptions opt;
    opt.threads = opt.codec.threads = a->threads;
    opt.closed_loop = !a->open_loop;
    opt.measure_unconstrained = false;
    apply_direction_options(a->direction, &opt);
    const std::vector<FittedLevel> levels = read_intermediate(a->input, &opt.fit);
    const Profile profile = load_profile(a->profile);
    if (profile.ratio_rgb != (opt.fit.ratio_form == RatioForm::Rgb))
      throw file_error(a->input, std::string("was fitted with the ") + (profile.ratio_rgb ? "luminance" : "rgb") +
                                     " ratio form; profile " + profile.name + " needs the other one");
    ConvertResult r;
    quantise_levels(levels, profile, opt, &r);
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
    const Manifest m = write_conversion(out, r, profile, opt.fit, !levels[0].sh.normals.empty(), a->zstd,
                                        {{"source", a->input + " (intermediate)"}}, total);
    if (!a->quiet) print_conversion("transcode " + a->input, out, m, r, opt.closed_loop, 0, total);
  });
}

}  // namespace ahd::cli
