#pragma once
// identify's discretisation check in report.json ("discretization") and report.md: the levels
// tried, their DOFs, the estimated marker error, the noise and what the loop did with them.
#include <nlohmann/json.hpp>

#include "isospring/fitting/discretization_check.hpp"
#include "isospring/io/report.hpp"

namespace isospring::io {

/// `allowance`: IdentifyResult::discretization_allowance (the widening of the F-tests).
nlohmann::json discretization_json(const fitting::DiscretizationCheck& check, double allowance);

void add_discretization(MarkdownReport& md, const fitting::DiscretizationCheck& check,
                        double allowance);

}  // namespace isospring::io
