// JSON parsing with messages that name the file, the line and column and the field
// (json_text.hpp).
#include "isospring/io/json_text.hpp"

#include <algorithm>
#include <limits>
#include <vector>

#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {
using json = nlohmann::json;

// A SAX handler that builds the document with nlohmann's own DOM builder and tracks the path of
// the value being read ("load_cases[0].tractions[1].value[2]"), so a number that overflows can be
// reported by its field: nlohmann's exception only quotes the number.
class PathTrackingParser {
 public:
  explicit PathTrackingParser(json& root) : dom_(root, true) {}

  bool null() { return value() && dom_.null(); }
  bool boolean(bool v) { return value() && dom_.boolean(v); }
  bool number_integer(json::number_integer_t v) { return value() && dom_.number_integer(v); }
  bool number_unsigned(json::number_unsigned_t v) { return value() && dom_.number_unsigned(v); }
  bool number_float(json::number_float_t v, const std::string& s) {
    return value() && dom_.number_float(v, s);
  }
  bool string(std::string& v) { return value() && dom_.string(v); }
  bool binary(json::binary_t& v) { return value() && dom_.binary(v); }
  bool start_object(std::size_t n) {
    value();
    frames_.push_back({false, 0, ""});
    return dom_.start_object(n);
  }
  bool key(std::string& k) {
    frames_.back().key = k;
    return dom_.key(k);
  }
  bool end_object() {
    frames_.pop_back();
    return dom_.end_object();
  }
  bool start_array(std::size_t n) {
    value();
    frames_.push_back({true, 0, ""});
    return dom_.start_array(n);
  }
  bool end_array() {
    frames_.pop_back();
    return dom_.end_array();
  }
  bool parse_error(std::size_t position, const std::string& token,
                   const nlohmann::detail::exception& error) {
    failed_ = true;
    position_ = position;
    token_ = token;
    message_ = error.what();
    overflow_ = error.id == 406;  // out_of_range.406: number overflow
    field_ = current_path();
    return false;
  }

  bool failed() const { return failed_; }
  bool overflow() const { return overflow_; }
  std::size_t position() const { return position_; }
  const std::string& token() const { return token_; }
  const std::string& message() const { return message_; }
  const std::string& field() const { return field_; }

 private:
  struct Frame {
    bool array;
    std::size_t next_index;
    std::string key;
  };

  // Called before every value: advances the index of the enclosing array.
  bool value() {
    if (!frames_.empty() && frames_.back().array) ++frames_.back().next_index;
    return true;
  }

  // The path of the value being parsed when the error occurred. An enclosing array has already
  // counted the container being read (index next_index - 1); the innermost one has not yet
  // counted the value that failed (index next_index).
  std::string current_path() const {
    std::string path;
    for (size_t i = 0; i < frames_.size(); ++i) {
      const Frame& f = frames_[i];
      if (f.array)
        path +=
            "[" + std::to_string(i + 1 == frames_.size() ? f.next_index : f.next_index - 1) + "]";
      else if (!f.key.empty())
        path += (path.empty() ? "" : ".") + f.key;
    }
    return path;
  }

  nlohmann::detail::json_sax_dom_parser<json> dom_;
  std::vector<Frame> frames_;
  bool failed_ = false, overflow_ = false;
  std::size_t position_ = 0;
  std::string token_, message_, field_;
};

// 1-based line and column of the 0-based byte `offset`.
std::string line_and_column(const std::string& text, std::size_t offset) {
  offset = std::min(offset, text.size());
  const auto begin = text.begin(), end = text.begin() + static_cast<std::ptrdiff_t>(offset);
  const std::size_t line = 1 + static_cast<std::size_t>(std::count(begin, end, '\n'));
  const std::size_t line_start = offset == 0 ? 0 : text.rfind('\n', offset - 1) + 1;  // npos+1 = 0
  return "line " + std::to_string(line) + ", column " + std::to_string(offset - line_start + 1);
}
}  // namespace

json parse_json_text(const std::string& text, const std::string& source, const std::string& what) {
  json document;
  PathTrackingParser parser(document);
  json::sax_parse(text, &parser);
  if (!parser.failed()) return document;
  // The reported position is just past the offending token: point at its first character.
  const std::size_t token_start =
      parser.position() >= parser.token().size() ? parser.position() - parser.token().size() : 0;
  const std::string where = source + ": " + line_and_column(text, token_start);
  if (parser.overflow())
    throw nurbs::InputError(where + ": " + (parser.field().empty() ? "a number" : parser.field()) +
                            " = " + parser.token() +
                            " does not fit in a double (largest about 1.8e308); give the value "
                            "in SI units as a finite number");
  throw nurbs::InputError(where + ": not valid JSON (" + parser.message() +
                          "); check commas, quotes and brackets there, or give a " + what);
}

std::optional<int> json_int(const json& value) {
  constexpr auto largest = static_cast<json::number_unsigned_t>(std::numeric_limits<int>::max());
  if (value.is_number_unsigned()) {
    const auto x = value.get<json::number_unsigned_t>();
    if (x <= largest) return static_cast<int>(x);
  } else if (value.is_number_integer()) {
    const auto x = value.get<json::number_integer_t>();
    if (x >= std::numeric_limits<int>::min() && x <= std::numeric_limits<int>::max())
      return static_cast<int>(x);
  }
  return std::nullopt;
}

}  // namespace isospring::io
