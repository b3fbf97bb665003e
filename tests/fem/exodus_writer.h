// Writes Exodus II test files with the Exodus library's own writer
// (ex_create, ex_put_*), as solvers and Cubit write them.
#pragma once

#include <string>
#include <vector>

namespace invmap::testing {

/// One element block to write.
struct ExodusBlockToWrite {
  int id = 1;
  std::string type;        ///< Exodus element type name, e.g. "HEX20".
  int nodesPerElement = 0;
  std::vector<int> connectivity;  ///< 1-based node ids, element-major.
  std::string name;
};

/// A nodal variable: its name and one array of node values per time step.
struct ExodusVariableToWrite {
  std::string name;
  std::vector<std::vector<double>> steps;
};

/// Writes `path`: `numDim` coordinates per node from `xyz` (3 per node),
/// the blocks, and the nodal variables at times 0.5, 1.0, 1.5, ...
/// `ioWordSize`: 8 stores doubles, 4 floats. Returns false when the
/// library reports an error.
bool WriteExodus(const std::string& path, int numDim, const std::vector<double>& xyz,
                 const std::vector<ExodusBlockToWrite>& blocks, const std::vector<ExodusVariableToWrite>& variables,
                 int ioWordSize = 8);

}  // namespace invmap::testing
