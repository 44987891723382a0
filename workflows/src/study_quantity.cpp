// Parsing and evaluation of the scalar followed by `study` (see
// isospring/workflows/study_quantity.hpp).
#include "isospring/workflows/study_quantity.hpp"

#include <cmath>

#include "isospring/analysis/dof_map.hpp"
#include "isospring/io/number_list.hpp"
#include "isospring/io/report.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;

namespace {

using nurbs::InputError;

// "PATCH:U,V[,W]" -> patch index and parameters, checked against the case's patches.
void parse_point(const std::string& text, const Case& c, StudyQuantity& q) {
  const std::string fix = " (give --point PATCH:U,V[,W], e.g. --point 0:1,0.5)";
  const size_t colon = text.find(':');
  if (colon == std::string::npos || colon == 0)
    throw InputError("--point '" + text + "': no patch index before ':'" + fix);
  const std::vector<double> patch = parse_number_list(text.substr(0, colon), "--point patch");
  const int patches = static_cast<int>(c.problem.patches.size());
  if (patch.size() != 1 || patch[0] != std::floor(patch[0]) || patch[0] < 0 || patch[0] >= patches)
    throw InputError("--point '" + text + "': the patch index must be an integer 0.." +
                     std::to_string(patches - 1) + fix);
  q.patch = static_cast<int>(patch[0]);
  const nurbs::Patch& p = c.problem.patches[static_cast<size_t>(q.patch)];
  const std::vector<double> u = parse_number_list(text.substr(colon + 1), "--point parameters");
  if (static_cast<int>(u.size()) != p.param_dim())
    throw InputError("--point '" + text + "': patch " + std::to_string(q.patch) + " has " +
                     std::to_string(p.param_dim()) + " parameters, got " +
                     std::to_string(u.size()) + fix);
  for (int d = 0; d < p.param_dim(); ++d) {
    const double value = u[static_cast<size_t>(d)];
    if (!(value >= p.param_min(d) && value <= p.param_max(d)))
      throw InputError("--point '" + text + "': parameter " + std::to_string(d) + " = " +
                       format_number(value) + " is outside [" + format_number(p.param_min(d)) +
                       ", " + format_number(p.param_max(d)) + "]");
    q.param[static_cast<size_t>(d)] = value;
  }
}

}  // namespace

StudyQuantity parse_study_quantity(const std::string& quantity, const std::string& point,
                                   const std::string& component, const Case& c) {
  StudyQuantity q;
  if (quantity == "max_displacement") {
    q.kind = StudyQuantity::Kind::kMaxDisplacement;
    q.label = "max |u| over the control points";
  } else if (quantity == "strain_energy") {
    q.kind = StudyQuantity::Kind::kStrainEnergy;
    q.label = "strain energy";
  } else if (quantity == "displacement") {
    q.kind = StudyQuantity::Kind::kDisplacement;
  } else {
    throw InputError("--quantity '" + quantity +
                     "': use strain_energy, max_displacement or displacement");
  }
  if (q.kind != StudyQuantity::Kind::kDisplacement) {
    if (!point.empty() || !component.empty())
      throw InputError("--point and --component apply to --quantity displacement only");
    return q;
  }
  if (point.empty())
    throw InputError("--quantity displacement needs --point PATCH:U,V[,W] (e.g. --point 0:1,0.5)");
  parse_point(point, c, q);
  const int dim = analysis::spatial_dimension(c.problem.formulation);
  const std::string name = component.empty() ? "magnitude" : component;
  if (name == "magnitude") {
    q.component = -1;
  } else if (name.size() == 1 && name[0] >= 'x' && name[0] <= 'z' && name[0] - 'x' < dim) {
    q.component = name[0] - 'x';
  } else {
    throw InputError("--component '" + name + "': use " + (dim == 2 ? "x, y" : "x, y, z") +
                     " or magnitude");
  }
  std::string params;
  for (int d = 0; d < c.problem.patches[static_cast<size_t>(q.patch)].param_dim(); ++d)
    params += (d ? ", " : "") + format_number(q.param[static_cast<size_t>(d)]);
  q.label = (q.component < 0 ? std::string("|u|") : "u_" + name) + " at patch " +
            std::to_string(q.patch) + " parameters (" + params + ")";
  return q;
}

double StudyQuantity::evaluate(const analysis::Problem& problem,
                               const analysis::LoadCaseResult& result) const {
  switch (kind) {
    case Kind::kMaxDisplacement:
      return result.max_displacement;
    case Kind::kStrainEnergy:
      return result.strain_energy;
    case Kind::kDisplacement: {
      const Eigen::Vector3d u =
          analysis::evaluate_field(problem, result.control_displacements, patch, param)
              .displacement;
      return component < 0 ? u.norm() : u[component];
    }
  }
  return NAN;
}

std::optional<double> StudyQuantity::exact(const Case& c) const {
  if (kind != Kind::kDisplacement || !c.analytic) return std::nullopt;
  const Eigen::Vector3d x = c.problem.patches[static_cast<size_t>(patch)].point(param);
  const Eigen::Vector3d u = c.analytic->displacement(x);
  return component < 0 ? u.norm() : u[component];
}

}  // namespace isospring::workflows
