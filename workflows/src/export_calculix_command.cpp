// run_export_calculix and its report (see export_calculix_command.hpp).
#include "isospring/workflows/export_calculix_command.hpp"

#include <cctype>
#include <filesystem>
#include <sstream>

#include "isospring/io/atomic_file.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;
namespace {

std::string deck_stem(const ExportCalculixCommandOptions& options) {
  return std::filesystem::path(options.output).stem().string();
}

}  // namespace

void check_calculix_output(const std::string& output) {
  if (std::filesystem::path(output).extension() != ".inp")
    throw nurbs::InputError("-o " + output +
                            ": CalculiX reads decks named *.inp; give a name ending in .inp");
}

void calculix_deck_sets(const std::string& text, std::vector<std::string>& node_sets,
                        std::vector<std::string>& element_sets) {
  node_sets.clear();
  element_sets.clear();
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
    (node_set ? node_sets : element_sets).push_back(name);
  }
}

ExportCalculixCommandResult run_export_calculix(const Case& c,
                                                const ExportCalculixCommandOptions& options) {
  check_calculix_output(options.output);
  CalculixOptions deck_options;
  deck_options.element_type = options.element;
  deck_options.title = "isospring case " + c.name;
  ExportCalculixCommandResult r;
  try {
    r.deck = make_calculix_deck(c.problem, deck_options);
  } catch (const nurbs::InputError& e) {
    throw nurbs::InputError(options.case_file + ": " + e.what());
  }
  write_file_atomically(options.output, r.deck.text);
  calculix_deck_sets(r.deck.text, r.node_sets, r.element_sets);
  return r;
}

void export_calculix_report(const ExportCalculixCommandResult& r,
                            const ExportCalculixCommandOptions& options, nlohmann::json& json,
                            MarkdownReport& md) {
  const CalculixDeck& deck = r.deck;
  const std::string stem = deck_stem(options);
  const nlohmann::json node_sets = r.node_sets, element_sets = r.element_sets;  // [] when none
  json["element_type"] = deck.element_type;
  json["nodes"] = deck.nodes.size();
  json["elements"] = deck.elements;
  json["load_cases"] = deck.load_case_ids;
  json["node_sets"] = node_sets;
  json["element_sets"] = element_sets;
  json["run"] = "ccx -i " + stem;
  md.heading(1, "isospring export-calculix: " + options.case_file);
  md.paragraph(
      "CalculiX deck " + options.output + ": " + std::to_string(deck.nodes.size()) + " nodes, " +
      std::to_string(deck.elements) + " " + deck.element_type + " elements (one per knot span, " +
      "nodes on the exact NURBS geometry), one *STEP per load case. Run `ccx -i " + stem +
      "` in its folder; displacements are in " + stem + ".dat. Node sets: " + node_sets.dump() +
      "; element sets: " + element_sets.dump() + ".");
  std::vector<std::vector<std::string>> rows;
  for (size_t i = 0; i < deck.load_case_ids.size(); ++i)
    rows.push_back({std::to_string(i + 1), deck.load_case_ids[i]});
  md.table({"step", "load case"}, rows);
}

std::string export_calculix_summary(const ExportCalculixCommandResult& r,
                                    const ExportCalculixCommandOptions& options) {
  return "wrote " + options.output + ": " + std::to_string(r.deck.nodes.size()) + " nodes, " +
         std::to_string(r.deck.elements) + " " + r.deck.element_type + " elements, " +
         std::to_string(r.deck.load_case_ids.size()) + " step(s); run `ccx -i " +
         deck_stem(options) + "` in its folder";
}

}  // namespace isospring::workflows
