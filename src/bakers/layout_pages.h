// Atlas pages of a paged layout: a file marked "per_page" holds pages × slices layers stacked
// vertically, page-major (Godot: each page's L0, L1y, L1z, L1x, then the next page). The page count
// is what the baker recorded (Godot: slices/vertical in NAME.exr.import = 4 × pages) or --pages;
// when neither is known the image is read as one page only if its layers are then square, and is
// refused otherwise — a wrong count would mix layers of different pages into garbage.
#pragma once
#include <string>

#include "bakers/baker_layout.h"

namespace ahd {

// The most atlas pages a set may hold (docs/robustness-input.md "Reader input files"): a real
// bake has a handful; each page costs a conversion.
constexpr int kMaxAtlasPages = 256;

// Whether any file of the layout is per_page.
bool layout_is_paged(const LayoutPreset& layout);

struct LayoutPages {
  int pages = 1;
  std::string why;  // where the count came from, for the user
};

// The page count of the set named by `input` (base or any file): `requested` (> 0, --pages), else
// the importer's record, else one page when the layers are square. Layouts without per_page files
// have one page (requested must then be 0 or 1). Throws ahd::Error("<file>: <cause>") when the
// count is unknown for non-square layers ("page count unknown …"), when the import's slice count is
// not a multiple of the layout's layers per page, when the count does not divide the image's rows,
// or when --pages contradicts the import file.
LayoutPages layout_pages(const LayoutPreset& layout, const std::string& input, int requested);

// The preset reading page `page` of `pages`: per_page files hold pages × slices layers and every
// source in them is moved to that page's layers.
LayoutPreset layout_page(const LayoutPreset& layout, int page, int pages);

}  // namespace ahd
