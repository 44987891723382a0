#pragma once
// The use case behind `isospring export-calculix CASE.json -o deck.inp [--element TYPE]`: the
// case's problem as a CalculiX input deck (calculix.hpp: 20-node hexahedra or, in 2D, 8-node
// quadrilaterals on the exact geometry) for an independent check with `ccx -i deck`, and the
// report of what the deck defines (counts, steps, the node and element sets CalculiX will see).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "isospring/io/calculix.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/report.hpp"

namespace isospring::workflows {

struct ExportCalculixCommandOptions {
  std::string case_file;  // names the case in messages and the report
  std::string output;     // the deck to write; must end in .inp (ccx -i takes the name without)
  std::string element;    // empty: the reduced-integration type of the case's formulation
};

struct ExportCalculixCommandResult {
  io::CalculixDeck deck;
  std::vector<std::string> node_sets, element_sets;  // as the deck defines them, in order
};

/// Throws nurbs::InputError when `output` is not a deck name CalculiX reads (*.inp); a program
/// calls it before checking the output path against the inputs, run_export_calculix again.
void check_calculix_output(const std::string& output);

/// The node sets (NSET= on *NODE/*NSET) and element sets (ELSET= on *ELEMENT/*ELSET) a deck
/// defines, read from its text, so the report names exactly what CalculiX will see.
void calculix_deck_sets(const std::string& text, std::vector<std::string>& node_sets,
                        std::vector<std::string>& element_sets);

/// Builds the deck of `c` (read_case_file) and writes it atomically to options.output. Throws
/// nurbs::InputError, naming the case file, for what a deck cannot express (make_calculix_deck).
ExportCalculixCommandResult run_export_calculix(const io::Case& c,
                                                const ExportCalculixCommandOptions& options);

/// The report's content beside the deck (FileReport's json and markdown).
void export_calculix_report(const ExportCalculixCommandResult& r,
                            const ExportCalculixCommandOptions& options, nlohmann::json& json,
                            io::MarkdownReport& md);

/// The last line the program prints: what was written and how to run it.
std::string export_calculix_summary(const ExportCalculixCommandResult& r,
                                    const ExportCalculixCommandOptions& options);

}  // namespace isospring::workflows
