// ahdpack: SH lightmaps in, AHD directional lightmaps out. A thin shell over the library.
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>

#if defined(__GLIBC__)
#include <malloc.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#endif

#include <ahd/version.h>

#include "cli/commands.h"
#include "cli/environment.h"
#include "core/error.h"
#include "core/large_buffer.h"

namespace {

// Every top-level command and the call that declares it (one call may declare two), in the order
// `ahdpack --help` lists them. CLI11 builds every option eagerly: all the commands cost ≈ 3 M
// instructions, a sixth of a small conversion's process start, so a run that names a command
// declares only that one; anything else (--help, a typo) declares them all.
struct Command {
  const char* name;
  void (*add)(CLI::App&);
};
constexpr Command kCommands[] = {
    {"convert", ahd::cli::add_convert_command},      {"layouts", ahd::cli::add_layouts_command},
    {"decode", ahd::cli::add_decode_command},        {"inspect", ahd::cli::add_inspect_command},
    {"compress", ahd::cli::add_compress_commands},   {"decompress", ahd::cli::add_compress_commands},
    {"sample", ahd::cli::add_sample_command},        {"transcode", ahd::cli::add_transcode_command},
    {"preview", ahd::cli::add_preview_command},      {"verify", ahd::cli::add_verify_command},
    {"scene", ahd::cli::add_scene_command},          {"bench", ahd::cli::add_lab_commands},
    {"report", ahd::cli::add_lab_commands},
};

// glibc maps every block of 128 KB or more on its own and unmaps it when freed, so each stage's
// buffers (a 256² map's are 0.2–1 MB) come back as fresh pages that fault in again, one by one: on
// this project's VM a plain 256² conversion took 1 950 page faults. Blocks under 32 MB now come
// from the heap, and up to 64 MB freed at its top is kept for the next stage; larger ones (a
// 2048² map's planes) are still mapped on their own and advised for huge pages
// (core/large_buffer.h). Plain 256²: 9 % less CPU, 0.9 MB more peak (docs/performance-real.md
// "Small maps"). Memory only: no output byte depends on it.
// AHD_MALLOC_DEFAULTS=1 leaves glibc's allocator as it is (`bench convert` measures OpenImageIO's
// read that way: the baseline is an application's read, not one with this tuning).
void tune_allocator() {
#if defined(__GLIBC__)
  if (const char* keep = std::getenv("AHD_MALLOC_DEFAULTS"); keep && *keep && std::strcmp(keep, "0") != 0) return;
  mallopt(M_TRIM_THRESHOLD, 64 << 20);
  // The first pages are fresh too, and each 4 KB one costs a fault (10–30 µs on a VM: an L1 256²
  // conversion took 2 800). So the heap grows in 64 MB steps and its first step is advised for
  // 2 MB pages, one heap serving every thread: L1/L2 256² ~1 200 faults, 5–8 % less CPU, +1 MB peak.
  mallopt(M_ARENA_MAX, 1);
  mallopt(M_TOP_PAD, 64 << 20);
  // The heap is grown by one block of kGrow (from the heap: the mapping threshold is raised for
  // it), advised, and given back. Two stretches of 2 MB would otherwise stay 4 KB pages:
  // - the one the heap's top header lands in when it grows (written before the advice, its page
  //   table then rules out a huge page there): at p + kGrow, past the 64 MB the heap keeps when the
  //   block is freed, so that stretch is unmapped again;
  // - the one from p to the first 2 MB boundary: a block that fills it, kept for the process and
  //   never written, starts the next blocks at the boundary.
  // Faults of a whole conversion on the project's VM: L1 256² 1 380 → 380, plain 256² 370–840
  // (where the heap happened to start) → 380–420 (docs/performance-real.md "Small maps, round 9").
  constexpr size_t kGrow = size_t(68) << 20, kHuge = size_t(2) << 20;
  mallopt(M_MMAP_THRESHOLD, 128 << 20);
  if (void* p = std::malloc(kGrow)) {  // the heap grows by kGrow + 64 MB (address space only)
    const uintptr_t from = reinterpret_cast<uintptr_t>(p), top = reinterpret_cast<uintptr_t>(sbrk(0));
    if (top > from && top - from <= kGrow + (size_t(80) << 20)) ahd::advise_huge_pages(p, size_t(top - from));
    std::free(p);
    const uintptr_t gap = ((from + kHuge - 1) & ~(kHuge - 1)) - from;
    if (gap >= 4096) {
      void* fill = std::malloc(gap - 2 * sizeof(size_t));
      if (fill != p) std::free(fill);  // not where the heap's top was: no gain, give it back
    }
  }
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
#endif
}

void add_commands(CLI::App& app, int argc, char** argv) {
  if (argc > 1)
    for (const Command& c : kCommands)
      if (std::strcmp(argv[1], c.name) == 0) return c.add(app);
  void (*last)(CLI::App&) = nullptr;
  for (const Command& c : kCommands)
    if (c.add != last) c.add(app), last = c.add;
}

}  // namespace

int main(int argc, char** argv) {
  tune_allocator();
  CLI::App app{"ahdpack: turn spherical-harmonics lightmaps into filter-safe AHD directional lightmaps"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "ahdpack " AHD_VERSION_STRING_LITERAL);
  add_commands(app, argc, argv);
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
    // One line: ahd::Error's constructor escaped any control character (a file name with a newline).
    std::fprintf(stderr, "ahdpack: error: %s\n", e.what());
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
