#pragma once
// Typed access to a JSON document with error messages naming the file and the field's path
// ("case.json: load_cases[0].tractions[1].value[2] must be a number, got string").
#include <Eigen/Core>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace isospring::io::case_json {

/// A value in the document and where it is ("load_cases[0].id").
class Field {
 public:
  Field(const nlohmann::json& value, std::string file, std::string path)
      : value_(&value), file_(std::move(file)), path_(std::move(path)) {}

  /// The field a message prefix "file: path" names (readers that are handed such a prefix).
  static Field at_where(const nlohmann::json& value, const std::string& where);

  const nlohmann::json& json() const { return *value_; }
  const std::string& path() const { return path_; }
  /// "case.json: path" for messages.
  std::string where() const;
  [[noreturn]] void fail(const std::string& message) const;

  /// This must be an object whose keys are all in `allowed` (unknown keys get a suggestion).
  void expect_object(std::initializer_list<const char*> allowed) const;
  bool has(const std::string& key) const;
  Field at(const std::string& key) const;  // a missing key fails with "is missing"
  Field at(size_t index) const;
  /// Array elements (fails unless this is an array; `allow_empty` false fails on []).
  std::vector<Field> elements(bool allow_empty = true) const;

  double number() const;  // finite
  double positive() const;
  double non_negative() const;
  int integer() const;
  bool boolean() const;
  std::string string() const;
  /// A vector of `min_size`..3 finite numbers, padded with zeros to 3.
  Eigen::Vector3d vector(int min_size, int max_size = 3) const;

  // Range checks: every reader of io states a range the same way ("... must be in [0, 1), got
  // 1.5"), so a user sees one wording whatever file or section the number is in.
  /// A finite number in the interval from `lo` to `hi` (open ends excluded; infinite ends
  /// allowed: `at_least`).
  double within(double lo, double hi, bool lo_open = false, bool hi_open = false) const;
  /// A finite number >= minimum (> minimum when `open`).
  double at_least(double minimum, bool open = false) const;
  /// An integer in [lo, hi].
  int integer_within(int lo, int hi) const;
  /// An integer >= minimum.
  int integer_at_least(int minimum) const;
  /// Arrays: every entry checked as above, its index in the message; `allow_empty` false
  /// refuses [].
  std::vector<double> numbers_within(double lo, double hi, bool allow_empty = false) const;
  std::vector<bool> booleans(bool allow_empty = false) const;
  std::vector<std::string> strings(bool allow_empty = true) const;

 private:
  const nlohmann::json* value_;
  std::string file_;
  std::string path_;
};

/// The allowed word closest to `word` by edit distance when it is a plausible typo, else "".
std::string closest_word(const std::string& word, const std::vector<std::string>& allowed);

/// The one wording of an unknown field for every JSON reader of io (case, patch, model and
/// marker settings, the "calibration" object): "<field>: unknown field; did you mean 'x'?
/// (allowed here: a b c)". `field` names the file and the field's path ("case.json:
/// calibration.gama"); `key` is its name in the object, `allowed` the names valid there.
[[noreturn]] void fail_unknown_field(const std::string& field, const std::string& key,
                                     const std::vector<std::string>& allowed);

/// fail_unknown_field for the first key of the object `object` not in `allowed`; `prefix` is what
/// goes before the key ("case.json: calibration." or "case.json: " at the top level).
void reject_unknown_fields(const nlohmann::json& object, const std::vector<std::string>& allowed,
                           const std::string& prefix);

}  // namespace isospring::io::case_json
