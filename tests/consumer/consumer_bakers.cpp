// A cook step outside the tree, on the installed ahdpack::bakers and ahdpack::cook:
//   consumer_bakers cook IN OUT [--profile P] [--zstd] [--cache DIR] [--depfile F] [--mesh M]
//       what `ahdpack convert IN -o OUT …` does, through ahd::cook (prints "key KEY" with --cache)
//   consumer_bakers key IN OUT [--profile P] [--mesh M]
//       the conversion's key (`ahdpack convert --print-key`)
//   consumer_bakers read IN OUTDIR NAME [--profile P] [--mesh M]
//       ahd::read_bake, then ahd::convert in memory, the files written into OUTDIR
#include <ahd/bakers.h>
#include <ahd/convert.h>
#include <ahd/cook.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: consumer_bakers cook|key|read IN OUT [options]\n");
    return 2;
  }
  const std::string mode = argv[1];
  ahd::CookRequest r;
  r.input.input = argv[2];
  r.output = argv[3];
  std::string name = "out";
  int i = 4;
  if (mode == "read" && argc > 4) name = argv[i++];
  for (; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--zstd") r.options.zstd = true;
    else if (a == "--profile" && has_value) r.options.profile = argv[++i];
    else if (a == "--cache" && has_value)
      r.cache = ahd::directory_cache(argv[++i], ahd::parse_byte_size("10G", "--cache-max-size"));
    else if (a == "--depfile" && has_value) r.depfile = argv[++i];
    else if (a == "--mesh" && has_value) r.input.mesh = argv[++i];
    else {
      std::fprintf(stderr, "consumer_bakers: unknown option %s\n", a.c_str());
      return 2;
    }
  }
  // The command's default (conversion_args.h): an error estimate in the report.
  r.options.measure = ahd::Measure::Estimate;
  try {
    if (mode == "cook" || mode == "key") {
      r.key_only = mode == "key";
      const ahd::CookResult res = ahd::cook(r);
      if (!res.key.empty()) std::printf("key %s\n", res.key.c_str());
      std::printf("%s: %dx%d, %zu planes, %zu files read\n", res.source.c_str(), res.width, res.height, res.planes,
                  res.files_read.size());
    } else if (mode == "read") {
      const ahd::BakeRead b = ahd::read_bake(r.input);
      if (b.pages.size() != 1)
        throw ahd::Error("read: " + std::to_string(b.pages.size()) + " pages (this test converts one)");
      const ahd::Conversion c = ahd::convert(b.pages[0], name, r.options, b.instances);
      for (const ahd::OutputFile& f : c.files) {
        std::ofstream out(r.output + "/" + f.name, std::ios::binary);
        out.write(reinterpret_cast<const char*>(f.bytes.data()), std::streamsize(f.bytes.size()));
        if (!out) return 1;
      }
      std::printf("%s: %zu files read, %zu probes, %zu files written\n", b.source.c_str(), b.files.size(),
                  b.probes.size(), c.files.size());
    } else {
      std::fprintf(stderr, "consumer_bakers: unknown mode %s\n", mode.c_str());
      return 2;
    }
  } catch (const ahd::Error& e) {
    std::fprintf(stderr, "consumer_bakers: %s\n", e.what());
    return 1;
  }
  return 0;
}
