// libFuzzer harness: spring model files (io::read_model_json, `model.json`). An accepted model
// must be a consistent network: check_spring_network finds nothing and its load cases name
// existing particles (the exports index particles with them).
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "fuzz_input.hpp"
#include "isospring/io/model_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const isospring::fuzz::InputFile file("model.json");
  const auto& path = file.write(data, size);
  isospring::fuzz::expect_input_errors_only([&] {
    const isospring::io::SpringModel model = isospring::io::read_model_json(path);
    const std::string problem = isospring::io::check_spring_network(model.network);
    if (!problem.empty()) {
      std::fprintf(stderr, "fuzz: accepted an inconsistent model: %s\n", problem.c_str());
      std::abort();
    }
    for (size_t c = 0; c < model.load_cases.size(); ++c) {
      const Eigen::VectorXd force = isospring::io::model_force_vector(model, c, true);
      (void)force;
    }
  });
  return 0;
}
