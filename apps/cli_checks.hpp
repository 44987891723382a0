#pragma once
// Option checks with messages a person can read. CLI11's PositiveNumber and NonNegativeNumber
// are ranges up to the largest double and print it with 300 digits ("not in range 0.000000 to
// 179769313486231570814527423731704356798070567525844996598917476803157260780028538760589558632
// 76687817154045895351438246423432132688946418276846754670353751698604991057655128207624549009
// 038932..."); these say what is wrong in one line.
#include <CLI/CLI.hpp>
#include <cmath>
#include <string>

namespace isospring::apps {

inline CLI::Validator number_check(bool allow_zero) {
  return CLI::Validator(
      [allow_zero](std::string& text) -> std::string {
        double value = 0.0;
        try {
          size_t used = 0;
          value = std::stod(text, &used);
          if (used != text.size()) return "'" + text + "' is not a number";
        } catch (const std::exception&) {
          return "'" + text + "' is not a number";
        }
        if (!std::isfinite(value) || value < 0.0 || (!allow_zero && value == 0.0))
          return std::string("must be a ") + (allow_zero ? "non-negative" : "positive") +
                 " finite number, got " + text;
        return {};
      },
      allow_zero ? "NONNEGATIVE" : "POSITIVE");
}

/// > 0 and finite.
inline const CLI::Validator kPositive = number_check(false);
/// >= 0 and finite.
inline const CLI::Validator kNonNegative = number_check(true);

}  // namespace isospring::apps
