#include "isospring/io/report_case.hpp"

#include <cassert>
#include <ostream>

#include "isospring/io/atomic_file.hpp"

namespace isospring::io {

std::string formulation_name(analysis::Formulation formulation) {
  switch (formulation) {
    case analysis::Formulation::kPlaneStress:
      return "plane_stress";
    case analysis::Formulation::kPlaneStrain:
      return "plane_strain";
    case analysis::Formulation::kSolid:
      return "solid";
  }
  return "unknown";
}

nlohmann::json case_summary(const Case& c, const analysis::Problem& problem) {
  nlohmann::json s;
  s["name"] = c.name;
  s["file"] = c.file.string();
  s["dimension"] = c.dimension;
  s["formulation"] = formulation_name(problem.formulation);
  s["volumetric"] = problem.volumetric == analysis::Volumetric::kBbar ? "bbar" : "displacement";
  s["material"] = {{"E", problem.material.youngs_modulus},
                   {"nu", problem.material.poisson_ratio},
                   {"density", problem.material.density}};
  if (c.dimension == 2) s["material"]["thickness"] = problem.material.thickness;
  int control_points = 0, elements = 0;
  nlohmann::json patches = nlohmann::json::array();
  for (const nurbs::Patch& patch : problem.patches) {
    nlohmann::json p;
    for (int d = 0; d < patch.param_dim(); ++d) {
      p["degree"].push_back(patch.degree(d));
      p["elements"].push_back(patch.knots(d).num_elements());
      p["control_points"].push_back(patch.num_points(d));
    }
    patches.push_back(p);
    control_points += patch.num_points();
    elements += patch.num_elements();
  }
  s["patches"] = patches;
  s["control_points"] = control_points;
  s["elements"] = elements;
  s["supports"] = problem.supports.size();
  for (const analysis::LoadCase& lc : problem.load_cases) s["load_cases"].push_back(lc.id);
  if (c.analytic) s["analytic"] = c.analytic->type;
  return s;
}

void add_case_summary(MarkdownReport& report, const nlohmann::json& s) {
  std::string degrees, elements;
  const auto& patch = s["patches"][0];
  for (size_t d = 0; d < patch["degree"].size(); ++d) {
    degrees += (d ? " x " : "") + patch["degree"][d].dump();
    elements += (d ? " x " : "") + patch["elements"][d].dump();
  }
  std::vector<std::string> items{
      "case: " + s["name"].get<std::string>() + " (`" + s["file"].get<std::string>() + "`)",
      "analysis: " + s["formulation"].get<std::string>() + ", " + s["dimension"].dump() + "D" +
          (s.value("volumetric", "") == "bbar" ? ", B-bar volumetric strain" : ""),
      "material: E = " + format_number(s["material"]["E"].get<double>()) +
          " Pa, nu = " + format_number(s["material"]["nu"].get<double>()) +
          ", density = " + format_number(s["material"]["density"].get<double>()) + " kg/m^3",
      "discretisation: " + std::to_string(s["patches"].size()) + " patch(es), degree " + degrees +
          ", elements " + elements + " (patch 0); " + s["elements"].dump() + " elements, " +
          s["control_points"].dump() + " control points in total"};
  if (s.contains("material") && s["material"].contains("thickness"))
    items.push_back("thickness: " + format_number(s["material"]["thickness"].get<double>()) + " m");
  if (s.contains("analytic"))
    items.push_back("analytic solution: " + s["analytic"].get<std::string>());
  report.bullets(items);
}

void write_control_displacements_csv(
    const std::filesystem::path& path, const std::vector<nurbs::Patch>& patches,
    const std::vector<std::vector<Eigen::Vector3d>>& control_displacements) {
  assert(patches.size() == control_displacements.size());
  write_file_atomically(path, [&](std::ostream& out) {
    out << "i,x,y,z,ux,uy,uz\n";
    int i = 0;
    for (size_t p = 0; p < patches.size(); ++p) {
      for (int k = 0; k < patches[p].num_points(); ++k, ++i) {
        const Eigen::Vector3d& x = patches[p].control_point(k);
        const Eigen::Vector3d& u = control_displacements[p][static_cast<size_t>(k)];
        out << i;
        for (int c = 0; c < 3; ++c) out << ',' << format_exact(x[c]);
        for (int c = 0; c < 3; ++c) out << ',' << format_exact(u[c]);
        out << '\n';
      }
    }
  });
}

}  // namespace isospring::io
