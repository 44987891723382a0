// Generator of the unseen-data suite of `isospring identify`, run by
// scripts/identify_suite.sh:
//
//   generate_identify_suite generate OUT_DIR [DATASET...]
//                                              writes OUT_DIR/<dataset>/{case.json, markers.csv,
//                                              truth.json} with CalculiX (ccx) on PATH
//   generate_identify_suite table DATA_DIR ISOSPRING [WORK_DIR]
//                                              runs `isospring identify` on every dataset and
//                                              prints the per-dataset table and the confusion
//                                              matrix (Markdown) the README quotes
//
// Each dataset's markers are ccx's displacements of the TRUE problem (identify_suite_datasets.hpp)
// plus measuring-frame motion and Gaussian noise. Markers are nodes of the truth mesh; their
// displacements come from the same problem on a mesh refined twice in every direction (which has
// a node at every node of the truth mesh). Mesh convergence is measured, not assumed: the change
// between the two meshes at the markers is stored in truth.json beside the noise.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <random>
#include <set>

#include "calculix_dataset.hpp"
#include "identify_suite_datasets.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/nurbs/refine.hpp"

namespace fs = std::filesystem;
using nlohmann::json;
using namespace isospring;
using namespace isospring::identify_suite;

namespace {

json truth_case(const Dataset& d, const Specimen& s, int refinement) {
  json truth = s.declared;
  truth["name"] = d.name + "_truth";
  truth["material"]["E"] = s.true_modulus;
  json elements = json::array();
  for (int n : s.truth_elements) elements.push_back(n * refinement);
  truth["discretization"]["elements"] = elements;
  if (d.hidden.gravity)
    for (auto& lc : truth["load_cases"])
      lc["gravity"] = {s.gravity.x(), s.gravity.y(), s.gravity.z()};
  if (d.hidden.load_scale != 1.0)
    for (auto& t : truth["load_cases"][1]["tractions"])
      for (auto& v : t["value"]) v = v.get<double>() * d.hidden.load_scale;
  return truth;
}

// A position as text precise to well below the mesh's round-off, for matching nodes of
// different meshes.
std::string node_key(const Eigen::Vector3d& x) {
  // Snapped to zero below 1e-12 m: the same node may be computed as 0 and as -1e-20.
  const Eigen::Vector3d y = x.unaryExpr([](double v) { return std::abs(v) < 1e-12 ? 0.0 : v; });
  char buffer[100];
  std::snprintf(buffer, sizeof(buffer), "%.9e %.9e %.9e", y.x(), y.y(), y.z());
  return buffer;
}

// Knots that split the `count` spans at the start (at_end: the end) of a direction into `splits`.
std::vector<double> split_end_spans(const nurbs::KnotVector& knots, int count, int splits,
                                    bool at_end) {
  const std::vector<double> u = knots.unique();
  const int spans = static_cast<int>(u.size()) - 1;
  std::vector<double> out;
  for (int i = 0; i < std::min(count, spans); ++i) {
    const int span = at_end ? spans - 1 - i : i;
    for (int k = 1; k < splits; ++k) out.push_back(u[span] + (u[span + 1] - u[span]) * k / splits);
  }
  return out;
}

// The graded truth mesh (Grading): the clamp's spans along the specimen's axis (its patches run
// along it in the same parametric direction, the clamp at its start) and the outermost spans of
// the other directions split.
nurbs::Patch graded(const nurbs::Patch& patch, const Grading& g, int axis) {
  nurbs::Patch out = patch;
  if (g.clamp_spans > 0 && g.clamp_splits > 1)
    out = nurbs::refine_knots(
        out, axis, split_end_spans(out.knots(axis), g.clamp_spans, g.clamp_splits, false));
  for (int d = 0; d < out.param_dim() && g.lateral_splits > 1; ++d) {
    if (d == axis) continue;
    std::vector<double> knots = split_end_spans(out.knots(d), 1, g.lateral_splits, false);
    const std::vector<double> end = split_end_spans(out.knots(d), 1, g.lateral_splits, true);
    knots.insert(knots.end(), end.begin(), end.end());
    out = nurbs::refine_knots(out, d, knots);
  }
  return out;
}

// The markers' positions: nodes of the uniform truth mesh on the observed faces, every
// stride-th, in the order of its nodes (a graded mesh keeps each of them as a node).
std::vector<Eigen::Vector3d> marker_positions(const Dataset& d, const Specimen& s,
                                              const fs::path& folder) {
  const io::Case truth = io::build_case_from_json(truth_case(d, s, 1), folder / "t.json");
  std::vector<Eigen::Vector3d> out;
  int seen = 0;
  for (const Eigen::Vector3d& x : io::make_calculix_deck(truth.problem).nodes)
    if (s.is_marker(x) && seen++ % s.stride == 0) out.push_back(x);
  return out;
}

// The spec ccx solves: true problem at `refinement` x the truth mesh (graded as the dataset asks,
// then every span split), the hidden material; the markers' nodes only, or every node.
testing::CalculixDatasetSpec truth_spec(const Dataset& d, const Specimen& s, int refinement,
                                        const fs::path& folder, bool markers_only) {
  const bool uniform = d.grading.empty();
  io::Case truth =
      io::build_case_from_json(truth_case(d, s, uniform ? refinement : 1), folder / "t.json");
  if (!uniform)
    for (auto& patch : truth.problem.patches)
      patch = nurbs::refine_uniform(graded(patch, d.grading, s.gradient_axis), refinement);
  testing::CalculixDatasetSpec spec;
  spec.truth = truth.problem;
  spec.nonlinear = d.hidden.nonlinear;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& p : truth.problem.patches) {
    const auto [plo, phi] = p.control_bounds();
    lo = lo.cwiseMin(plo);
    hi = hi.cwiseMax(phi);
  }
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  const int axis = s.gradient_axis;
  const double E = s.true_modulus, length = hi[axis] - lo[axis];
  if (d.hidden.gradient != 0.0) {
    const double a = d.hidden.gradient;
    spec.youngs_modulus_at = [=](const Eigen::Vector3d& x) {
      return E * (1.0 + a * (x[axis] - centre[axis]) / length);
    };
  } else if (d.hidden.soft_layer > 0.0) {
    const double factor = d.hidden.soft_layer, slab = s.slab, start = lo[axis];
    spec.youngs_modulus_at = [=](const Eigen::Vector3d& x) {
      return x[axis] - start < slab ? factor * E : E;
    };
  }
  if (markers_only && uniform) {
    spec.is_marker = s.is_marker;
    spec.stride = s.stride;
  } else if (markers_only) {
    std::set<std::string> keys;
    for (const auto& x : marker_positions(d, s, folder)) keys.insert(node_key(x));
    spec.is_marker = [keys](const Eigen::Vector3d& x) { return keys.count(node_key(x)) > 0; };
  } else {
    spec.is_marker = [](const Eigen::Vector3d&) { return true; };
  }
  return spec;
}

// A graded mesh's markers in the uniform truth mesh's order (load case by load case), the order
// the noise is drawn in, so that the same seed puts the same noise on the same marker; checked
// complete.
std::vector<fitting::Marker> in_uniform_order(std::vector<fitting::Marker> markers,
                                              const std::vector<Eigen::Vector3d>& positions) {
  std::map<std::string, size_t> index, load_case_rank;
  for (size_t i = 0; i < positions.size(); ++i) index[node_key(positions[i])] = i;
  for (const auto& m : markers) load_case_rank.emplace(m.load_case, load_case_rank.size());
  if (markers.size() != positions.size() * load_case_rank.size())
    throw std::runtime_error("the graded mesh has " + std::to_string(markers.size()) + " of the " +
                             std::to_string(positions.size() * load_case_rank.size()) +
                             " markers of the uniform mesh");
  std::stable_sort(markers.begin(), markers.end(), [&](const auto& a, const auto& b) {
    return std::pair(load_case_rank[a.load_case], index.at(node_key(a.position))) <
           std::pair(load_case_rank[b.load_case], index.at(node_key(b.position)));
  });
  return markers;
}

void write_markers(const fs::path& path, const std::vector<fitting::Marker>& markers, int dim) {
  std::ofstream out(path);
  out.precision(17);
  out << (dim == 3 ? "load_case,x,y,z,ux,uy,uz\n" : "load_case,x,y,ux,uy\n");
  for (const auto& m : markers) {
    out << m.load_case;
    for (int c = 0; c < dim; ++c) out << ',' << m.position[c];
    for (int c = 0; c < dim; ++c) out << ',' << m.displacement[c];
    out << '\n';
  }
}

// The markers (positions chosen on the truth mesh) with the displacements of the twice refined
// mesh, which has a node at every node of the truth mesh; `change` receives the largest over load
// cases of the RMS (per component) change between the two meshes at the markers.
std::vector<fitting::Marker> refined_markers(const std::vector<fitting::Marker>& markers,
                                             const std::vector<fitting::Marker>& fine, int dim,
                                             double* change) {
  auto key = [](const std::string& lc, const Eigen::Vector3d& x) { return lc + " " + node_key(x); };
  std::map<std::string, Eigen::Vector3d> fine_at;
  for (const auto& m : fine) fine_at[key(m.load_case, m.position)] = m.displacement;
  std::map<std::string, std::pair<double, int>> sums;
  std::vector<fitting::Marker> out = markers;
  for (auto& m : out) {
    const auto it = fine_at.find(key(m.load_case, m.position));
    if (it == fine_at.end())
      throw std::runtime_error("marker at " + key(m.load_case, m.position) +
                               " is not a node of the refined mesh");
    auto& [sum, count] = sums[m.load_case];
    sum += (it->second - m.displacement).head(dim).squaredNorm();
    count += dim;
    m.displacement = it->second;
  }
  *change = 0.0;
  for (const auto& [lc, s] : sums) *change = std::max(*change, std::sqrt(s.first / s.second));
  return out;
}

// Measuring-frame motion (translation, small rotation about `centre`), then Gaussian noise of
// sigma = noise_fraction x the largest displacement component.
double add_frame_and_noise(std::vector<fitting::Marker>& markers, const Dataset& d,
                           const Eigen::Vector3d& centre, int dim) {
  double largest = 0.0;
  for (auto& m : markers) {
    m.displacement +=
        d.hidden.frame_translation + d.hidden.frame_rotation.cross(m.position - centre);
    largest = std::max(largest, m.displacement.head(dim).cwiseAbs().maxCoeff());
  }
  const double sigma = d.noise_fraction * largest;
  std::mt19937 rng(d.seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (auto& m : markers)
    for (int c = 0; c < dim; ++c) m.displacement[c] += sigma * noise(rng);
  return sigma;
}

// The centre of the true body's control-point box: the frame rotation's centre.
Eigen::Vector3d centre_of(const Specimen& s, const Dataset& d) {
  const io::Case truth = io::build_case_from_json(truth_case(d, s, 1), "truth.json");
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& p : truth.problem.patches) {
    const auto [plo, phi] = p.control_bounds();
    lo = lo.cwiseMin(plo);
    hi = hi.cwiseMax(phi);
  }
  return 0.5 * (lo + hi);
}

int generate(const fs::path& out, const std::set<std::string>& only) {
  if (!testing::calculix_available()) {
    std::cerr << "ccx (CalculiX, Debian package calculix-ccx) is not on PATH\n";
    return 2;
  }
  for (const Dataset& d : datasets()) {
    if (!only.empty() && !only.count(d.name)) continue;
    const auto start = std::chrono::steady_clock::now();
    const Specimen s = specimen(d);
    const fs::path folder = out / d.name, work = fs::temp_directory_path() / ("isg-" + d.name);
    fs::create_directories(folder);
    fs::remove_all(work);
    fs::create_directories(work);
    const testing::CalculixDatasetSpec base_spec = truth_spec(d, s, 1, work, true);
    const testing::CalculixDataset base = testing::make_calculix_dataset(base_spec, work / "base");
    const testing::CalculixDataset fine =
        testing::make_calculix_dataset(truth_spec(d, s, 2, work, false), work / "fine");
    for (const auto* set : {&base, &fine})
      if (!set->error.empty()) {
        std::cerr << d.name << ": " << set->error << "\n";
        return 1;
      }
    const int dim = s.declared.contains("analysis") ? 2 : 3;
    double change = 0.0;
    std::vector<fitting::Marker> markers = refined_markers(
        d.grading.empty() ? base.markers
                          : in_uniform_order(base.markers, marker_positions(d, s, work)),
        fine.markers, dim, &change);
    const double max_displacement = [&] {
      double largest = 0.0;
      for (const auto& m : markers)
        largest = std::max(largest, m.displacement.head(dim).cwiseAbs().maxCoeff());
      return largest;
    }();
    const double sigma = add_frame_and_noise(markers, d, centre_of(s, d), dim);
    write_markers(folder / "markers.csv", markers, dim);

    json declared = s.declared;
    declared["name"] = d.name;
    declared["description"] =
        "Unseen-data suite of isospring identify, generated by "
        "scripts/identify_suite.sh with CalculiX: " +
        d.note +
        ". The truth (truth.json) is not declared here: the modulus is off and the "
        "discretisation modest on purpose.";
    declared["measurements"] = {{"file", "markers.csv"}, {"effects", candidate_effects()}};
    std::ofstream(folder / "case.json") << declared.dump(2) << "\n";

    json hidden = {
        {"gravity", d.hidden.gravity ? json::array({s.gravity.x(), s.gravity.y(), s.gravity.z()})
                                     : json(nullptr)},
        {"soft_layer_modulus_factor", d.hidden.soft_layer},
        {"soft_layer_thickness", d.hidden.soft_layer > 0 ? s.slab : 0.0},
        {"modulus_gradient_per_length", d.hidden.gradient},
        {"gradient_axis", std::string(1, "xyz"[s.gradient_axis])},
        {"second_load_case_scale", d.hidden.load_scale},
        {"large_deformation", d.hidden.nonlinear},
        {"frame_translation",
         {d.hidden.frame_translation.x(), d.hidden.frame_translation.y(),
          d.hidden.frame_translation.z()}},
        {"frame_rotation",
         {d.hidden.frame_rotation.x(), d.hidden.frame_rotation.y(), d.hidden.frame_rotation.z()}}};
    json elements = s.truth_elements, finer = json::array();
    if (!d.grading.empty()) {  // one patch: its spans per direction
      elements = json::array();
      const nurbs::Patch& patch = base_spec.truth.patches.front();
      for (int dir = 0; dir < patch.param_dim(); ++dir)
        elements.push_back(patch.knots(dir).num_elements());
    }
    for (int n : elements) finer.push_back(2 * n);
    json truth = {{"dataset", d.name},
                  {"specimen", d.specimen},
                  {"effects", d.effects},
                  {"note", d.note},
                  {"youngs_modulus", s.true_modulus},
                  {"declared_youngs_modulus", s.declared["material"]["E"]},
                  {"hidden", hidden},
                  {"noise_fraction", d.noise_fraction},
                  {"noise_sigma", sigma},
                  {"max_displacement", max_displacement},
                  {"markers", markers.size()},
                  {"seed", d.seed},
                  {"calculix",
                   {{"elements_per_patch", elements},
                    {"element_type", dim == 3 ? "C3D20R" : "CPS8R"},
                    {"mesh_check_elements_per_patch", finer},
                    {"data_from", "the refined mesh (mesh_check_elements_per_patch)"},
                    {"mesh_change_at_markers_rms", change},
                    {"mesh_change_over_noise", change / sigma},
                    // 20-node elements converge at second order in displacement: the refined
                    // mesh's own error is about the change / (2^2 - 1).
                    {"estimated_data_error_over_noise", change / 3.0 / sigma}}}};
    if (!d.grading.empty())
      truth["calculix"]["graded_mesh"] = {
          {"uniform_elements_per_patch", s.truth_elements},
          {"clamp_spans_split", d.grading.clamp_spans},
          {"clamp_span_splits", d.grading.clamp_splits},
          {"lateral_outer_span_splits", d.grading.lateral_splits},
          {"markers", "nodes of the uniform mesh (every one is a node of the graded mesh)"}};
    std::ofstream(folder / "truth.json") << truth.dump(2) << "\n";
    fs::remove_all(work);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%-30s %5zu markers, noise %.3g m, mesh change %.2f x noise, %.0f s\n",
                d.name.c_str(), markers.size(), sigma, change / sigma, seconds);
    std::fflush(stdout);
  }
  return 0;
}

std::string joined(const json& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n.get<std::string>();
  return s.empty() ? "none" : s;
}

int table(const fs::path& data_dir, const std::string& isospring, const fs::path& work) {
  std::map<std::string, std::map<std::string, int>> confusion;  // truth -> found -> datasets
  std::set<std::string> columns;
  int right = 0, total = 0;
  std::printf("| dataset | hidden | found | rms_after / noise | E / true E | wall [s] | right |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  for (const Dataset& d : datasets()) {
    const fs::path folder = data_dir / d.name, out = work / d.name;
    if (!fs::exists(folder / "truth.json")) {
      std::printf("| %s | (not generated) | | | | | |\n", d.name.c_str());
      continue;
    }
    json truth;
    std::ifstream(folder / "truth.json") >> truth;
    const std::string command = isospring + " identify " + (folder / "case.json").string() +
                                " -o " + out.string() + " --quiet > " +
                                (work / (d.name + ".log")).string() + " 2>&1";
    fs::create_directories(work);
    fs::remove_all(out);
    const auto start = std::chrono::steady_clock::now();
    const int status = std::system(command.c_str());
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    json report;
    if (status == 0) std::ifstream(out / "report.json") >> report;
    const json found = status == 0 ? report["effects_added"] : json::array({"(failed)"});
    std::set<std::string> want(truth["effects"].begin(), truth["effects"].end());
    std::set<std::string> got(found.begin(), found.end());
    const bool ok = want == got;
    right += ok;
    ++total;
    double modulus = 0;
    if (status == 0)
      for (const auto& p : report["parameters"])
        if (p["name"] == "E") modulus = p["value"].get<double>();
    const double ratio =
        status == 0 ? report["rms_after"].get<double>() / truth["noise_sigma"].get<double>() : 0;
    std::printf("| %s | %s | %s | %.2f | %.4f | %.0f | %s |\n", d.name.c_str(),
                joined(truth["effects"]).c_str(), joined(found).c_str(), ratio,
                modulus / truth["youngs_modulus"].get<double>(), seconds, ok ? "yes" : "NO");
    std::fflush(stdout);
    const std::string row = want.empty() ? "none" : joined(truth["effects"]);
    if (got.empty()) got.insert("none");
    for (const auto& g : got) {
      ++confusion[row][g];
      columns.insert(g);
    }
  }
  std::printf(
      "\nRight effect set on %d of %d datasets.\n\nConfusion (rows: hidden, columns: "
      "added by identify; datasets):\n\n| hidden \\ added |",
      right, total);
  for (const auto& c : columns) std::printf(" %s |", c.c_str());
  std::printf("\n|---|");
  for (size_t i = 0; i < columns.size(); ++i) std::printf("---|");
  std::printf("\n");
  for (const auto& [row, counts] : confusion) {
    std::printf("| %s |", row.c_str());
    for (const auto& c : columns) std::printf(" %d |", counts.count(c) ? counts.at(c) : 0);
    std::printf("\n");
  }
  return right == total ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string mode = argc > 1 ? argv[1] : "";
    if (mode == "generate" && argc >= 3) return generate(argv[2], {argv + 3, argv + argc});
    if (mode == "table" && (argc == 4 || argc == 5))
      return table(argv[2], argv[3],
                   argc == 5 ? fs::path(argv[4]) : fs::temp_directory_path() / "identify_suite");
    std::cerr << "usage: generate_identify_suite generate OUT_DIR [DATASET...]\n"
                 "       generate_identify_suite table DATA_DIR ISOSPRING [WORK_DIR]\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "generate_identify_suite: " << e.what() << "\n";
    return 1;
  }
}
