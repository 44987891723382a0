#pragma once
// Shared by the libFuzzer harnesses: the readers under test take file names, so each input is
// written to a file of this process's own temporary folder first (removed at exit).
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

#include "isospring/nurbs/error.hpp"

namespace isospring::fuzz {

class InputFile {
 public:
  explicit InputFile(const std::string& file_name)
      : folder_(std::filesystem::temp_directory_path() /
                ("isospring-fuzz-" + std::to_string(::getpid()))),
        path_(folder_ / file_name) {
    std::filesystem::create_directories(folder_);
  }
  ~InputFile() {
    std::error_code ignored;
    std::filesystem::remove_all(folder_, ignored);
  }
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  /// The input file with these bytes.
  const std::filesystem::path& write(const uint8_t* data, size_t size) const {
    write_file(path_, reinterpret_cast<const char*>(data), size);
    return path_;
  }

  /// Another file beside the input (e.g. the data file a case file names).
  void add(const std::string& file_name, const std::string& text) const {
    write_file(folder_ / file_name, text.data(), text.size());
  }

 private:
  static void write_file(const std::filesystem::path& path, const char* data, size_t size) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(data, static_cast<std::streamsize>(size));
    out.close();
    if (!out) {
      std::fprintf(stderr, "fuzz: cannot write %s\n", path.c_str());
      std::abort();
    }
  }

  std::filesystem::path folder_, path_;
};

/// Runs `read`: an nurbs::InputError (the documented answer to a bad file: exit 1 with a message)
/// is expected; any other exception would reach the user as an internal error (exit 3/4), so the
/// harness aborts, and libFuzzer keeps the input as a crash.
template <class Read>
void expect_input_errors_only(Read&& read) {
  try {
    read();
  } catch (const nurbs::InputError& e) {
    if (std::string(e.what()).empty()) {
      std::fprintf(stderr, "fuzz: an InputError without a message\n");
      std::abort();
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz: not an InputError: %s\n", e.what());
    std::abort();
  }
}

}  // namespace isospring::fuzz
