// A crash of a third-party reader becomes an input error (crash_guard.hpp).
#include "crash_guard.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <stdexcept>
#include <string>

#include "isospring/nurbs/error.hpp"

namespace isospring::geometry::detail {

void fail_if_it_crashes(const std::filesystem::path& file, const std::function<void()>& work) {
  const pid_t child = ::fork();
  if (child < 0)
    throw std::runtime_error("cannot start a process to read '" + file.string() +
                             "': " + std::strerror(errno));
  if (child == 0) {
    // Whatever handlers the process installed for fatal signals (AddressSanitizer's and
    // libFuzzer's report a SEGV and then exit with a status, a crash reporter may do anything),
    // the child must die *by* the signal for the parent to see the crash.
    for (const int fatal : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGTRAP, SIGSYS})
      std::signal(fatal, SIG_DFL);
    int status = 0;
    try {
      work();
    } catch (...) {
      status = 1;  // the parent repeats the work and reports the exception itself
    }
    ::_exit(status);
  }
  int status = 0;
  while (::waitpid(child, &status, 0) < 0)
    if (errno != EINTR)
      throw std::runtime_error("cannot wait for the process reading '" + file.string() +
                               "': " + std::strerror(errno));
  if (WIFSIGNALED(status))
    throw nurbs::InputError(
        file.string() + ": OpenCascade crashed reading this file (" +
        ::strsignal(WTERMSIG(status)) +
        "): it is corrupted or not valid STEP/IGES; export it again from the CAD "
        "program");
}

}  // namespace isospring::geometry::detail
