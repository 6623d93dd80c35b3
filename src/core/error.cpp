#include "core/error.h"

namespace ahd {

Error::Error(const std::string& what) : std::runtime_error(printable_path(what)) {}

Error::Error(const char* what) : std::runtime_error(printable_path(what)) {}

}  // namespace ahd
