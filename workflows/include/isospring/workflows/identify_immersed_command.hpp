#pragma once
// `isospring identify` on an immersed case ({"geometry": {"type": "immersed", ...}} with a
// "measurements" object) as one library call: the part immersed in its background grid, the
// markers checked against the part's cells, fitting::identify_immersed; the result is an
// IdentifyCommandResult, so write_identify_outputs writes the same files as for a body-fitted
// case (report.json, report.md, residuals, markers_*.vtp), without model.json: the spring model
// is not recalibrated against an immersed corrected reference (the report says so; `isospring
// calibrate` calibrates an immersed part's spring model).
//
//   const io::Progress progress("identify", true);
//   const workflows::IdentifyCommandResult r = workflows::run_identify_immersed(
//       io::read_immersed_case("part.json"), {}, progress);
//   workflows::write_identify_outputs("out", r, progress);
#include "isospring/io/immersed_case.hpp"
#include "isospring/workflows/identify_command.hpp"

namespace isospring::workflows {

/// Runs the loop on the immersed case `c`. Throws nurbs::InputError when the case has no
/// "measurements", for a bad "measurements" object or marker file, for markers outside the
/// part's cells unless options.drop_outside, and as fitting::identify_immersed. The
/// discretisation check climbs the case's ladder of background grids (immersed_grid_ladder.hpp);
/// options.max_dofs and discretization_check apply as for a body-fitted case.
IdentifyCommandResult run_identify_immersed(const io::ImmersedCase& c,
                                            const IdentifyCommandOptions& options,
                                            const io::Progress& progress);

}  // namespace isospring::workflows
