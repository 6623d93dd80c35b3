#include "pipeline/pages.h"

#include <algorithm>

#include "core/error.h"

namespace ahd {

namespace {

// Error figures of several pages as one: texel-weighted mean, largest max; the p99 is the largest
// page's p99, an upper bound of the pooled p99 (no page has more than 1 % of its texels above it,
// so neither has the union). docs/container-format.md "The report".
ErrorReport combine(const std::vector<const ErrorReport*>& parts) {
  ErrorReport e;
  auto add = [](ErrorStat* to, const ErrorStat& s, double w) {
    to->mean += s.mean * w;
    to->p99 = std::max(to->p99, s.p99);
    to->max = std::max(to->max, s.max);
  };
  for (const ErrorReport* p : parts) {
    e.texels += p->texels, e.population += p->population, e.negative += p->negative;
    const double w = double(p->texels);
    add(&e.rmse, p->rmse, w), add(&e.relative, p->relative, w), add(&e.log2, p->log2, w), add(&e.normal_rel, p->normal_rel, w);
  }
  if (e.texels)
    for (ErrorStat* s : {&e.rmse, &e.relative, &e.log2, &e.normal_rel}) s->mean /= double(e.texels);
  return e;
}

ErrorReport combine(const std::vector<PipelineResult>& pages, ErrorReport PipelineResult::*field) {
  std::vector<const ErrorReport*> parts;
  for (const PipelineResult& p : pages) parts.push_back(&(p.*field));
  return combine(parts);
}

std::string page_list(const std::vector<size_t>& pages) {
  std::string s;
  for (size_t i = 0; i < pages.size(); ++i) s += (i ? ", " : "") + std::to_string(pages[i]);
  return s;
}

// The first pass's reason with the verb taken off ("kept: I_z alone …" → "I_z alone …").
std::string reason_body(const std::string& r) {
  const size_t at = r.find(": ");
  return at == std::string::npos ? r : r.substr(at + 2);
}

// Every page's figures as the atlas's: counts summed, errors combined, warnings judged on the totals.
void total_pages(const std::vector<PipelineResult>& results, PipelineResult* r) {
  FitStats fs;
  PlaneCodecStats cs;
  L1Figures l1;
  for (const PipelineResult& p : results) {
    const FitStats& s = p.fit_stats;
    fs.texels += s.texels, fs.covered += s.covered, fs.no_direction += s.no_direction, fs.dir_clamped += s.dir_clamped;
    fs.negative_iz += s.negative_iz, fs.black += s.black, fs.guard_reverted += s.guard_reverted;
    cs.clamped += p.codec_stats.clamped, cs.non_finite += p.codec_stats.non_finite;
    l1 += p.l1;
  }
  r->fit_stats = fs;
  r->codec_stats = cs;
  r->l1 = l1;
  r->fit_error = combine(results, &PipelineResult::fit_error);
  r->unconstrained_error = combine(results, &PipelineResult::unconstrained_error);
  r->open_loop_error = combine(results, &PipelineResult::open_loop_error);
  r->final_error = combine(results, &PipelineResult::final_error);
  r->ambient_error = combine(results, &PipelineResult::ambient_error);
  for (size_t l = 0; l < r->level_error.size(); ++l) {
    std::vector<const ErrorReport*> parts;
    for (const PipelineResult& p : results)
      if (l < p.level_error.size()) parts.push_back(&p.level_error[l]);
    r->level_error[l] = combine(parts);
  }
  for (size_t l = 0; l < r->dilate_stats.size(); ++l) {
    DilateStats d;
    for (const PipelineResult& p : results) {
      if (l >= p.dilate_stats.size()) continue;
      const DilateStats& s = p.dilate_stats[l];
      d.covered += s.covered, d.guard += s.guard, d.filled += s.filled, d.far += s.far, d.rings = std::max(d.rings, s.rings);
    }
    r->dilate_stats[l] = d;
  }
  // Judged on the totals; when they pass, a damaged page among sound ones is still said, by page.
  r->warnings = sh_input_warnings(r->l1, r->fit_stats, r->coeffs);
  if (r->warnings.empty())
    for (size_t p = 0; p < results.size(); ++p)
      for (const std::string& w : results[p].warnings) r->warnings.push_back("page " + std::to_string(p) + ": " + w);
}

}  // namespace

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
  std::vector<size_t> kept, dropped;
  std::string first_reason;  // the first pass's reason of a page that decided the plane set
  for (size_t i = 0; i < pages.size(); ++i) {
    (results[i].directional ? kept : dropped).push_back(i);
    if (first_reason.empty() && results[i].directional == any_directional) first_reason = results[i].direction_reason;
  }
  if (any_directional) {
    PipelineOptions keep = opt;
    keep.direction = DirectionPlanes::Keep;
    for (size_t i : dropped) {
      const std::string alone = results[i].direction_reason;
      results[i] = run_conversion(pages[i], profile, keep);
      results[i].direction_reason = alone + "; kept for the atlas's one plane set";
    }
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
  total_pages(results, &r);
  // The decision over every page: which pages decided it, and that one plane set serves them all.
  const std::string n = std::to_string(pages.size());
  if (dropped.empty() || kept.empty())
    r.direction_reason = first_reason + " (every one of the " + n + " pages; one plane set for every page)";
  else
    r.direction_reason = "kept: " + reason_body(first_reason) + " on page(s) " + page_list(kept) + " of " + n +
                         "; page(s) " + page_list(dropped) + " would drop them alone and keep them for the one plane set";
  for (PipelineResult& p : results) {  // the report's per-page figures: no copy of the planes
    std::vector<Plane> planes = std::move(p.planes);
    r.pages.push_back(p);
    r.pages.back().timings.clear();
    p.planes = std::move(planes);
  }
  if (per_page) *per_page = std::move(results);
  return r;
}

}  // namespace ahd
