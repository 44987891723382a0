#pragma once
// Measured-data sets from an independent solver for the identification tests: CalculiX (C3D20R
// hexahedra, Debian package calculix-ccx) solves the TRUE problem (true material, undeclared
// effects, a converged mesh of its own), markers are ccx nodes on chosen faces, and measuring-frame
// effects and Gaussian noise are added to the printed displacements. Nothing of the model the
// identification fits (its degree, its mesh, its code path) enters the data.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "isospring/analysis/problem.hpp"
#include "isospring/fitting/measure.hpp"
#include "isospring/io/calculix.hpp"

namespace isospring::testing {

struct CalculixDatasetSpec {
  analysis::Problem truth;  // at ccx's mesh: every knot span becomes one C3D20R element
  std::function<bool(const Eigen::Vector3d&)> is_marker;  // which ccx nodes are markers
  int stride = 1;                                         // every stride-th qualifying node
  double noise_fraction = 0.0;  // noise sigma / largest displacement of the data
  unsigned seed = 1;
  bool nonlinear = false;  // ccx NLGEOM: large deformation (undeclared geometric nonlinearity)
  /// Young's modulus per element from its centroid (graded material, soft layers); empty: uniform.
  std::function<double(const Eigen::Vector3d&)> youngs_modulus_at;
  /// Measuring-frame motion added to every marker of a load case (all load cases alike):
  /// translation [m] and small rotation [rad] about `rotation_centre`.
  Eigen::Vector3d frame_translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d frame_rotation = Eigen::Vector3d::Zero();
  Eigen::Vector3d rotation_centre = Eigen::Vector3d::Zero();
};

struct CalculixDataset {
  std::vector<fitting::Marker> markers;
  double noise_sigma = 0.0;  // [m]
  double max_displacement = 0.0;
  std::string error;  // non-empty when ccx failed (the log's path)
};

inline bool calculix_available() {
  return std::system("command -v ccx > /dev/null 2>&1") == 0;
}

/// ccx on `deck` in `folder` (created): its displacement blocks, one per step; `error` is set
/// when ccx failed or printed another number of blocks.
inline std::vector<io::CalculixDisplacements> run_calculix(const io::CalculixDeck& deck,
                                                           const std::filesystem::path& folder,
                                                           std::string* error) {
  std::filesystem::create_directories(folder);
  std::ofstream(folder / "deck.inp") << deck.text;
  const std::string command = "cd '" + folder.string() + "' && ccx -i deck > ccx.log 2>&1";
  if (std::system(command.c_str()) != 0) {
    *error = "ccx failed; see " + (folder / "ccx.log").string();
    return {};
  }
  auto blocks = io::read_calculix_dat(folder / "deck.dat");
  if (blocks.size() != deck.load_case_ids.size())
    *error = (folder / "deck.dat").string() + ": ccx printed " + std::to_string(blocks.size()) +
             " displacement blocks for " + std::to_string(deck.load_case_ids.size()) + " steps";
  return blocks;
}

/// Large deformation: every load case its own ccx run (folder/<load case>), from the undeformed
/// body, two at a time. In one deck each NLGEOM step starts from the previous step's deformed
/// state; an elastic body reaches the same equilibrium either way, but Newton needs more
/// iterations to unload the previous case (the tissue-like cantilever at nu = 0.49, 30 x 6 x 6:
/// 4, 6 and 9 iterations in one deck, 4, 4 and 3 apart, the displacements within 0.13 x the
/// noise of each other, ccx's own convergence tolerance), and on the refined mesh each iteration
/// is a factorisation of over 100,000 equations.
inline std::vector<io::CalculixDisplacements> run_calculix_per_load_case(
    const analysis::Problem& problem, const io::CalculixOptions& options,
    const io::CalculixDeck& whole, const std::filesystem::path& folder, std::string* error) {
  const size_t n = problem.load_cases.size();
  std::vector<io::CalculixDisplacements> blocks(n);
  std::vector<std::string> errors(n);
  auto solve = [&](size_t c) {
    analysis::Problem one = problem;
    one.load_cases = {problem.load_cases[c]};
    const io::CalculixDeck deck = io::make_calculix_deck(one, options);
    if (deck.nodes != whole.nodes || deck.load_case_ids != std::vector{whole.load_case_ids[c]}) {
      errors[c] = "the deck of load case " + whole.load_case_ids[c] + " numbers its nodes apart";
      return;
    }
    auto got = run_calculix(deck, folder / whole.load_case_ids[c], &errors[c]);
    if (errors[c].empty()) blocks[c] = std::move(got.front());
  };
  for (size_t c = 0; c < n; c += 2) {
    std::thread second;
    if (c + 1 < n) second = std::thread(solve, c + 1);
    solve(c);
    if (second.joinable()) second.join();
  }
  for (const std::string& e : errors)
    if (!e.empty()) {
      *error = e;
      return {};
    }
  return blocks;
}

/// Runs ccx in `folder` (created) and returns the markers.
inline CalculixDataset make_calculix_dataset(const CalculixDatasetSpec& spec,
                                             const std::filesystem::path& folder) {
  CalculixDataset out;
  io::CalculixOptions options;
  options.nonlinear = spec.nonlinear;
  options.youngs_modulus_at = spec.youngs_modulus_at;
  const io::CalculixDeck deck = io::make_calculix_deck(spec.truth, options);
  const auto blocks =
      spec.nonlinear ? run_calculix_per_load_case(spec.truth, options, deck, folder, &out.error)
                     : run_calculix(deck, folder, &out.error);
  if (!out.error.empty()) return out;
  int row = 2;
  for (size_t s = 0; s < blocks.size(); ++s) {
    int seen = 0;
    for (size_t n = 0; n < deck.nodes.size(); ++n) {
      if (!spec.is_marker(deck.nodes[n]) || seen++ % spec.stride != 0) continue;
      fitting::Marker m;
      m.load_case = deck.load_case_ids[s];
      m.position = deck.nodes[n];
      m.displacement = blocks[s].nodes.at(static_cast<int>(n) + 1) + spec.frame_translation +
                       spec.frame_rotation.cross(deck.nodes[n] - spec.rotation_centre);
      m.row = row++;
      out.markers.push_back(m);
    }
  }
  for (const auto& m : out.markers)
    out.max_displacement = std::max(out.max_displacement, m.displacement.cwiseAbs().maxCoeff());
  out.noise_sigma = spec.noise_fraction * out.max_displacement;
  std::mt19937 rng(spec.seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (auto& m : out.markers)
    for (int c = 0; c < 3; ++c) m.displacement[c] += out.noise_sigma * noise(rng);
  return out;
}

/// The markers as the default CSV of `isospring identify` (load_case,x,y,z,ux,uy,uz), in metres.
inline void write_markers_csv(const std::filesystem::path& path,
                              const std::vector<fitting::Marker>& markers) {
  std::ofstream out(path);
  out.precision(17);
  out << "load_case,x,y,z,ux,uy,uz\n";
  for (const auto& m : markers)
    out << m.load_case << ',' << m.position.x() << ',' << m.position.y() << ',' << m.position.z()
        << ',' << m.displacement.x() << ',' << m.displacement.y() << ',' << m.displacement.z()
        << '\n';
}

}  // namespace isospring::testing
