// Writes profiles-v1.exr: the recording of tests/sensor/exr_fixture.h through
// the version-1 writer (the ProfileExrWriter of commit 9fdf564, before
// version 2). Not built by CMake; tests/data/README.md says how it was run.
#include "sensor/profile_exr.h"
#include "tests/sensor/exr_fixture.h"

int main(int argc, char** argv) {
  const vts::ProfileFileInfo info = vts::test::fixture_info();
  vts::ProfileExrWriter writer(argc > 1 ? argv[1] : "profiles-v1.exr", info);
  for (int r = 0; r < info.profiles; ++r) {
    const vts::Profile p = vts::test::fixture_profile(info.scanner.points, r);
    const vts::Profile ref = vts::test::fixture_profile(info.scanner.points, r, 1);
    writer.write(p, &ref);
  }
  writer.finish();
}
