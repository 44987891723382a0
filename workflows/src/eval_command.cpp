// run_eval and its outputs (see eval_command.hpp).
#include "isospring/workflows/eval_command.hpp"

#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "isospring/io/number_list.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;
namespace {

nurbs::Param parse_param(const std::string& text, const nurbs::Patch& patch) {
  const std::vector<double> values = parse_number_list(text, "--at");
  if (static_cast<int>(values.size()) != patch.param_dim())
    throw nurbs::InputError("--at " + text + ": the patch has parametric dimension " +
                            std::to_string(patch.param_dim()) + ", so give " +
                            std::to_string(patch.param_dim()) + " comma-separated parameters");
  nurbs::Param u{0, 0, 0};
  for (int d = 0; d < patch.param_dim(); ++d) {
    u[d] = values[static_cast<size_t>(d)];
    if (u[d] < patch.param_min(d) || u[d] > patch.param_max(d))
      throw nurbs::InputError("--at " + text + ": parameter " + std::to_string(u[d]) +
                              " lies outside [" + std::to_string(patch.param_min(d)) + ", " +
                              std::to_string(patch.param_max(d)) + "] in direction " +
                              std::to_string(d));
  }
  return u;
}

}  // namespace

EvalCommandResult run_eval(const std::vector<nurbs::Patch>& patches,
                           const EvalCommandOptions& options) {
  if (options.patch < 0 || options.patch >= static_cast<int>(patches.size()))
    throw nurbs::InputError("--patch " + std::to_string(options.patch) + ": the file has " +
                            std::to_string(patches.size()) + " patches (0-based index)");
  const nurbs::Patch& patch = patches[static_cast<size_t>(options.patch)];
  EvalCommandResult r;
  r.patch = options.patch;
  for (const std::string& text : options.at) {
    const nurbs::Param u = parse_param(text, patch);
    const nurbs::PatchDerivatives der = patch.derivatives(u, 1);
    // Control points or weights near the limits of a double (e.g. 1e308) overflow in the
    // rational sums; a failure beats printing inf or -nan as if it were a point.
    const bool finite = der.point.allFinite() &&
                        (!options.derivatives || der.first.leftCols(patch.param_dim()).allFinite());
    if (!finite)
      throw std::runtime_error(options.input + ": patch " + std::to_string(options.patch) + " at " +
                               text +
                               ": the point or its derivatives overflow a double (not finite); "
                               "check the control points and weights of the patch");
    EvalPoint p;
    p.text = text;
    p.at.assign(u.begin(), u.begin() + patch.param_dim());
    p.point = der.point;
    if (options.derivatives)
      for (int d = 0; d < patch.param_dim(); ++d) p.derivatives.push_back(der.first.col(d));
    r.points.push_back(std::move(p));
  }
  return r;
}

std::string eval_text(const EvalCommandResult& r) {
  std::ostringstream out;
  out << std::setprecision(17);
  for (const EvalPoint& p : r.points) {
    out << p.text << ": " << p.point.x() << " " << p.point.y() << " " << p.point.z();
    for (size_t d = 0; d < p.derivatives.size(); ++d)
      out << " | d"
          << "uvw"[d] << ": " << p.derivatives[d].x() << " " << p.derivatives[d].y() << " "
          << p.derivatives[d].z();
    out << "\n";
  }
  return out.str();
}

nlohmann::json eval_json(const EvalCommandResult& r) {
  nlohmann::json points = nlohmann::json::array();
  for (const EvalPoint& p : r.points) {
    nlohmann::json entry = {{"at", p.at}, {"point", {p.point.x(), p.point.y(), p.point.z()}}};
    for (const Eigen::Vector3d& d : p.derivatives)
      entry["derivatives"].push_back({d.x(), d.y(), d.z()});
    points.push_back(entry);
  }
  return {{"patch", r.patch}, {"points", points}};
}

}  // namespace isospring::workflows
