// libFuzzer harness: STEP or IGES import through OpenCascade (geometry::read_cad, the reader of
// `import`, `info` and CAD case geometries), built twice: ISOSPRING_FUZZ_EXTENSION is ".step"
// or ".igs". The reader runs OpenCascade's parser first in a forked child (crash_guard.hpp), so
// a crash inside OpenCascade is an InputError here as in the program; each input costs a fork.
// OpenCascade's Standard_Failure is not a std::exception: read_cad must translate it too.
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "fuzz_input.hpp"
#include "isospring/geometry/cad.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const isospring::fuzz::InputFile file(std::string("part") + ISOSPRING_FUZZ_EXTENSION);
  const auto& path = file.write(data, size);
  try {
    isospring::fuzz::expect_input_errors_only([&] {
      const isospring::geometry::CadModel model = isospring::geometry::read_cad(path);
      (void)isospring::geometry::describe(model);
    });
  } catch (...) {
    std::fprintf(stderr, "fuzz: read_cad let a non-standard exception escape\n");
    std::abort();
  }
  return 0;
}
