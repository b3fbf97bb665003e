#include "cli/path_checks.h"

#include <sys/stat.h>

namespace invmap::cli {

void RefuseOutputOverInput(const std::string& output, const std::string& input, const char* option) {
  // stat follows symbolic links, so a link to the input has its device and
  // inode, as does a hard link or the same file by another spelling.
  struct stat outputFile {}, inputFile {};
  if (::stat(output.c_str(), &outputFile) != 0 || ::stat(input.c_str(), &inputFile) != 0) return;
  if (outputFile.st_dev != inputFile.st_dev || outputFile.st_ino != inputFile.st_ino) return;
  throw UsageError("--output " + output + " is the " + option + " file " + input +
                   ": writing it would destroy the input; choose another output");
}

}  // namespace invmap::cli
