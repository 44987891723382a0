#pragma once
// The consumer's checks of the fitting module through the installed package: calibrate and
// identify on shipped cases against the installed program's report.json (fitting_checks.cpp).
#include <string>

namespace consumer {

/// Relative difference of `ours` from `reported` printed, and whether it is at most 1e-12.
bool agrees(const std::string& what, double ours, double reported);

/// fitting::calibrate with the case's "calibration" values against `isospring calibrate`.
bool check_calibration(const char* case_file, const char* report_file);

/// fitting::identify on the case's "measurements" against `isospring identify`.
bool check_identification(const char* case_file, const char* report_file);

}  // namespace consumer
