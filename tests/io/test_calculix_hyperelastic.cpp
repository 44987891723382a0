// CalculiX decks for large deformation: the neo-Hookean material card (C10 = mu / 2, D1 = 2 / K
// of E and nu), ccx's Newton criteria, the reaction output and its reader. ccx itself runs in
// tests/workflows/test_neo_hookean_calculix.cpp.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "isospring/io/calculix.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring::io {
namespace {
namespace fs = std::filesystem;

analysis::Problem block(analysis::Formulation formulation) {
  analysis::Problem problem;
  problem.formulation = formulation;
  problem.material = {1000.0, 0.3, 0.0, 1.0};
  const nurbs::KnotVector linear(1, {0, 0, 1, 1});
  if (formulation == analysis::Formulation::kSolid)
    problem.patches.push_back(
        nurbs::elevate_degree(nurbs::Patch({linear, linear, linear}, {{0, 0, 0},
                                                                      {1, 0, 0},
                                                                      {0, 1, 0},
                                                                      {1, 1, 0},
                                                                      {0, 0, 1},
                                                                      {1, 0, 1},
                                                                      {0, 1, 1},
                                                                      {1, 1, 1}}),
                              1));
  else
    problem.patches.push_back(nurbs::elevate_degree(
        nurbs::Patch({linear, linear}, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}), 1));
  analysis::Support clamp;
  clamp.side = {0, 0, 0};
  clamp.fixed = {true, true, true};
  problem.supports.push_back(clamp);
  analysis::LoadCase load;
  load.id = "pull";
  analysis::Traction t;
  t.side = {0, 0, 1};
  t.value = {10.0, 0, 0};
  load.tractions.push_back(t);
  problem.load_cases.push_back(load);
  return problem;
}

// The data line after the first line starting with `keyword`.
std::string line_after(const std::string& text, const std::string& keyword) {
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(keyword, 0) == 0 && std::getline(in, line)) return line;
  return "";
}

TEST(CalculixHyperelastic, NeoHookeCardHasTheModuliOfEAndNu) {
  CalculixOptions options;
  options.nonlinear = true;
  options.neo_hookean = true;
  const CalculixDeck deck = make_calculix_deck(block(analysis::Formulation::kSolid), options);
  EXPECT_EQ(deck.text.find("*ELASTIC"), std::string::npos);
  std::istringstream card(line_after(deck.text, "*HYPERELASTIC, NEO HOOKE"));
  double c10 = 0, d1 = 0;
  char comma = 0;
  ASSERT_TRUE(card >> c10 >> comma >> d1);
  // mu = E / (2 (1 + nu)) = 384.615..., K = E / (3 (1 - 2 nu)) = 833.33...
  EXPECT_NEAR(c10, 1000.0 / 2.6 / 2.0, 1e-12 * c10);
  EXPECT_NEAR(d1, 2.0 / (1000.0 / 1.2), 1e-12 * d1);
  EXPECT_NE(deck.text.find("*STEP, NLGEOM"), std::string::npos);
  // Defaults: ccx's own Newton criteria and no reaction output.
  EXPECT_EQ(deck.text.find("*CONTROLS"), std::string::npos);
  EXPECT_EQ(deck.text.find("RF\n"), std::string::npos);
}

TEST(CalculixHyperelastic, NewtonCriteriaAndReactionsOnRequest) {
  CalculixOptions options;
  options.nonlinear = true;
  options.newton_tolerance = 1e-9;
  options.print_reactions = true;
  const CalculixDeck deck = make_calculix_deck(block(analysis::Formulation::kSolid), options);
  EXPECT_EQ(line_after(deck.text, "*CONTROLS, PARAMETERS=FIELD"), "1e-09, 1e-07");
  EXPECT_NE(deck.text.find("*NODE PRINT, NSET=Nall\nRF\n"), std::string::npos);
  EXPECT_NE(deck.text.find("*ELASTIC\n1000, 0.29999999999999999"), std::string::npos)
      << deck.text.substr(deck.text.find("*MATERIAL"), 80);
}

TEST(CalculixHyperelastic, PlaneStressAndIncompressibleAreRefused) {
  CalculixOptions options;
  options.neo_hookean = true;
  try {
    make_calculix_deck(block(analysis::Formulation::kPlaneStress), options);
    FAIL() << "expected an InputError";
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("plane stress"), std::string::npos) << e.what();
  }
  analysis::Problem incompressible = block(analysis::Formulation::kSolid);
  incompressible.material.poisson_ratio = 0.5;
  try {
    make_calculix_deck(incompressible, options);
    FAIL() << "expected an InputError";
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("Poisson"), std::string::npos) << e.what();
  }
  // Plane strain is written (CPE8 with the same card).
  EXPECT_NO_THROW(make_calculix_deck(block(analysis::Formulation::kPlaneStrain), options));
}

TEST(CalculixHyperelastic, ReactionBlocksAreRead) {
  const fs::path dat =
      fs::temp_directory_path() / ("isospring-reactions-" + std::to_string(getpid()) + ".dat");
  std::ofstream(dat) << "\n displacements (vx,vy,vz) for set NALL and time  0.1000000E+01\n\n"
                        "         1  1.000000E-01  0.000000E+00  0.000000E+00\n\n"
                        " forces (fx,fy,fz) for set NALL and time  0.1000000E+01\n\n"
                        "         1 -2.500000E+00  1.000000E-03  0.000000E+00\n"
                        "         2  2.500000E+00  0.000000E+00  0.000000E+00\n\n";
  const auto forces = read_calculix_reactions(dat);
  ASSERT_EQ(forces.size(), 1u);
  EXPECT_EQ(forces[0].time, 1.0);
  ASSERT_EQ(forces[0].nodes.size(), 2u);
  EXPECT_EQ(forces[0].nodes.at(1), Eigen::Vector3d(-2.5, 1e-3, 0.0));
  EXPECT_EQ(read_calculix_dat(dat)[0].nodes.at(1).x(), 0.1);
  // A file without reactions: an error naming the file and the missing request.
  std::ofstream(dat) << "\n displacements (vx,vy,vz) for set NALL and time  0.1000000E+01\n\n"
                        "         1  1.000000E-01  0.000000E+00  0.000000E+00\n\n";
  try {
    read_calculix_reactions(dat);
    FAIL() << "expected an InputError";
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(dat.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("RF"), std::string::npos) << e.what();
  }
  fs::remove(dat);
}

}  // namespace
}  // namespace isospring::io
