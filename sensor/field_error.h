#pragma once
// The message every parameter check in sensor/ gives for a bad value
// (cells, grooves, saddles, scanners, sim cells), so each prints its numbers
// the same way.
#include <string>
#include <string_view>

namespace vts {

// "<field> = <value>: <why>", e.g. "gap_mm = -1: must be >= 0".
std::string field_error(std::string_view field, double value, std::string_view why);
// A number as those messages print it (std::ostream's default: 6
// significant digits).
std::string message_number(double value);

}  // namespace vts
