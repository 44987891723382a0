#include "runtime_test_support.hpp"

#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <new>

namespace {
std::atomic<long> allocations{0};
}  // namespace

// Counting replacements of the global allocation functions (every other form forwards here).
void* operator new(std::size_t size) {
  allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}

namespace isospring::runtime {

ModelHandle load_model(const std::filesystem::path& path) {
  char error[1000] = "";
  isospring_model* m = isospring_model_load(path.c_str(), error, sizeof(error));
  if (!m) ADD_FAILURE() << "the runtime refused " << path << ": " << error;
  return ModelHandle(m, ModelDeleter());
}

std::string load_error(const std::string& text, const std::string& source) {
  char error[1000] = "";
  isospring_model* m =
      isospring_model_parse(text.data(), text.size(), source.c_str(), error, sizeof(error));
  isospring_model_free(m);
  return m ? std::string() : std::string(error);
}

std::filesystem::path test_directory() {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("isospring_test_runtime-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

long allocation_count() {
  return allocations.load();
}

}  // namespace isospring::runtime
