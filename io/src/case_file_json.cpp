#include "case_file_json.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "isospring/nurbs/error.hpp"

namespace isospring::io::case_json {
using nlohmann::json;

namespace {
std::string type_name(const json& value) {
  if (value.is_number_integer()) return "integer";
  if (value.is_number()) return "number";
  return value.type_name();
}

size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t substitute = diagonal + (std::tolower(a[i - 1]) != std::tolower(b[j - 1]));
      diagonal = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitute});
    }
  }
  return row[b.size()];
}
}  // namespace

std::string closest_word(const std::string& word, const std::vector<std::string>& allowed) {
  std::string best;
  size_t best_distance = std::string::npos;
  for (const std::string& candidate : allowed) {
    const size_t d = edit_distance(word, candidate);
    if (d < best_distance) best_distance = d, best = candidate;
  }
  // A typo changes a few characters; beyond a third of the word it is a different word.
  const size_t limit = std::max<size_t>(2, word.size() / 3);
  return best_distance <= limit ? best : "";
}

Field Field::at_where(const nlohmann::json& value, const std::string& where) {
  const size_t colon = where.find(": ");
  if (colon == std::string::npos) return Field(value, where, "");
  return Field(value, where.substr(0, colon), where.substr(colon + 2));
}

std::string Field::where() const {
  return file_ + ": " + (path_.empty() ? "(document)" : path_);
}

void Field::fail(const std::string& message) const {
  throw nurbs::InputError(where() + message);
}

void Field::expect_object(std::initializer_list<const char*> allowed) const {
  if (!value_->is_object()) fail(" must be an object {...}, got " + type_name(*value_));
  reject_unknown_fields(*value_, std::vector<std::string>(allowed.begin(), allowed.end()),
                        file_ + ": " + (path_.empty() ? "" : path_ + "."));
}

void fail_unknown_field(const std::string& field, const std::string& key,
                        const std::vector<std::string>& allowed) {
  std::string message = field + ": unknown field";
  const std::string suggestion = closest_word(key, allowed);
  if (!suggestion.empty()) message += "; did you mean '" + suggestion + "'?";
  message += " (allowed here:";
  for (const std::string& name : allowed) message += " " + name;
  message += ")";
  throw nurbs::InputError(message);
}

void reject_unknown_fields(const nlohmann::json& object, const std::vector<std::string>& allowed,
                           const std::string& prefix) {
  for (const auto& [key, value] : object.items())
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end())
      fail_unknown_field(prefix + key, key, allowed);
}

bool Field::has(const std::string& key) const {
  return value_->is_object() && value_->contains(key);
}

Field Field::at(const std::string& key) const {
  const std::string child = path_.empty() ? key : path_ + "." + key;
  if (!has(key)) throw nurbs::InputError(file_ + ": " + child + " is missing");
  return Field((*value_)[key], file_, child);
}

Field Field::at(size_t index) const {
  return Field((*value_)[index], file_, path_ + "[" + std::to_string(index) + "]");
}

std::vector<Field> Field::elements(bool allow_empty) const {
  if (!value_->is_array()) fail(" must be an array [...], got " + type_name(*value_));
  if (!allow_empty && value_->empty()) fail(" must not be empty");
  std::vector<Field> out;
  for (size_t i = 0; i < value_->size(); ++i) out.push_back(at(i));
  return out;
}

double Field::number() const {
  if (!value_->is_number()) fail(" must be a number, got " + type_name(*value_));
  const double x = value_->get<double>();
  if (!std::isfinite(x)) fail(" is not finite (NaN or inf)");
  return x;
}

double Field::positive() const {
  const double x = number();
  if (!(x > 0)) fail(" must be > 0, got " + nlohmann::json(x).dump());
  return x;
}

double Field::non_negative() const {
  const double x = number();
  if (x < 0) fail(" must be >= 0, got " + nlohmann::json(x).dump());
  return x;
}

int Field::integer() const {
  if (!value_->is_number_integer()) fail(" must be an integer, got " + type_name(*value_));
  const auto x = value_->get<long long>();
  if (x < -1000000000LL || x > 1000000000LL)
    fail(" is out of range for an integer (|n| <= 1e9), got " + value_->dump());
  return static_cast<int>(x);
}

bool Field::boolean() const {
  if (!value_->is_boolean()) fail(" must be true or false, got " + type_name(*value_));
  return value_->get<bool>();
}

std::string Field::string() const {
  if (!value_->is_string()) fail(" must be a string, got " + type_name(*value_));
  return value_->get<std::string>();
}

Eigen::Vector3d Field::vector(int min_size, int max_size) const {
  const std::string sizes = min_size == max_size
                                ? std::to_string(min_size)
                                : std::to_string(min_size) + " or " + std::to_string(max_size);
  if (!value_->is_array() || static_cast<int>(value_->size()) < min_size ||
      static_cast<int>(value_->size()) > max_size)
    fail(" must be an array of " + sizes + " numbers, got " +
         (value_->is_array() ? std::to_string(value_->size()) + " entries" : type_name(*value_)));
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < value_->size(); ++i) v[static_cast<int>(i)] = at(i).number();
  return v;
}

namespace {
std::string bound(double x) {
  std::ostringstream out;
  out.precision(12);
  out << x;  // 0, 0.999, 1e-12, inf
  return out.str();
}
}  // namespace

double Field::within(double lo, double hi, bool lo_open, bool hi_open) const {
  const double x = number();
  const bool low_ok = lo_open ? x > lo : x >= lo;
  const bool high_ok = hi_open ? x < hi : x <= hi;
  if (low_ok && high_ok) return x;
  std::string range;
  if (std::isinf(hi))
    range = std::string(lo_open ? "> " : ">= ") + bound(lo);
  else if (std::isinf(lo))
    range = std::string(hi_open ? "< " : "<= ") + bound(hi);
  else
    range = "in " + std::string(lo_open ? "(" : "[") + bound(lo) + ", " + bound(hi) +
            (hi_open ? ")" : "]");
  fail(" must be " + range + ", got " + value_->dump());
}

double Field::at_least(double minimum, bool open) const {
  return within(minimum, std::numeric_limits<double>::infinity(), open, false);
}

int Field::integer_within(int lo, int hi) const {
  const int x = integer();
  if (x < lo || x > hi)
    fail(" must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
         value_->dump());
  return x;
}

int Field::integer_at_least(int minimum) const {
  const int x = integer();
  if (x < minimum)
    fail(" must be an integer >= " + std::to_string(minimum) + ", got " + value_->dump());
  return x;
}

std::vector<double> Field::numbers_within(double lo, double hi, bool allow_empty) const {
  std::vector<double> out;
  for (const Field& entry : elements(allow_empty)) out.push_back(entry.within(lo, hi));
  return out;
}

std::vector<bool> Field::booleans(bool allow_empty) const {
  std::vector<bool> out;
  for (const Field& entry : elements(allow_empty)) out.push_back(entry.boolean());
  return out;
}

std::vector<std::string> Field::strings(bool allow_empty) const {
  std::vector<std::string> out;
  for (const Field& entry : elements(allow_empty)) out.push_back(entry.string());
  return out;
}

}  // namespace isospring::io::case_json
