// Atlas pages → array planes: each page of a multi-page lightmap atlas is converted on its own
// (the same `convert` as a one-page lightmap) and each plane's pages are stacked into one array
// texture, layer p = page p — how an engine binds a lightmap atlas (Godot: a texture array).
#pragma once
#include <vector>

#include "pipeline/convert.h"

namespace ahd {

// Converts every page and stacks the planes. All pages get the same plane set: when
// DirectionPlanes::Auto keeps the direction for some pages and drops it for others, the pages that
// dropped it are converted again with Keep. The result's statistics and errors are every page's
// totals (counts summed; error means texel-weighted, p99 and max the largest page's:
// docs/container-format.md "The report"), its direction reason says which pages decided, its
// warnings are judged on the totals (else each page's, named), and r.pages holds each page's own
// figures (no planes); the complete per-page results go to *per_page when given. Its planes are the stacked arrays, and
// every layer's bytes equal that page's own conversion (with the common plane set). Throws
// ahd::Error when pages is empty or the pages differ in size.
PipelineResult convert_pages(const std::vector<ShImage>& pages, const Profile& profile, const PipelineOptions& opt,
                            std::vector<PipelineResult>* per_page = nullptr);

}  // namespace ahd
