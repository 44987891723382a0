#pragma once
// "analysis": {"volumetric": ...} of a case file, body-fitted or immersed: one reader, so both
// kinds accept the same values and refuse a bad one with the same message.
#include "case_file_json.hpp"
#include "isospring/analysis/problem.hpp"

namespace isospring::io::case_json {

/// The "volumetric" key of the "analysis" object `analysis_object`: "displacement" (the default
/// when the key is absent) or "bbar". Any other value fails naming the file, the field, the allowed
/// values and the fix; "bbar" under plane stress fails too (plane stress does not lock).
analysis::Volumetric read_volumetric(const Field& analysis_object,
                                     analysis::Formulation formulation);

}  // namespace isospring::io::case_json
