#include "common/version.h"

namespace vts {

std::string_view version() { return VTS_VERSION; }

}  // namespace vts
