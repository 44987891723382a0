// The export-calculix use case (export_calculix_command.hpp): the deck written is the one built,
// its report names what the deck defines, the sets are read from the deck text, and a deck name
// CalculiX cannot read is refused before anything is written.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: CTest runs tests in parallel processes

#include <fstream>
#include <sstream>

#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/export_calculix_command.hpp"

namespace isospring::workflows {
using namespace isospring::io;  // the formats the use cases read and write
namespace {
namespace fs = std::filesystem;

const std::string kExamples = std::string(ISOSPRING_SOURCE_DIR) + "/examples/";

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(ExportCalculixUseCase, DeckSetsAreReadFromTheText) {
  std::vector<std::string> nodes, elements;
  calculix_deck_sets(
      "** *NSET,NSET=COMMENTED\n*NODE, NSET=Nall\n1, 0, 0, 0\n*ELEMENT, TYPE=C3D20R, "
      "ELSET=Eall\n*nset,nset=fix \n*Elset,Elset=E1 ,GENERATE\n*BOUNDARY\nfix, 1, 3\n",
      nodes, elements);
  EXPECT_EQ(nodes, (std::vector<std::string>{"Nall", "fix"}));
  EXPECT_EQ(elements, (std::vector<std::string>{"Eall", "E1"}));
}

TEST(ExportCalculixUseCase, WritesTheDeckAndReportsWhatItDefines) {
  const fs::path dir = fs::temp_directory_path() /
                       ("isospring_test_export_calculix_use_case-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  ExportCalculixCommandOptions options;
  options.case_file = kExamples + "cantilever_box.json";
  options.output = (dir / "box.inp").string();
  const Case c = read_case_file(options.case_file);
  const ExportCalculixCommandResult r = run_export_calculix(c, options);
  EXPECT_EQ(read(options.output), r.deck.text);
  EXPECT_EQ(r.deck.element_type, "C3D20R");  // the default of a solid
  EXPECT_GT(r.deck.elements, 0);
  EXPECT_EQ(r.deck.load_case_ids.size(), c.problem.load_cases.size());
  std::vector<std::string> nodes, elements;
  calculix_deck_sets(r.deck.text, nodes, elements);
  EXPECT_EQ(r.node_sets, nodes);
  EXPECT_EQ(r.element_sets, elements);
  EXPECT_FALSE(r.node_sets.empty());

  nlohmann::json json;
  MarkdownReport md;
  export_calculix_report(r, options, json, md);
  EXPECT_EQ(json["nodes"], r.deck.nodes.size());
  EXPECT_EQ(json["elements"], r.deck.elements);
  EXPECT_EQ(json["node_sets"], nlohmann::json(r.node_sets));
  EXPECT_EQ(json["run"], "ccx -i box");
  EXPECT_EQ(export_calculix_summary(r, options),
            "wrote " + options.output + ": " + std::to_string(r.deck.nodes.size()) + " nodes, " +
                std::to_string(r.deck.elements) + " C3D20R elements, " +
                std::to_string(r.deck.load_case_ids.size()) +
                " step(s); run `ccx -i box` in its folder");

  // An element type that does not fit the formulation is named with the case file.
  options.output = (dir / "plane.inp").string();
  options.element = "CPS8";
  try {
    run_export_calculix(c, options);
    FAIL() << "expected an InputError";
  } catch (const nurbs::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(options.case_file + ": ", 0), 0u) << e.what();
  }
  EXPECT_FALSE(fs::exists(options.output));

  // ccx -i takes the deck's name without .inp: another extension is refused, nothing written.
  options.element.clear();
  options.output = (dir / "box.txt").string();
  EXPECT_THROW(run_export_calculix(c, options), nurbs::InputError);
  EXPECT_FALSE(fs::exists(options.output));
  EXPECT_THROW(check_calculix_output("deck"), nurbs::InputError);
  EXPECT_NO_THROW(check_calculix_output("deck.inp"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace isospring::workflows
