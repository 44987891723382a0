// identify's discretisation check in the reports (report_discretization.hpp).
#include "isospring/io/report_discretization.hpp"

#include <cmath>

namespace isospring::io {

nlohmann::json discretization_json(const fitting::DiscretizationCheck& check, double allowance) {
  nlohmann::json j{{"done", check.done},
                   {"note", check.note},
                   {"noise", check.noise},
                   {"target", check.target},
                   {"chosen_level", check.chosen},
                   {"within_target", check.within_target},
                   {"budget_exhausted", check.budget_exhausted},
                   {"volumetric", check.volumetric},
                   {"volumetric_rule", check.volumetric_rule},
                   {"f_test_allowance", allowance}};
  // A level without an estimate has NaN errors; write_json_report writes them as null.
  j["levels"] = nlohmann::json::array();
  for (const auto& level : check.levels)
    j["levels"].push_back({{"level", level.level},
                           {"discretization", level.description},
                           {"dofs", level.dofs},
                           {"marker_error_rms", level.error_rms},
                           {"marker_error_max", level.error_max},
                           {"marker_error_rms_after_material", level.error_rms_after_material},
                           {"error_over_noise", level.error_rms / check.noise},
                           {"estimate", level.estimate},
                           {"seconds", level.seconds}});
  return j;
}

void add_discretization(MarkdownReport& md, const fitting::DiscretizationCheck& check,
                        double allowance) {
  md.heading(2, "Discretisation");
  if (!check.done) {
    md.paragraph("Not checked: " + check.note + ".");
    return;
  }
  std::string what;
  if (check.within_target)
    what = check.chosen == 0
               ? "The case's own discretisation is accurate enough: its estimated error at the "
                 "markers is below a third of the noise."
               : "The case's discretisation is too coarse for this data; the loop ran on level " +
                     std::to_string(check.chosen) + " (" +
                     check.levels[static_cast<size_t>(check.chosen)].description +
                     "), whose estimated marker error is below the target.";
  else
    what = "Within the DOF budget the reference's marker error stays above the target (" +
           check.note +
           "). The loop ran on the finest level solved and widened every F-test by "
           "the weighted discretisation error (" +
           format_number(allowance, 4) + "), so no effect is added to absorb it.";
  md.paragraph(what + " Noise " + format_number(check.noise, 3) + " m, target " +
               format_number(check.target, 3) +
               " m rms. Volumetric strain: " + check.volumetric_rule + ".");
  std::vector<std::vector<std::string>> rows;
  for (const auto& level : check.levels)
    rows.push_back(
        {std::to_string(level.level) + (level.level == check.chosen ? " (used)" : ""),
         level.description, std::to_string(level.dofs),
         std::isfinite(level.error_rms) ? format_number(level.error_rms, 3) : "-",
         std::isfinite(level.error_rms) ? format_number(level.error_rms / check.noise, 3) : "-",
         std::isfinite(level.error_rms_after_material)
             ? format_number(level.error_rms_after_material, 3)
             : "-",
         level.estimate.empty() ? "-" : level.estimate});
  md.table({"level", "discretisation", "DOFs", "marker error rms [m]", "/ noise",
            "after E refit [m]", "estimate"},
           rows);
}

}  // namespace isospring::io
