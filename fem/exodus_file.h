// An open Exodus II file, shared by the Lagrange and the Bezier extraction
// readers: the calls they make, each checked, with the file named in every
// error.
#pragma once

#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

namespace invmap::fem {

/// One element block as ex_get_block describes it.
struct ExodusBlock {
  std::int64_t id = 0;
  std::string typeName;
  std::int64_t numElements = 0;
  int nodesPerElement = 0;  ///< Connectivity entries per element.
  std::string name;         ///< The block's name, empty when it has none.
};

/// Opens a file read-only (Exodus's own messages and aborts switched off)
/// and closes it with the object. The Exodus library is not thread-safe:
/// one file is open at a time in the process.
class ExodusFile {
 public:
  explicit ExodusFile(const std::string& path);
  ~ExodusFile();
  ExodusFile(const ExodusFile&) = delete;
  ExodusFile& operator=(const ExodusFile&) = delete;

  const std::string& path() const { return path_; }
  /// The netCDF id of the file (Exodus files are netCDF files), for the
  /// variables the Exodus API of this version cannot read.
  int ncid() const { return id_; }
  int numDim() const { return numDim_; }
  std::int64_t numNodes() const { return numNodes_; }

  /// Node coordinates, 3 per node (z = 0 in 2D files), checked finite.
  std::vector<double> Coordinates() const;
  std::vector<ExodusBlock> Blocks() const;
  /// Connectivity of a block, 1-based node ids as stored.
  std::vector<int> Connectivity(const ExodusBlock& block) const;
  /// Number of time steps.
  int NumTimeSteps() const;
  /// Names of the nodal variables.
  std::vector<std::string> NodalVariableNames() const;
  /// Nodal variable `index` (1-based) at time step `step` (1-based).
  std::vector<double> NodalVariable(int index, int step) const;

  /// Throws InputError "<path>: <what>".
  [[noreturn]] void Fail(const std::string& what) const;

 private:
  std::unique_lock<std::mutex> lock_;
  std::string path_;
  int id_ = -1;
  int numDim_ = 0;
  std::int64_t numNodes_ = 0;
  std::int64_t numElements_ = 0;
  int numBlocks_ = 0;
  double countLimit_ = 0.0;  ///< Bytes the arrays of the file may take (its size, allowing compression).
};

}  // namespace invmap::fem
