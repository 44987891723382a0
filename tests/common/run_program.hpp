#pragma once
// Runs the `isospring` program for end-to-end tests: captures its output and exit status.
#include <sys/wait.h>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>

namespace isospring::testing {

struct ProgramResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

/// Runs a shell command line as written (stdout and stderr captured together).
inline ProgramResult run_program(const std::string& command_line) {
  const std::string command = command_line + " 2>&1";
  ProgramResult result;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer{};
  size_t n = 0;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    result.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

/// Runs `isospring ARGS` (ARGS is passed to the shell as written).
inline ProgramResult run_isospring(const std::string& args) {
  return run_program(std::string(ISOSPRING_EXECUTABLE) + " " + args);
}

/// Runs `ENVIRONMENT isospring ARGS` (passed to the shell as written; ENVIRONMENT an `env`
/// prefix such as "env -u VAR NAME=value", or empty).
inline ProgramResult run_isospring_with_environment(const std::string& environment,
                                                    const std::string& args) {
  return run_program(environment + " " + std::string(ISOSPRING_EXECUTABLE) + " " + args);
}

/// Path of a shipped example: ISOSPRING_SOURCE_DIR/examples/NAME.
inline std::string example(const std::string& name) {
  return std::string(ISOSPRING_SOURCE_DIR) + "/examples/" + name;
}

/// The whole text of a file ("" when it cannot be read).
// A JSON file the program wrote (report.json, model.json), parsed.
inline nlohmann::json read_json(const std::filesystem::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

inline std::string file_contents(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// A fresh temporary folder for one test, removed when the object goes away.
class TemporaryFolder {
 public:
  TemporaryFolder() {
    std::random_device device;
    path_ = std::filesystem::temp_directory_path() /
            ("isospring-test-" + std::to_string(device()) + std::to_string(device()));
    std::filesystem::create_directories(path_);
  }
  ~TemporaryFolder() {
    // ISOSPRING_KEEP_TEST_FOLDERS=1 keeps them for a look (the path goes to stderr).
    if (std::getenv("ISOSPRING_KEEP_TEST_FOLDERS")) {
      std::fprintf(stderr, "kept %s\n", path_.c_str());
      return;
    }
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

}  // namespace isospring::testing
