// A failed write says why: the rename's own error, not the "Success" of the cleanup after it.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

#include "isospring/io/atomic_file.hpp"
#include "isospring/nurbs/error.hpp"
#include "run_program.hpp"

namespace isospring::io {
namespace {
namespace fs = std::filesystem;

TEST(AtomicFileErrors, AFailedRenameGivesItsReason) {
  isospring::testing::TemporaryFolder dir;
  const fs::path target = dir.path() / "taken";
  fs::create_directories(target / "child");  // a non-empty folder: rename(file, folder) fails
  try {
    write_file_atomically(target, "text");
    FAIL() << "writing over a folder succeeded";
  } catch (const nurbs::InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(target.string()), std::string::npos) << message;
    EXPECT_NE(message.find(std::strerror(EISDIR)), std::string::npos) << message;
    EXPECT_EQ(message.find("Success"), std::string::npos) << message;
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1)
      << "the temporary file was left behind";
}

}  // namespace
}  // namespace isospring::io
