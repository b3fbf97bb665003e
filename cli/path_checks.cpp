#include "cli/path_checks.h"

#include <sys/stat.h>

#include "io/file_io.h"
#include "io/point_reader.h"
#include "io/result_writer.h"

namespace invmap::cli {

void RefuseOutputOverInput(const std::string& output, const std::string& input, const char* option,
                           const char* outputOption) {
  // stat follows symbolic links, so a link to the input has its device and
  // inode, as does a hard link or the same file by another spelling.
  struct stat outputFile {}, inputFile {};
  if (::stat(output.c_str(), &outputFile) != 0 || ::stat(input.c_str(), &inputFile) != 0) return;
  if (outputFile.st_dev != inputFile.st_dev || outputFile.st_ino != inputFile.st_ino) return;
  throw UsageError(std::string(outputOption) + " " + output + " is the " + option + " file " + input +
                   ": writing it would destroy the input; choose another output");
}

void RequireOutputExtension(const std::string& output, const char* extension, const char* command,
                            const char* option) {
  if (io::LowerExtension(output) == extension) return;
  throw UsageError(std::string(option) + " " + output + ": " + command + " writes " + extension + " files (name it *" +
                   extension + ")");
}

void CheckWritable(const std::string& output) {
  // The temporary file AtomicOutput creates beside the target is removed
  // again when it goes out of scope uncommitted.
  io::AtomicOutput probe(output);
}

void CheckInversionPaths(const std::string& geometry, const std::string& points, const std::string& output,
                         bool trimmed) {
  RefuseOutputOverInput(output, points, "--points");
  RefuseOutputOverInput(output, geometry, "--geometry");
  const io::PointFormat pointFormat = io::PointFormatOf(points);
  if (trimmed) {
    io::PointFormat outputFormat;
    if (!io::IsPointFileName(output, &outputFormat) || outputFormat != pointFormat) {
      throw UsageError("--output " + output + ": trim writes the points' own format, give it the extension of " +
                       points);
    }
  } else if (!io::IsResultFileName(output)) {
    throw UsageError("--output " + output + ": unknown result file extension '" + io::LowerExtension(output) +
                     "' (expected .csv, .ply or .npy)");
  }
}

}  // namespace invmap::cli
