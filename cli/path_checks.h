// Checks of a command's file arguments that need no file read, made before
// any work so that a usage mistake costs nothing and destroys nothing.
#pragma once

#include <stdexcept>
#include <string>

namespace invmap::cli {

/// A mistake in the command line itself (exit code 2), found after parsing.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Throws UsageError when `output` is the file `input` names (`option`, such
/// as "--points", says which), by any path: the same name, another spelling
/// of it, a hard link or a symbolic link to it. Writing the output would
/// replace that input. Nothing to check when either does not exist yet.
void RefuseOutputOverInput(const std::string& output, const std::string& input, const char* option);

/// The checks of a command that inverts `points` onto `geometry` into
/// `output` that need no file read: the output is neither input, its
/// extension names a format the command writes (`trimmed`: the points' own
/// format family; else a result file), and the points' extension is one the
/// command reads. Usage errors throw UsageError, an unknown point format
/// io::InputError (exit code 3).
void CheckInversionPaths(const std::string& geometry, const std::string& points, const std::string& output,
                         bool trimmed);

}  // namespace invmap::cli
