// The floor a reader of ahdpack could reach (issue 28, docs/performance-real.md): a process that
// links OpenEXR only (no OpenImageIO), reads an RGB(A) EXR's first part into float RGB with
// OpenEXR's own threads, and prints its stage times. Not part of the build and not part of
// ahdpack: scripts/probe-exr-read.sh compiles and runs it beside `oiiotool` and `ahdpack --help`.
#include <time.h>

#include <cstdio>
#include <vector>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfThreading.h>

namespace {
double seconds(clockid_t id) {
  timespec t;
  clock_gettime(id, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}
}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return std::fprintf(stderr, "usage: exr_read FILE.exr [threads]\n"), 1;
  const double w0 = seconds(CLOCK_MONOTONIC), c0 = seconds(CLOCK_PROCESS_CPUTIME_ID);
  Imf::setGlobalThreadCount(argc > 2 ? std::atoi(argv[2]) : 2);
  Imf::InputFile in(argv[1]);
  const Imath::Box2i dw = in.header().dataWindow();
  const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
  std::vector<float> rgb(size_t(w) * h * 3);
  Imf::FrameBuffer fb;
  const char* names[3] = {"R", "G", "B"};
  for (int c = 0; c < 3; ++c) {
    char* base = reinterpret_cast<char*>(rgb.data() + c) -
                 (size_t(dw.min.y) * w + dw.min.x) * 3 * sizeof(float);
    fb.insert(names[c], Imf::Slice(Imf::FLOAT, base, 3 * sizeof(float), size_t(w) * 3 * sizeof(float)));
  }
  in.setFrameBuffer(fb);
  in.readPixels(dw.min.y, dw.max.y);
  double sum = 0;
  for (size_t i = 0; i < rgb.size(); i += 997) sum += rgb[i];
  std::printf("%dx%d read in %.3f s wall, %.3f s CPU (checksum %.6g)\n", w, h, seconds(CLOCK_MONOTONIC) - w0,
              seconds(CLOCK_PROCESS_CPUTIME_ID) - c0, sum);
}
