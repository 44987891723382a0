// libFuzzer harness: marker CSV files (io::read_markers_csv), read as a 3D file of a case with
// load cases L1 and L2 and as a 2D file with a default load case. Accepted markers must be
// finite.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "fuzz_input.hpp"
#include "isospring/io/markers.hpp"

namespace {

void check(const isospring::fitting::Measurements& data) {
  for (const auto& marker : data.markers)
    if (!marker.position.allFinite() || !marker.displacement.allFinite() ||
        !std::isfinite(marker.sigma)) {
      std::fprintf(stderr, "fuzz: accepted a non-finite marker (row %d)\n", marker.row);
      std::abort();
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const isospring::fuzz::InputFile file("markers.csv");
  const auto& path = file.write(data, size);
  isospring::io::MarkerFileOptions solid;
  solid.load_cases = {"L1", "L2"};
  isospring::fuzz::expect_input_errors_only([&] { check(read_markers_csv(path, solid)); });
  isospring::io::MarkerFileOptions plane;
  plane.dimension = 2;
  plane.unit_scale = 1e-3;
  plane.default_load_case = "L1";
  isospring::fuzz::expect_input_errors_only([&] { check(read_markers_csv(path, plane)); });
  return 0;
}
