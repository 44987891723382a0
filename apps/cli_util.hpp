#pragma once
// Small helpers shared by the subcommands: parsing parameter lists, reading patch inputs and
// checking the output folder.
#include <filesystem>
#include <string>
#include <vector>

#include "isospring/io/case_file.hpp"
#include "isospring/io/input_file.hpp"
#include "isospring/io/number_list.hpp"
#include "isospring/nurbs/patch.hpp"

namespace isospring::apps {

// parse_number_list is the library's (io/number_list.hpp).
using io::parse_number_list;

// Input kinds and the files an input reads are the library's (io/input_file.hpp).
using io::case_inputs;
using io::input_files;
using io::input_kind;
using io::InputKind;
using io::read_patches_any;

/// The output folder given with -o, checked before any work: throws nurbs::InputError when the
/// path exists and is not a folder, when files cannot be created there, or when one of the files
/// `names` the command writes into it is one of `inputs` (io/output_guard.hpp). The folder itself
/// is created when the outputs are written.
std::filesystem::path output_folder(const std::string& option_value,
                                    const std::vector<std::filesystem::path>& inputs,
                                    const std::vector<std::string>& names);

/// The same for the single-file commands: `output`, its two reports (file_report.hpp) and
/// `extra` outputs must spare the inputs, and its folder must be writable.
void check_output_file(const std::filesystem::path& output,
                       const std::vector<std::filesystem::path>& inputs,
                       const std::vector<std::filesystem::path>& extra = {});

/// The memory a run may use: `max_memory_gb` (the --max-memory option; 0 when not given) or the
/// available memory, whichever is smaller; `source` says which, for messages.
struct MemoryLimit {
  double bytes = 0;  // 0: unknown (no limit)
  std::string source;
};
MemoryLimit memory_limit(double max_memory_gb);

/// The same as the limit of a static solve for io::read_case_file.
io::CaseLimits solve_limits(double max_memory_gb);

/// `folder / name` for each name, for the output checks after the case is read (file names
/// that depend on load-case ids).
std::vector<std::filesystem::path> in_folder(const std::filesystem::path& folder,
                                             const std::vector<std::string>& names);

}  // namespace isospring::apps
