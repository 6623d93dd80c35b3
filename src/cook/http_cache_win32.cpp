// open_http_cache on Windows: the HTTP cache's client (cook/http_cache.cpp) speaks over POSIX
// sockets, not ported to Winsock yet (docs/platforms.md "Windows").
#ifdef _WIN32
#include <ahd/cook.h>

#include "core/error.h"

namespace ahd {

std::shared_ptr<const CacheBackend> open_http_cache(const std::string& url, uint64_t /*max_bytes*/) {
  throw Error(url + ": an HTTP cache is not available in the Windows build yet; use a cache folder");
}

}  // namespace ahd
#endif  // _WIN32
