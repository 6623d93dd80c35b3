// <ahd/cook.h>: the public cook over cook/cook.h, and the directory cache as a CacheBackend.
// Compiled into the installed ahdpack::cook only (CMakeLists.txt).
#include <ahd/cook.h>

#include "cook/conversion_cache.h"
#include "cook/cook.h"

namespace ahd {

CookResult cook(const CookRequest& request, const CookEvents& events) { return cook_conversion(request, {events, {}}); }

std::shared_ptr<const CacheBackend> directory_cache(const std::string& dir, uint64_t max_bytes) {
  return std::make_shared<const ConversionCache>(dir, max_bytes);
}

}  // namespace ahd
