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
/// `outputOption` names the output's own option.
void RefuseOutputOverInput(const std::string& output, const std::string& input, const char* option,
                           const char* outputOption = "--output");

/// Throws UsageError unless `output` ends in `extension` (".json"), the one
/// format `command` writes there (`option` names the option): a wrong name
/// would make the next command read the file as another format and fail.
void RequireOutputExtension(const std::string& output, const char* extension, const char* command,
                            const char* option);

/// Throws io::InputError (kind Output, exit code 4) when `output` cannot be
/// created (a missing or read-only directory, a directory in its place):
/// found before the work instead of after it. Leaves nothing behind.
void CheckWritable(const std::string& output);

/// The checks of a command that inverts `points` onto `geometry` into
/// `output` that need no file read: the output is neither input, its
/// extension names a format the command writes (`trimmed`: the points' own
/// format family; else a result file), and the points' extension is one the
/// command reads. Usage errors throw UsageError, an unknown point format
/// io::InputError (exit code 3).
void CheckInversionPaths(const std::string& geometry, const std::string& points, const std::string& output,
                         bool trimmed);

}  // namespace invmap::cli
