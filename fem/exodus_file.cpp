#include "fem/exodus_file.h"

#include <exodusII.h>

#include <cmath>
#include <filesystem>

#include "fem/file_checks.h"
#include "fem/netcdf_header.h"
#include "io/input_error.h"

namespace invmap::fem {
namespace {

std::mutex& ExodusMutex() {
  static std::mutex mutex;
  return mutex;
}

/// A name as Exodus stores it: fixed-size, NUL-padded, maybe space-padded.
std::string Trimmed(const char* text) {
  std::string s(text);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\0')) s.pop_back();
  return s;
}

}  // namespace

ExodusFile::ExodusFile(const std::string& path) : lock_(ExodusMutex()), path_(path) {
  RequireReadableFile(path);
  if (std::string problem = CheckNetcdfHeader(path); !problem.empty()) Fail("not an Exodus II file: " + problem);
  // The library's defaults print to stderr and may abort the process on
  // errors; a reader reports them instead.
  ex_opts(EX_DEFAULT);
  int cpuWordSize = 8;
  int ioWordSize = 0;
  float version = 0.0f;
  id_ = ex_open(path.c_str(), EX_READ, &cpuWordSize, &ioWordSize, &version);
  if (id_ < 0) Fail("not an Exodus II file (the Exodus library cannot open it)");
  // A throw from here on skips the destructor: close the file first.
  const auto closeAndFail = [&](const std::string& what) {
    ex_close(id_);
    id_ = -1;
    Fail(what);
  };
  char title[MAX_LINE_LENGTH + 1] = {};
  int numDim = 0, numNodes = 0, numElements = 0, numBlocks = 0, numNodeSets = 0, numSideSets = 0;
  if (ex_get_init(id_, title, &numDim, &numNodes, &numElements, &numBlocks, &numNodeSets, &numSideSets) < 0) {
    closeAndFail("cannot read the Exodus header (ex_get_init)");
  }
  if (numDim < 1 || numDim > 3) closeAndFail("dimension " + std::to_string(numDim) + " is not 1, 2 or 3");
  if (numNodes < 0 || numElements < 0 || numBlocks < 0) closeAndFail("negative counts in the header");
  // Arrays are sized by these counts: a count the file cannot hold (even
  // compressed a thousandfold) is a corrupt header, not an allocation.
  std::error_code error;
  const double bytes = static_cast<double>(std::filesystem::file_size(path, error));
  const double limit = countLimit_ = 1000.0 * bytes + 1e6;
  if (8.0 * numNodes * numDim > limit || 4.0 * numElements > limit || 8.0 * numBlocks > limit) {
    closeAndFail("the header's counts (" + std::to_string(numNodes) + " nodes, " + std::to_string(numElements) +
                 " elements, " + std::to_string(numBlocks) + " blocks) do not fit a file of this size");
  }
  numDim_ = numDim;
  numNodes_ = numNodes;
  numElements_ = numElements;
  numBlocks_ = numBlocks;
}

ExodusFile::~ExodusFile() {
  if (id_ >= 0) ex_close(id_);
}

void ExodusFile::Fail(const std::string& what) const { throw io::InputError(path_, 0, what); }

std::vector<double> ExodusFile::Coordinates() const {
  const std::size_t n = static_cast<std::size_t>(numNodes_);
  std::vector<double> x(n, 0.0), y(n, 0.0), z(n, 0.0);
  if (n > 0 && ex_get_coord(id_, x.data(), numDim_ > 1 ? y.data() : nullptr, numDim_ > 2 ? z.data() : nullptr) < 0) {
    Fail("cannot read the node coordinates");
  }
  std::vector<double> xyz(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    xyz[3 * i] = x[i];
    xyz[3 * i + 1] = y[i];
    xyz[3 * i + 2] = z[i];
    if (!std::isfinite(x[i]) || !std::isfinite(y[i]) || !std::isfinite(z[i])) {
      Fail("node " + std::to_string(i + 1) + " has a coordinate that is not finite");
    }
  }
  return xyz;
}

std::vector<ExodusBlock> ExodusFile::Blocks() const {
  std::vector<int> ids(static_cast<std::size_t>(numBlocks_));
  if (numBlocks_ > 0 && ex_get_ids(id_, EX_ELEM_BLOCK, ids.data()) < 0) Fail("cannot read the element block ids");
  std::vector<ExodusBlock> blocks;
  std::int64_t total = 0;
  for (const int id : ids) {
    char type[MAX_STR_LENGTH + 1] = {};
    int numElements = 0, nodesPer = 0, edgesPer = 0, facesPer = 0, attributes = 0;
    if (ex_get_block(id_, EX_ELEM_BLOCK, id, type, &numElements, &nodesPer, &edgesPer, &facesPer, &attributes) < 0) {
      Fail("element block " + std::to_string(id) + ": cannot read its description");
    }
    ExodusBlock block;
    block.id = id;
    block.typeName = Trimmed(type);
    block.numElements = numElements;
    block.nodesPerElement = nodesPer;
    if (numElements < 0 || nodesPer < 0) Fail("element block " + std::to_string(id) + ": negative counts");
    if (4.0 * numElements * nodesPer > countLimit_) {
      Fail("element block " + std::to_string(id) + ": " + std::to_string(numElements) + " elements of " +
           std::to_string(nodesPer) + " nodes do not fit a file of this size");
    }
    total += numElements;
    char name[MAX_STR_LENGTH + 1] = {};
    if (ex_get_name(id_, EX_ELEM_BLOCK, id, name) >= 0) block.name = Trimmed(name);
    blocks.push_back(std::move(block));
  }
  if (total != numElements_) {
    Fail("the blocks hold " + std::to_string(total) + " elements, the header says " + std::to_string(numElements_));
  }
  return blocks;
}

std::vector<int> ExodusFile::Connectivity(const ExodusBlock& block) const {
  std::vector<int> nodes(static_cast<std::size_t>(block.numElements) * static_cast<std::size_t>(block.nodesPerElement));
  if (!nodes.empty() && ex_get_conn(id_, EX_ELEM_BLOCK, block.id, nodes.data(), nullptr, nullptr) < 0) {
    Fail("element block " + std::to_string(block.id) + ": cannot read its connectivity");
  }
  return nodes;
}

int ExodusFile::NumTimeSteps() const { return static_cast<int>(ex_inquire_int(id_, EX_INQ_TIME)); }

std::vector<std::string> ExodusFile::NodalVariableNames() const {
  int count = 0;
  if (ex_get_variable_param(id_, EX_NODAL, &count) < 0 || count < 0) Fail("cannot read the nodal variable count");
  std::vector<std::vector<char>> storage(static_cast<std::size_t>(count), std::vector<char>(MAX_STR_LENGTH + 1, '\0'));
  std::vector<char*> pointers;
  for (auto& s : storage) pointers.push_back(s.data());
  if (count > 0 && ex_get_variable_names(id_, EX_NODAL, count, pointers.data()) < 0) {
    Fail("cannot read the nodal variable names");
  }
  std::vector<std::string> names;
  for (const auto& s : storage) names.push_back(Trimmed(s.data()));
  return names;
}

std::vector<double> ExodusFile::NodalVariable(int index, int step) const {
  std::vector<double> values(static_cast<std::size_t>(numNodes_));
  if (numNodes_ > 0 && ex_get_var(id_, step, EX_NODAL, index, 1, numNodes_, values.data()) < 0) {
    Fail("cannot read nodal variable " + std::to_string(index) + " at time step " + std::to_string(step));
  }
  return values;
}

}  // namespace invmap::fem
