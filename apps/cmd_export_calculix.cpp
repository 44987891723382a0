// `isospring export-calculix CASE.json -o deck.inp`: the case's problem as a CalculiX input
// deck (20-node hexahedra or, in 2D, 8-node quadrilaterals on the exact geometry), for an
// independent check with `ccx -i deck`.
#include <cctype>
#include <memory>
#include <sstream>

#include "cli_util.hpp"
#include "command.hpp"
#include "file_report.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/calculix.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/report.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::apps {
namespace {

struct ExportCalculixOptions {
  std::string case_file;
  std::string output;
  std::string element;  // empty: the reduced-integration type of the case's formulation
  bool quiet = false;
};

// The node and element sets the deck defines (NSET= on *NODE/*NSET, ELSET= on *ELEMENT/*ELSET),
// read from the deck text itself so the report names exactly what CalculiX will see.
nlohmann::json deck_sets(const std::string& text) {
  nlohmann::json sets = {{"node_sets", nlohmann::json::array()},
                         {"element_sets", nlohmann::json::array()}};
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] != '*' || line.rfind("**", 0) == 0) continue;  // ** is a comment
    std::string upper = line;
    for (char& ch : upper) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    const std::string keyword = upper.substr(0, upper.find(','));
    const bool node_set = keyword == "*NODE" || keyword == "*NSET";
    const bool element_set = keyword == "*ELEMENT" || keyword == "*ELSET";
    const std::string key = node_set ? "NSET=" : "ELSET=";
    const size_t at = upper.find(key);
    if ((!node_set && !element_set) || at == std::string::npos) continue;
    const size_t begin = at + key.size();
    std::string name = line.substr(begin, line.find(',', begin) - begin);
    while (!name.empty() && std::isspace(static_cast<unsigned char>(name.back()))) name.pop_back();
    sets[node_set ? "node_sets" : "element_sets"].push_back(name);
  }
  return sets;
}

void run_export_calculix(const ExportCalculixOptions& options) {
  const io::Progress progress("export-calculix", options.quiet);
  const std::filesystem::path output(options.output);
  if (output.extension() != ".inp")
    throw nurbs::InputError("-o " + options.output +
                            ": CalculiX reads decks named *.inp; give a name ending in .inp");
  check_output_file(output, input_files(options.case_file));
  const io::Case c = io::read_case_file(options.case_file);
  io::CalculixOptions deck_options;
  deck_options.element_type = options.element;
  deck_options.title = "isospring case " + c.name;
  io::CalculixDeck deck;
  try {
    deck = io::make_calculix_deck(c.problem, deck_options);
  } catch (const nurbs::InputError& e) {
    throw nurbs::InputError(options.case_file + ": " + e.what());
  }
  io::write_file_atomically(output, deck.text);
  FileReport report("export-calculix", options.case_file, output);
  report.json["element_type"] = deck.element_type;
  report.json["nodes"] = deck.nodes.size();
  report.json["elements"] = deck.elements;
  report.json["load_cases"] = deck.load_case_ids;
  const nlohmann::json sets = deck_sets(deck.text);
  report.json["node_sets"] = sets["node_sets"];
  report.json["element_sets"] = sets["element_sets"];
  report.json["run"] = "ccx -i " + output.stem().string();
  report.markdown.heading(1, "isospring export-calculix: " + options.case_file);
  report.markdown.paragraph(
      "CalculiX deck " + options.output + ": " + std::to_string(deck.nodes.size()) + " nodes, " +
      std::to_string(deck.elements) + " " + deck.element_type + " elements (one per knot span, " +
      "nodes on the exact NURBS geometry), one *STEP per load case. Run `ccx -i " +
      output.stem().string() + "` in its folder; displacements are in " + output.stem().string() +
      ".dat. Node sets: " + sets["node_sets"].dump() +
      "; element sets: " + sets["element_sets"].dump() + ".");
  std::vector<std::vector<std::string>> rows;
  for (size_t i = 0; i < deck.load_case_ids.size(); ++i)
    rows.push_back({std::to_string(i + 1), deck.load_case_ids[i]});
  report.markdown.table({"step", "load case"}, rows);
  report.write();
  progress("wrote " + options.output + ": " + std::to_string(deck.nodes.size()) + " nodes, " +
           std::to_string(deck.elements) + " " + deck.element_type + " elements, " +
           std::to_string(deck.load_case_ids.size()) + " step(s); run `ccx -i " +
           output.stem().string() + "` in its folder");
}

void setup_export_calculix(CLI::App& app) {
  auto options = std::make_shared<ExportCalculixOptions>();
  CLI::App* cmd = app.add_subcommand(
      "export-calculix",
      "Write a case as a CalculiX deck (20-node hexahedra, 8-node quads in 2D) for cross-checks");
  cmd->footer(
      "One element per knot span of the discretised patches; nodes are exact NURBS points at\n"
      "element corners and mid-edges. Supports become *BOUNDARY, tractions and pressures\n"
      "consistent nodal forces (*CLOAD), body force and gravity *DLOAD; one *STEP per load case\n"
      "printing U for all nodes. Point loads and single-control-point supports have no nodes and\n"
      "are rejected. Run: ccx -i DECK (without .inp); displacements are in DECK.dat.");
  cmd->add_option("CASE", options->case_file, "Case file (.json)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", options->output, "Deck to write (.inp)")->required();
  cmd->add_option("--element", options->element,
                  "3D: C3D20R (reduced integration, default: no locking in bending) or C3D20; "
                  "plane stress: CPS8R (default) or CPS8; plane strain: CPE8R (default) or CPE8")
      ->check(CLI::IsMember({"C3D20R", "C3D20", "CPS8R", "CPS8", "CPE8R", "CPE8"}));
  cmd->add_flag("-q,--quiet", options->quiet, "No progress lines on stderr");
  cmd->callback([options] { run_export_calculix(*options); });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(85, setup_export_calculix);
}  // namespace isospring::apps
