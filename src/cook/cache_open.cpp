// open_cache (<ahd/cook.h>): which CacheBackend a cache's name selects.
#include <ahd/cook.h>

#include <vector>

#include "cook/conversion_cache.h"

namespace ahd {

std::shared_ptr<const CacheBackend> open_http_cache(const std::string& url, uint64_t max_bytes);  // cook/http_cache.cpp

namespace {

// A backend reached by a name with a scheme ("http://host/path"): one row each, the backend itself
// in its own file (docs/maintaining.md "Adding a cache backend").
struct CacheScheme {
  const char* prefix;
  std::shared_ptr<const CacheBackend> (*open)(const std::string& where, uint64_t max_bytes);
};
const std::vector<CacheScheme>& cache_schemes() {
  static const std::vector<CacheScheme> schemes = {{"http://", open_http_cache}, {"https://", open_http_cache}};
  return schemes;
}

}  // namespace

std::shared_ptr<const CacheBackend> open_cache(const std::string& where, uint64_t max_bytes) {
  for (const CacheScheme& s : cache_schemes())
    if (where.rfind(s.prefix, 0) == 0) return s.open(where, max_bytes);
  return std::make_shared<const ConversionCache>(where, max_bytes);
}

}  // namespace ahd
