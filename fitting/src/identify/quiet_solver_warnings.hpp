#pragma once
// QuietSolverWarnings: Ceres' warnings about trial steps hidden while a fit of the fitting module
// runs (the identification and its spring recalibration). Private to the module.
#include <glog/logging.h>

namespace isospring::fitting {

// Ceres logs a trial step whose parameters leave the physical range ("Step failed to evaluate")
// as a glog warning on stderr; the fit handles that step (it shortens the step), so the warning
// is noise for the user: hidden while a fit runs, the caller's level restored.
class QuietSolverWarnings {
 public:
  // Writes the flag only when it changes it: identify() holds one for the whole run, so the fits
  // of the hold-out folds, which run on several threads, only read it.
  QuietSolverWarnings() : previous_(FLAGS_minloglevel) {
    if (FLAGS_minloglevel < google::GLOG_ERROR) FLAGS_minloglevel = google::GLOG_ERROR;
  }
  ~QuietSolverWarnings() {
    if (FLAGS_minloglevel != previous_) FLAGS_minloglevel = previous_;
  }
  QuietSolverWarnings(const QuietSolverWarnings&) = delete;
  QuietSolverWarnings& operator=(const QuietSolverWarnings&) = delete;

 private:
  int previous_;
};

}  // namespace isospring::fitting
