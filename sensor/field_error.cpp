#include "sensor/field_error.h"

#include <sstream>

namespace vts {

std::string field_error(std::string_view field, double value, std::string_view why) {
  std::ostringstream s;
  s << field << " = " << value << ": " << why;
  return s.str();
}

std::string message_number(double value) {
  std::ostringstream s;
  s << value;
  return s.str();
}

}  // namespace vts
