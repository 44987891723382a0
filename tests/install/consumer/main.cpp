// A consumer of the installed isospring package (tests/install): reads a patch file, refines it
// exactly, evaluates points on its circular arcs; reads case files, solves, calibrates and
// identifies them (fitting_checks.cpp) and compares with the report.json that the installed
// `isospring analyze`, `calibrate` and `identify` wrote for the same cases.
//
//   consumer PATCH.json CASE.json REPORT.json CALIBRATE_CASE.json CALIBRATE_REPORT.json
//            IDENTIFY_CASE.json IDENTIFY_REPORT.json
//
// Prints what it measured and exits 1 when a check fails: the arcs of the quarter annulus keep
// radii 1 and 2 to 1e-12 after refinement, and every reported number compared agrees with the
// program's to 1e-12 (relative).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <isospring/analysis/static_solver.hpp>
#include <isospring/io/case_file.hpp>
#include <isospring/io/patch_file.hpp>
#include <isospring/nurbs/error.hpp>
#include <isospring/nurbs/refine.hpp>
#include <nlohmann/json.hpp>

#include "fitting_checks.hpp"

namespace {

using isospring::nurbs::Patch;

// Largest | |X(u, v)| - radius | along the side v of the annulus (radius 1 at v = 0, 2 at v = 1).
double radius_error(const Patch& patch, double v, double radius) {
  double worst = 0.0;
  for (int i = 0; i <= 100; ++i) {
    const Eigen::Vector3d x = patch.point({i / 100.0, v, 0.0});
    worst = std::max(worst, std::abs(x.norm() - radius));
  }
  return worst;
}

bool check_patch(const char* file) {
  const std::vector<Patch> patches = isospring::io::read_patch_file(file);
  const Patch fine =
      isospring::nurbs::refine_uniform(isospring::nurbs::elevate_degree(patches.at(0), 1), 4);
  const double inner = radius_error(fine, 0.0, 1.0), outer = radius_error(fine, 1.0, 2.0);
  const Eigen::Vector3d mid = fine.point({0.5, 0.0, 0.0});
  std::printf("refined patch: degrees %d %d, %d control points\n", fine.degree(0), fine.degree(1),
              fine.num_points());
  std::printf("point at (0.5, 0): %.17g %.17g %.17g, radius %.17g\n", mid.x(), mid.y(), mid.z(),
              mid.norm());
  std::printf("radius error: inner %.3g, outer %.3g\n", inner, outer);
  return inner < 1e-12 && outer < 1e-12 && fine.num_points() == 7 * 6;
}

bool check_case(const char* case_file, const char* report_file) {
  const isospring::io::Case c = isospring::io::read_case_file(case_file);
  const isospring::analysis::StaticResult result = isospring::analysis::solve_static(c.problem);
  std::ifstream in(report_file);
  const nlohmann::json report = nlohmann::json::parse(in);
  std::printf("case %s: %d DOFs\n", c.name.c_str(), result.dofs);
  bool ok = report.at("load_cases").size() == result.load_cases.size();
  for (size_t i = 0; i < result.load_cases.size(); ++i) {
    const auto& lc = result.load_cases[i];
    const nlohmann::json& reported = report.at("load_cases").at(i);
    ok = reported.at("id") == lc.id && ok;
    ok = consumer::agrees("max_displacement " + lc.id, lc.max_displacement,
                          reported.at("max_displacement")) &&
         ok;
    ok = consumer::agrees("strain_energy " + lc.id, lc.strain_energy,
                          reported.at("strain_energy")) &&
         ok;
  }
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 8) {
    std::fprintf(stderr,
                 "usage: consumer PATCH.json CASE.json REPORT.json CALIBRATE_CASE.json "
                 "CALIBRATE_REPORT.json IDENTIFY_CASE.json IDENTIFY_REPORT.json\n");
    return 2;
  }
  try {
    bool ok = check_patch(argv[1]);
    ok = check_case(argv[2], argv[3]) && ok;
    ok = consumer::check_calibration(argv[4], argv[5]) && ok;
    ok = consumer::check_identification(argv[6], argv[7]) && ok;
    std::printf("%s\n", ok ? "consumer: all checks passed" : "consumer: FAILED");
    return ok ? 0 : 1;
  } catch (const std::exception& e) {  // InputError, or a report without a field
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  }
}
