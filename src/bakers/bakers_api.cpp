// <ahd/bakers.h>: the public baker reader over bakers/bake_input.h (the reader `ahdpack convert`
// uses). Compiled into the installed ahdpack::bakers only (CMakeLists.txt).
#include <ahd/bakers.h>

#include "bakers/bake_input.h"
#include "bakers/baker_layout.h"
#include "bakers/layout_detect.h"
#include "bakers/scene_export.h"
#include "core/error.h"
#include "files/input_record.h"
#include "image/image_io.h"

namespace ahd {

BakeRead read_bake(const BakeSource& source, int threads) {
  if (source.struct_size != sizeof(BakeSource))
    throw Error("ahd::read_bake: BakeSource of another ahdpack version (struct_size " +
                std::to_string(source.struct_size) + ", this library " + std::to_string(sizeof(BakeSource)) + ")");
  BakeInput in;
  static_cast<BakeSource&>(in) = source;
  InputRecord record;
  ReadStats rs;
  BakeRead out;
  {
    // The same steps, in the same order, as the cook (cook/cook.cpp): every file read is noted.
    const RecordInputs recording(&record);
    const ImageInfoScope headers;  // the input's header read once (image/image_io.h)
    resolve_auto_layout(&in);
    find_scene_for_input(&in);
    check_bake_input(in);
    out.pages = read_bake_pages(in, threads, &rs, &out.source);
  }
  out.notes = in.notes;
  out.non_finite_texels = rs.non_finite_texels;
  out.coverage_derived = rs.coverage_derived;
  out.input_space = rs.input_space;
  out.files = std::move(record.files);
  out.probes = std::move(record.probes);
  // As the cook (cook/cook.cpp), after the inputs are recorded: the manifest's "instances".
  for (const ManifestInstance& m : bake_instances(in)) {
    LightmapInstance i;
    i.node = m.node;
    i.page = m.page;
    for (int k = 0; k < 2; ++k) i.uv_scale[k] = m.scale[k], i.uv_offset[k] = m.offset[k];
    out.instances.push_back(std::move(i));
  }
  return out;
}

std::vector<std::string> bake_layouts() { return list_layouts(); }

std::vector<std::string> auto_detected_bake_layouts() { return auto_detected_layouts(); }

}  // namespace ahd
