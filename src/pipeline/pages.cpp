#include "pipeline/pages.h"

#include "core/error.h"

namespace ahd {

PipelineResult convert_pages(const std::vector<ShImage>& pages, const Profile& profile, const PipelineOptions& opt,
                            std::vector<PipelineResult>* per_page) {
  if (pages.empty()) throw Error("no atlas pages to convert");
  for (const ShImage& p : pages)
    if (p.width != pages[0].width || p.height != pages[0].height) throw Error("atlas pages differ in size");
  std::vector<PipelineResult> results;
  bool any_directional = false;
  for (const ShImage& p : pages) {
    results.push_back(run_conversion(p, profile, opt));
    any_directional = any_directional || results.back().directional;
  }
  // One plane set for the whole array: a page whose lighting alone would drop the direction keeps
  // it when another page needs it.
  if (any_directional) {
    PipelineOptions keep = opt;
    keep.direction = DirectionPlanes::Keep;
    for (size_t i = 0; i < pages.size(); ++i)
      if (!results[i].directional) results[i] = run_conversion(pages[i], profile, keep);
  }
  PipelineResult r = results[0];
  for (size_t k = 0; k < r.planes.size(); ++k) {
    std::vector<Texture> layers;
    for (const PipelineResult& pr : results) {
      if (pr.planes.size() != r.planes.size() || pr.planes[k].name != r.planes[k].name)
        throw Error("atlas pages converted to different plane sets");
      layers.push_back(pr.planes[k].texture);
    }
    r.planes[k].texture = stack_layers(layers);
  }
  for (size_t i = 1; i < results.size(); ++i)
    for (size_t t = 0; t < r.timings.size() && t < results[i].timings.size(); ++t) r.timings[t].seconds += results[i].timings[t].seconds;
  r.direction_reason += " (page 0 of " + std::to_string(pages.size()) + "; one plane set for every page)";
  if (per_page) *per_page = std::move(results);
  return r;
}

}  // namespace ahd
