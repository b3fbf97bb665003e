// Checks of numeric option values whose messages name the value given and
// the range in a few words (CLI11's own range checks print the largest
// double in full, 309 digits, and call a word "not in range").
#pragma once

#include <CLI/CLI.hpp>

namespace invmap::cli {

/// A number >= 0.
const CLI::Validator& NonNegativeNumber();

/// A whole number >= 1.
const CLI::Validator& PositiveInteger();

}  // namespace invmap::cli
