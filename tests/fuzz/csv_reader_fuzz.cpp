// libFuzzer target: any bytes given as a CSV profile file either read into
// profiles or raise vts::CsvError; anything else (a crash, another exception)
// is a bug. What reads must also write back (write_profile_csv) and read again
// to the same y, z and valid bit for bit, as sensor/profile_csv.h promises.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "sensor/profile_csv.h"

namespace {

void check(bool ok) {
  if (!ok) std::abort();
}

bool same_floats(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  std::vector<vts::Profile> profiles;
  try {
    profiles = vts::read_profile_csv(in, "fuzz.csv");
  } catch (const vts::CsvError&) {
    return 0;
  }
  for (const vts::Profile& p : profiles) {
    const std::size_t n = p.y_mm.size();
    check(p.z_mm.size() == n && p.valid.size() == n && p.range_mm.size() == n);
    check(p.index >= 0);
  }
  std::ostringstream out;
  vts::write_profile_csv(out, profiles);
  std::istringstream back_in(out.str());
  std::vector<vts::Profile> back;
  try {
    back = vts::read_profile_csv(back_in, "fuzz-roundtrip.csv");
  } catch (const vts::CsvError&) {
    std::abort();  // what we write must read back
  }
  // Profiles without points have no rows, so they do not come back.
  std::vector<const vts::Profile*> nonempty;
  for (const vts::Profile& p : profiles)
    if (!p.y_mm.empty()) nonempty.push_back(&p);
  check(back.size() == nonempty.size());
  for (std::size_t i = 0; i < back.size(); ++i) {
    check(back[i].index == nonempty[i]->index);
    check(same_floats(back[i].y_mm, nonempty[i]->y_mm));
    check(same_floats(back[i].z_mm, nonempty[i]->z_mm));
    check(back[i].valid == nonempty[i]->valid);
  }
  return 0;
}
