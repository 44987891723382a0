#pragma once
// `isospring study` on an immersed case ({"geometry": {"type": "immersed", ...}}): the same
// refinement study as the body-fitted one (study_command.hpp), on the background grid. Level l
// has the case's cells x 2^l per direction (the case's grid, or the one immerse_solid chose, is
// level 0) in the same box, so the cell size halves from level to level; each degree of
// `degrees` is a background grid of that degree (k-refinement). Every level immerses the part
// again on its exact B-rep and solves the load case. Errors are against the case's "analytic"
// solution (relative L2 and energy norms over the part, analysis::immersed_error_norms) when it
// names one; the followed quantity is the strain energy or the largest displacement of the
// active control points, Richardson-extrapolated as in the body-fitted study. The report,
// study.csv and convergence.png are the body-fitted study's (write_study_outputs), with the
// case summary saying the path is immersed.
#include "isospring/io/immersed_case.hpp"
#include "isospring/workflows/study_command.hpp"

namespace isospring::workflows {

/// Solves every level of every degree. Throws nurbs::InputError naming the option for bad
/// options (--quantity displacement, which takes a patch point, has no immersed meaning) and
/// when the finest level's estimated solve would not fit options.limits.
StudyCommandResult run_study_immersed(const io::ImmersedCase& c, const StudyCommandOptions& options,
                                      const io::Progress& progress);

}  // namespace isospring::workflows
