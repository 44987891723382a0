// The crash guard (geometry/src/crash_guard.hpp) turns a crash of the work in its child process
// into an InputError naming the file, also when the process has its own handler for fatal
// signals (AddressSanitizer and libFuzzer install one that reports and then *exits*, which the
// guard used to take for an exception and repeat the crashing work in the process itself).
#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "../../geometry/src/crash_guard.hpp"
#include "isospring/nurbs/error.hpp"

namespace {

using isospring::geometry::detail::fail_if_it_crashes;

extern "C" void exit_quietly(int) {
  std::_Exit(1);
}

// Restores the previous handler of a signal at the end of a test.
class HandlerFor {
 public:
  HandlerFor(int signal, void (*handler)(int)) : signal_(signal) {
    previous_ = std::signal(signal, handler);
  }
  ~HandlerFor() { std::signal(signal_, previous_); }
  HandlerFor(const HandlerFor&) = delete;
  HandlerFor& operator=(const HandlerFor&) = delete;

 private:
  int signal_;
  void (*previous_)(int);
};

void expect_crash_reported(int signal) {
  try {
    fail_if_it_crashes("part.step", [signal] { std::raise(signal); });
    FAIL() << "a child killed by signal " << signal << " was not reported";
  } catch (const isospring::nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("part.step: OpenCascade crashed"), std::string::npos)
        << e.what();
  }
}

TEST(CrashGuard, WorkThatReturnsOrThrowsIsRepeatedByTheCaller) {
  EXPECT_NO_THROW(fail_if_it_crashes("part.step", [] {}));
  EXPECT_NO_THROW(fail_if_it_crashes("part.step", [] { throw std::runtime_error("bad"); }));
}

TEST(CrashGuard, ACrashIsAnInputErrorNamingTheFile) {
  expect_crash_reported(SIGSEGV);
  expect_crash_reported(SIGABRT);
}

TEST(CrashGuard, ACrashIsReportedEvenWhenTheProcessHandlesFatalSignalsByExiting) {
  const HandlerFor segv(SIGSEGV, exit_quietly), bus(SIGBUS, exit_quietly),
      abrt(SIGABRT, exit_quietly), fpe(SIGFPE, exit_quietly);
  expect_crash_reported(SIGSEGV);
  expect_crash_reported(SIGBUS);
  expect_crash_reported(SIGABRT);
  expect_crash_reported(SIGFPE);
}

}  // namespace
