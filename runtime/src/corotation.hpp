#pragma once
// The corotated reduced model in the runtime (docs/reduced_model.md, "Large rotation"): the
// network's rest stiffness and damping blocks applied in each particle's shape-matched frame,
// projected on the basis. The same arithmetic as analysis::CorotatedForces and
// analysis::CorotatedReducedModel. Private to the runtime.
#include <nlohmann/json.hpp>

#include "model.hpp"

namespace isospring::runtime {

class JsonFields;

/// Reads the document's "corotation" object into the model (after the basis).
void read_corotation(const nlohmann::json& corotation, const JsonFields& fields, Model& model);

/// g_el = Phi^T f_corot(X + Phi q, Phi qdot) (qdot may be NULL) into g (basis size); returns
/// the corotated energy 1/2 sum_i l_i . sum_j K_ij l_j (l: displacements in particle i's frame).
/// With `dq` given instead of q's rest offsets: the force's derivative along (dq, dqdot) at the
/// rotations of q. Uses the model's scratch.
double corotated_reduced_force(const Model& model, const double* q, const double* qdot, double* g);
void corotated_reduced_jvp(const Model& model, const double* q, const double* dq,
                           const double* dqdot, double* dg);

}  // namespace isospring::runtime
