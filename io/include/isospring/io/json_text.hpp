#pragma once
// The one JSON parser of every input file (case, patch and model files): syntax errors and
// numbers a double cannot hold (e.g. 1e999) become nurbs::InputError naming the file, the line
// and column, and for numbers the field, instead of escaping as a library exception (exit 4).
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace isospring::io {

/// Parses `text` read from `source` (a file name for messages). `what` says what the file should
/// be ("case file"), for the fix in the message.
nlohmann::json parse_json_text(const std::string& text, const std::string& source,
                               const std::string& what);

/// The value of an integer JSON number that fits an int; nullopt for anything else (a float, a
/// string, or an integer such as 4294967298 that nlohmann's get<int>() silently wraps to 2).
std::optional<int> json_int(const nlohmann::json& value);

}  // namespace isospring::io
