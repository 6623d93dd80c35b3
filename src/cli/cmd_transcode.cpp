// ahdpack transcode NAME.ahd.exr -o OUT.ktx2|OUT.dds --profile P: re-emit a conversion for another
// profile or container from the lossless intermediate (`convert --keep-intermediate`), without
// reading the baker files or fitting directions and I_z again. The closed loop still refits each
// texel's ratio against its decoded direction and I_z, which is what closed-loop quantisation is.
#include <filesystem>

#include "api/options.h"
#include "cli/commands.h"
#include "cli/conversion_args.h"
#include "cli/output.h"
#include "cli/progress.h"
#include "core/error.h"
#include "image/ahd_intermediate.h"
#include "files/profile_file.h"
#include "pipeline/run.h"

namespace ahd::cli {
namespace fs = std::filesystem;

void add_transcode_command(CLI::App& app) {
  struct Args {
    std::string input, output;
    ConversionArgs conv;
  };
  auto a = std::make_shared<Args>();
  CLI::App* c = app.add_subcommand("transcode", "Re-emit a conversion for another profile/container from NAME.ahd.exr");
  c->add_option("input", a->input, "NAME.ahd.exr written by convert --keep-intermediate")->required();
  c->add_option("-o,--output", a->output, "OUT.ktx2 or OUT.dds")->required();
  add_conversion_options(c, &a->conv, false);
  c->callback([a]() {
    const OutputPaths out = output_paths(a->output);
    ConversionOptions co = conversion_options(a->conv);
    co.container = out.kind;
    attach_terminal_progress(&co, a->conv.quiet);
    const Profile profile = load_profile(a->conv.options.profile);
    const auto t0 = std::chrono::steady_clock::now();
    FitOptions fit;
    const std::vector<FittedLevel> levels = read_intermediate(a->input, &fit);
    const double read_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (profile.ratio_rgb != (fit.ratio_form == RatioForm::Rgb))
      throw file_error(a->input, std::string("was fitted with the ") + (profile.ratio_rgb ? "luminance" : "rgb") +
                                     " ratio form; profile " + profile.name + " needs the other one");
    co.ratio = fit.ratio_form;
    co.eps = fit.dz_min;
    ResolvedOptions ro = resolve_options(co, out.name, profile);
    ro.convert.fit = fit;  // the stored fit's parameters, whatever the flags say
    ro.package.world_frame = !levels[0].sh.normals.empty();
    ro.package.report_extra = {{"source", a->input + " (intermediate)"}};
    ConversionRun run = run_transcode(levels, profile, ro.convert, ro.package, {{"read", read_seconds}});
    // Transcoding NAME.ahd.exr into NAME itself keeps it: the new set has the same fit.
    std::error_code ec;
    IntermediateFile im;
    im.keep_existing = fs::equivalent(a->input, out.sibling(".ahd.exr"), ec);
    publish_conversion(out, std::move(run.output.files), std::move(im));  // the summary needs the manifest
    if (!a->conv.quiet) print_conversion("transcode " + a->input, out, run, ro.convert.closed_loop, 0);
  });
}

}  // namespace ahd::cli
