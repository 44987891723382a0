// Output checks made before any work (io/output_guard.hpp): an output never resolves to an
// input (same name, another spelling, a symlink, a hard link), and a folder that cannot be
// written is reported with the reason, without creating anything.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "isospring/io/output_guard.hpp"
#include "isospring/nurbs/error.hpp"
#include "run_program.hpp"

namespace isospring::io {
namespace {
namespace fs = std::filesystem;
using isospring::testing::TemporaryFolder;

void touch(const fs::path& path) {
  std::ofstream(path) << "{}\n";
}

// The message of the InputError `check` throws ("" when it throws none).
template <typename Check>
std::string error_of(Check check) {
  try {
    check();
  } catch (const nurbs::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(OutputGuard, AnOutputThatIsAnInputUnderAnyNameIsRefused) {
  TemporaryFolder dir;
  const fs::path input = dir.path() / "p.json";
  touch(input);
  fs::create_directory(dir.path() / "sub");
  fs::create_symlink(input, dir.path() / "link.json");
  fs::create_hard_link(input, dir.path() / "hard.json");
  for (const fs::path& output : {input, dir.path() / "sub" / ".." / "p.json",
                                 dir.path() / "link.json", dir.path() / "hard.json"}) {
    const std::string message = error_of([&] { check_outputs_spare_inputs({input}, {output}); });
    EXPECT_NE(message.find("would overwrite the input"), std::string::npos) << output;
    EXPECT_NE(message.find(output.string()), std::string::npos) << message;
    EXPECT_NE(message.find(input.string()), std::string::npos) << message;
  }
}

TEST(OutputGuard, DistinctFilesPass) {
  TemporaryFolder dir;
  touch(dir.path() / "p.json");
  EXPECT_NO_THROW(check_outputs_spare_inputs(
      {dir.path() / "p.json"}, {dir.path() / "q.json", dir.path() / "new" / "p.json"}));
}

TEST(OutputGuard, AFileInTheWayOfTheFolderIsReported) {
  TemporaryFolder dir;
  touch(dir.path() / "file");
  const std::string message = error_of([&] { check_writable_folder(dir.path() / "file" / "out"); });
  EXPECT_NE(message.find("is not a folder"), std::string::npos) << message;
}

TEST(OutputGuard, AnUnwritableFolderIsReportedWithTheReason) {
  // /sys refuses new files even to root, who passes every permission check elsewhere.
  const std::string message = error_of([] { check_writable_folder("/sys/isospring-out"); });
  ASSERT_FALSE(message.empty());
  EXPECT_NE(message.find("/sys/isospring-out"), std::string::npos) << message;
  EXPECT_EQ(message.find("Success"), std::string::npos) << message;
  if (::geteuid() != 0) {  // permissions only bind other users
    TemporaryFolder dir;
    fs::permissions(dir.path(), fs::perms::owner_read | fs::perms::owner_exec);
    const std::string denied = error_of([&] { check_writable_folder(dir.path() / "out"); });
    fs::permissions(dir.path(), fs::perms::owner_all);
    EXPECT_NE(denied.find("Permission denied"), std::string::npos) << denied;
  }
}

TEST(OutputGuard, AWritableFolderPassesAndIsNotCreated) {
  TemporaryFolder dir;
  EXPECT_NO_THROW(check_writable_folder(dir.path() / "a" / "b"));
  EXPECT_FALSE(fs::exists(dir.path() / "a"));
  EXPECT_TRUE(fs::is_empty(dir.path()));  // the probe file is gone
}

}  // namespace
}  // namespace isospring::io
