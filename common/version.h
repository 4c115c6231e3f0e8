#pragma once
// The vts version (CMake's project version), for `vts --version` and the
// files that record which vts wrote them (dataset manifests).
#include <string_view>

namespace vts {

std::string_view version();

}  // namespace vts
