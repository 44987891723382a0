#pragma once
// Helpers of the runtime tests: an owning handle, loading that fails the test with the runtime's
// message, a scratch folder per process, and a count of operator new calls.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>

#include "isospring/runtime/runtime.h"

namespace isospring::runtime {

struct ModelDeleter {
  void operator()(isospring_model* m) const { isospring_model_free(m); }
};
using ModelHandle = std::shared_ptr<isospring_model>;

/// Loads a model; ADD_FAILURE with the runtime's message when it is refused (returns null).
ModelHandle load_model(const std::filesystem::path& path);

/// The runtime's error for a document (empty when it loads).
std::string load_error(const std::string& text, const std::string& source = "model.json");

/// A folder of this test process (CTest runs tests in parallel processes).
std::filesystem::path test_directory();

/// operator new calls so far in this process.
long allocation_count();

}  // namespace isospring::runtime
