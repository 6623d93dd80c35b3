// Converts the built-in sample in memory with the C++ API and writes the files into argv[1].
#include <ahd/convert.h>
#include <ahd/sample.h>

#include <cstdio>
#include <fstream>
#include <string>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: consumer_cpp OUTDIR PROFILE\n");
    return 2;
  }
  try {
    ahd::ConversionOptions opt;
    opt.profile = argv[2];
    const ahd::Conversion c = ahd::convert(ahd::bake_sample(), "sample", opt);
    for (const ahd::OutputFile& f : c.files) {
      std::ofstream out(std::string(argv[1]) + "/" + f.name, std::ios::binary);
      out.write(reinterpret_cast<const char*>(f.bytes.data()), std::streamsize(f.bytes.size()));
      if (!out) return 1;
    }
    std::printf("%zu files, directional %d\n", c.files.size(), int(c.directional));
  } catch (const ahd::Error& e) {
    std::fprintf(stderr, "consumer_cpp: %s\n", e.what());
    return 1;
  }
  return 0;
}
