#pragma once
// The use case behind `isospring eval IN --at u[,v[,w]] ... [--derivs] [--json]`: physical
// points (and first derivatives) of a patch at given parameters, as lines for people or as JSON
// with full precision.
#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::workflows {

struct EvalCommandOptions {
  std::string input;            // names the patch file in messages
  std::vector<std::string> at;  // "u[,v[,w]]" per point, as given
  int patch = 0;                // 0-based index into the file's patches
  bool derivatives = false;     // also dX/du, dX/dv, dX/dw
};

struct EvalPoint {
  std::string text;        // the --at value as given
  std::vector<double> at;  // its parameters (the patch's parametric dimension)
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> derivatives;  // per parametric direction; empty without them
};

struct EvalCommandResult {
  int patch = 0;
  std::vector<EvalPoint> points;
};

/// Evaluates patches[options.patch] at every options.at. Throws nurbs::InputError for a patch
/// index outside the file, a parameter count that is not the patch's parametric dimension or a
/// parameter outside its range; std::runtime_error when a point (or a requested derivative)
/// overflows a double.
EvalCommandResult run_eval(const std::vector<nurbs::Patch>& patches,
                           const EvalCommandOptions& options);

/// One line per point, "u,v: x y z | du: ... | dv: ...", 17 significant digits.
std::string eval_text(const EvalCommandResult& r);

/// {"patch": i, "points": [{"at": [...], "point": [x, y, z], "derivatives": [[...], ...]}]}
/// ("derivatives" only when evaluated).
nlohmann::json eval_json(const EvalCommandResult& r);

}  // namespace isospring::workflows
