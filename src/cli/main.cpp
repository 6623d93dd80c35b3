// ahdpack: SH lightmaps in, AHD directional lightmaps out. A thin shell over the library.
#include <cstdio>
#include <exception>
#include <new>

#include "cli/commands.h"
#include "cli/environment.h"
#include "core/error.h"

int main(int argc, char** argv) {
  CLI::App app{"ahdpack: turn spherical-harmonics lightmaps into filter-safe AHD directional lightmaps"};
  app.require_subcommand(1);
  ahd::cli::add_convert_command(app);
  ahd::cli::add_layouts_command(app);
  ahd::cli::add_decode_command(app);
  ahd::cli::add_inspect_command(app);
  ahd::cli::add_compress_commands(app);
  ahd::cli::add_sample_command(app);
  ahd::cli::add_transcode_command(app);
  ahd::cli::add_preview_command(app);
  ahd::cli::add_verify_command(app);
  ahd::cli::add_scene_command(app);
  ahd::cli::add_lab_commands(app);
  try {
    ahd::cli::apply_size_limit_from_environment();
    ahd::cli::apply_cpu_disable_from_environment();
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const ahd::Cancelled&) {
    std::fprintf(stderr, "\nahdpack: cancelled: nothing was written\n");
    return 130;
  } catch (const ahd::Error& e) {
    // printable_path: a control character anywhere (a file name with a newline) must not split the line.
    std::fprintf(stderr, "ahdpack: error: %s\n", ahd::printable_path(e.what()).c_str());
    return 1;
  } catch (const std::bad_alloc&) {
    // Readers bound every allocation by the file and the size limit; this is a machine short of memory.
    std::fprintf(stderr, "ahdpack: error: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ahdpack: internal error: %s\n", e.what());
    return 2;
  }
  return 0;
}
