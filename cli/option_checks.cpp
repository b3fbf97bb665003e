#include "cli/option_checks.h"

#include <cmath>
#include <string>

namespace invmap::cli {

const CLI::Validator& NonNegativeNumber() {
  static const CLI::Validator check(
      [](const std::string& text) {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value) || !(value >= 0.0)) return "'" + text + "' is not a number >= 0";
        return std::string();
      },
      "NUMBER >= 0");
  return check;
}

const CLI::Validator& PositiveInteger() {
  static const CLI::Validator check(
      [](const std::string& text) {
        long long value = 0;
        if (!CLI::detail::lexical_cast(text, value) || value < 1) return "'" + text + "' is not a whole number >= 1";
        return std::string();
      },
      "INTEGER >= 1");
  return check;
}

}  // namespace invmap::cli
