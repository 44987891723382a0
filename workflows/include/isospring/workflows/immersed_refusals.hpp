#pragma once
// What the commands that take body-fitted geometry say when given an immersed case
// ({"geometry": {"type": "immersed", ...}}), before any work: why the command has no immersed
// form and what to do instead. `analyze`, `study`, `calibrate` and `identify` run immersed cases.
#include <filesystem>
#include <string>

namespace isospring::workflows {

/// Throws nurbs::InputError naming the case file, the command and the way forward when
/// `case_file` is an immersed case; returns otherwise (also for files that are not JSON: the
/// command's own reader reports those). `command` is the program's command name
/// (export-calculix, export-step).
void refuse_immersed_case(const std::filesystem::path& case_file, const std::string& command);

}  // namespace isospring::workflows
