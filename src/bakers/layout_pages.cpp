#include "bakers/layout_pages.h"

#include <cstdint>
#include <filesystem>

#include "core/error.h"
#include "files/input_file.h"
#include "bakers/godot/godot_import.h"
#include "image/image_io.h"
#include "files/utf8_path.h"

namespace ahd {
namespace fs = std::filesystem;

bool layout_is_paged(const LayoutPreset& layout) {
  for (const LayoutFile& f : layout.files)
    if (f.per_page) return true;
  return false;
}

namespace {

std::string n_str(long long n) { return std::to_string(n); }

// The first per_page file's path (patterns are "{base}SUFFIX" or contain {base}).
std::string paged_path(const LayoutPreset& layout, const std::string& base, const LayoutFile** file) {
  for (const LayoutFile& f : layout.files)
    if (f.per_page) {
      *file = &f;
      std::string p = f.pattern;
      const size_t at = p.find("{base}");
      if (at != std::string::npos) p.replace(at, 6, base);
      return p;
    }
  return "";
}

// 64-bit: pages and slices come from flags and files (--pages 1073741824 x 4 layers wrapped to 0
// in int and divided by it); more layers than rows is refused before the remainder is taken.
void check_divides(const std::string& path, int64_t rows, int64_t pages, int64_t slices, const std::string& source) {
  if (pages <= 0 || slices <= 0 || pages * slices > rows || rows % (pages * slices) != 0)
    throw file_error(path, n_str(rows) + " rows do not divide into " + n_str(pages) + " page(s) x " + n_str(slices) +
                               " layers (" + source + ")");
  // Each page is a conversion of its own (a fixed cost each): 2048 pages of 2x2 took 150 s.
  if (pages > kMaxAtlasPages)
    throw file_error(path, n_str(pages) + " atlas pages (" + source + "), at most " + n_str(kMaxAtlasPages) + " are read");
}

}  // namespace

LayoutPages layout_pages(const LayoutPreset& layout, const std::string& input, int requested) {
  if (requested < 0) throw Error("--pages must be positive");
  if (!layout_is_paged(layout)) {
    if (requested > 1) throw Error("layout " + layout.name + " has one page per set of files: --pages does not apply");
    return {1, ""};
  }
  const LayoutFile* lf = nullptr;
  const std::string path = paged_path(layout, layout_base(layout, input), &lf);
  if (!input_exists(path)) throw file_error(path, "file not found (layout " + layout.name + " needs it)");
  const ImageFileInfo info = read_image_info(path, lf->part);
  const int slices = lf->slices, rows = info.height;
  const GodotImport gi = read_godot_import(path);
  const std::string import_file = utf8_string(fs_path(path).filename()) + ".import";
  int recorded = 0;
  if (gi.found && gi.slices_vertical > 0) {
    if (gi.slices_vertical % slices != 0)
      throw file_error(path + ".import", "slices/vertical=" + n_str(gi.slices_vertical) + " is not a multiple of the " +
                                             n_str(slices) + " layers per page of layout " + layout.name);
    recorded = gi.slices_vertical / slices;
  }
  if (requested > 0 && recorded > 0 && requested != recorded)
    throw file_error(path + ".import", "records " + n_str(recorded) + " page(s) (slices/vertical=" +
                                           n_str(gi.slices_vertical) + "), --pages says " + n_str(requested));
  if (requested > 0) {
    check_divides(path, rows, requested, slices, "--pages " + n_str(requested));
    return {requested, n_str(requested) + " page(s) from --pages"};
  }
  if (recorded > 0) {
    check_divides(path, rows, recorded, slices, import_file);
    return {recorded, n_str(recorded) + " page(s) from " + import_file + " (slices/vertical=" +
                          n_str(gi.slices_vertical) + " = " + n_str(slices) + " x pages)"};
  }
  if (rows % slices != 0)
    throw file_error(path, "height " + n_str(rows) + " does not divide into " + n_str(slices) + " stacked layers");
  if (rows / slices == info.width)
    return {1, "1 page assumed: no " + import_file + " and no --pages, and " + n_str(slices) + " square layers fill the image"};
  throw file_error(path, "page count unknown: " + n_str(info.width) + "x" + n_str(rows) + " holds " + n_str(slices) +
                             " layers per atlas page but how many pages is not recorded (no " + import_file +
                             " with slices/vertical beside it): give --pages N");
}

LayoutPreset layout_page(const LayoutPreset& layout, int page, int pages) {
  LayoutPreset p = layout;
  auto move = [&](LayoutSource& s) {
    const LayoutFile& f = layout.files[size_t(s.file)];
    if (f.per_page) s.slice += page * f.slices;
  };
  for (LayoutCoefficient& c : p.coefficients) {
    for (LayoutSource& s : c.source) move(s);
    if (c.divided) move(c.divisor);
    if (c.multiplied) move(c.multiplier);
  }
  for (LayoutFile& f : p.files)
    if (f.per_page) f.slices *= pages;
  p.page_count = pages;
  return p;
}

}  // namespace ahd
