// The "volumetric" key of a case file's "analysis" object (case_volumetric.hpp).
#include "case_volumetric.hpp"

#include <string>

namespace isospring::io::case_json {

analysis::Volumetric read_volumetric(const Field& analysis_object,
                                     analysis::Formulation formulation) {
  if (!analysis_object.has("volumetric")) return analysis::Volumetric::kDisplacement;
  const Field volumetric = analysis_object.at("volumetric");
  const std::string name = volumetric.string();
  if (name == "displacement") return analysis::Volumetric::kDisplacement;
  if (name != "bbar") {
    const std::string suggestion = closest_word(name, {"displacement", "bbar"});
    volumetric.fail(": unknown volumetric treatment '" + name + "'" +
                    (suggestion.empty() ? "." : "; did you mean '" + suggestion + "'?") +
                    " Allowed: \"displacement\" (the default: the displacement field's strain) "
                    "or \"bbar\" (mean dilatation, locking-free for nu near 0.5); set one of "
                    "them or leave \"volumetric\" out");
  }
  if (formulation == analysis::Formulation::kPlaneStress)
    volumetric.fail(
        ": \"bbar\" needs plane_strain or solid; plane stress does not lock, use "
        "\"displacement\"");
  return analysis::Volumetric::kBbar;
}

}  // namespace isospring::io::case_json
