// Optional parts of ahdpack behind dlopen: a dependency that most runs never need (OpenImageIO for
// formats other than EXR, OpenColorIO for colour spaces other than the working one, Assimp for
// meshes) lives in a
// small module, libahd_<name>.so, opened on first use, so that a process that does not need it
// never pays for loading it (docs/performance-real.md "Process start"). A module exports one
// function, `extern "C" const void* ahd_<name>_module()` (exactly that type: it is called through
// it, and UBSan's -fsanitize=function checks), returning its table of plain function pointers whose
// first member is an int ABI number; the table's header (image/oiio_module.h, image/ocio_module.h,
// scene/assimp_module.h) is the contract.
#pragma once
#include <string>

namespace ahd {

// What loading a module gave: its table (null on failure), where it was looked for, and why it
// failed.
struct LoadedModule {
  const void* table = nullptr;
  std::string path, error;
};

// Opens libahd_<name> (.so, .dll on Windows) and checks its table's ABI number. Where it looks,
// relative to the running code only (never a path compiled in: a relocated or copied binary must not
// load whatever a build folder holds at that path now, issue 44):
//  1. installed: <prefix>/<libdir>/ahdpack/ for <prefix>/<bindir>/ahdpack, or for
//     <prefix>/<libdir>/libahd_bakers.so (the install's relative layout, as files/paths.cpp finds
//     formats/);
//  2. beside the executable, then beside the library holding this code (the build tree: CMake puts
//     modules beside ahdpack and copies them beside the test binaries).
// The first that exists; else the executable's neighbour, so the error names where it was looked
// for. Never throws; call it once per module (callers keep the result in a function-local static).
LoadedModule load_module_table(const std::string& name, int abi);

// The table `loaded` holds. Throws ahd::Error("<why>: needs <dependency>, whose module cannot be
// loaded (<loaded.error>)") when it holds none: `why` is the file (or option) that needed it.
const void* module_table(const LoadedModule& loaded, const std::string& why, const char* dependency);

}  // namespace ahd
