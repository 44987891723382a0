// libFuzzer harness: case files (io::read_case_file: JSON, validation, geometry, discretisation
// and the problem's supports and loads). Solves are refused above 64 MB (the `--max-memory`
// check) so that an input asking for a huge discretisation fails fast instead of exhausting the
// fuzzer's memory limit. The folder also holds markers.csv, the measurement file of the
// identification cases of the seed corpus.
#include <cstdint>

#include "fuzz_input.hpp"
#include "isospring/io/case_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const isospring::fuzz::InputFile file("case.json");
  static const bool markers_written = (file.add("markers.csv",
                                                "load_case,x,y,ux,uy\n"
                                                "L1,0.0035,0.0028,8.9e-06,-1.1e-06\n"
                                                "L1,0.0107,0.0028,1.8e-05,-9.5e-07\n"
                                                "L2,0.0178,0.0028,2.6e-05,-2.7e-06\n"),
                                       true);
  (void)markers_written;
  const auto& path = file.write(data, size);
  isospring::io::CaseLimits limits;
  limits.solve_memory_bytes = 64e6;
  limits.solve_memory_source = "the fuzzer's limit of 64 MB";
  isospring::fuzz::expect_input_errors_only(
      [&] { (void)isospring::io::read_case_file(path, limits); });
  return 0;
}
