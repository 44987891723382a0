// libFuzzer harness: patch files (io::read_patch_file). A patch the reader accepts must then be
// safe to evaluate: its corners and centre are evaluated (ASan/UBSan check the reader's
// validation of degrees, knots, control point counts and weights).
#include <cstdint>

#include "fuzz_input.hpp"
#include "isospring/io/patch_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const isospring::fuzz::InputFile file("patches.json");
  const auto& path = file.write(data, size);
  isospring::fuzz::expect_input_errors_only([&] {
    for (const auto& patch : isospring::io::read_patch_file(path)) {
      for (int corner = 0; corner < 9; ++corner) {
        isospring::nurbs::Param u{0, 0, 0};
        for (int d = 0; d < patch.param_dim(); ++d) {
          const int pick = (corner >> d) % 2 + (corner == 8 ? 2 : 0);
          u[static_cast<size_t>(d)] = pick == 0   ? patch.param_min(d)
                                      : pick == 1 ? patch.param_max(d)
                                                  : 0.5 * (patch.param_min(d) + patch.param_max(d));
        }
        // Not required finite: control points near the double range may overflow the sum.
        volatile double x = patch.point(u).x();
        (void)x;
      }
    }
  });
  return 0;
}
