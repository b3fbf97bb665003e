#include "tests/fem/exodus_writer.h"

#include <exodusII.h>

namespace invmap::testing {

bool WriteExodus(const std::string& path, int numDim, const std::vector<double>& xyz,
                 const std::vector<ExodusBlockToWrite>& blocks, const std::vector<ExodusVariableToWrite>& variables,
                 int ioWordSize) {
  ex_opts(EX_DEFAULT);
  int cpuWordSize = 8;
  const int exoid = ex_create(path.c_str(), EX_CLOBBER, &cpuWordSize, &ioWordSize);
  if (exoid < 0) return false;
  const int numNodes = static_cast<int>(xyz.size() / 3);
  int numElements = 0;
  for (const ExodusBlockToWrite& b : blocks) {
    numElements += static_cast<int>(b.connectivity.size()) / (b.nodesPerElement > 0 ? b.nodesPerElement : 1);
  }
  bool ok = ex_put_init(exoid, "invmap test", numDim, numNodes, numElements, static_cast<int>(blocks.size()), 0, 0) >= 0;
  std::vector<double> x(numNodes), y(numNodes), z(numNodes);
  for (int i = 0; i < numNodes; ++i) {
    x[i] = xyz[3 * i];
    y[i] = xyz[3 * i + 1];
    z[i] = xyz[3 * i + 2];
  }
  ok = ok && ex_put_coord(exoid, x.data(), y.data(), z.data()) >= 0;
  for (const ExodusBlockToWrite& b : blocks) {
    const int count = static_cast<int>(b.connectivity.size()) / (b.nodesPerElement > 0 ? b.nodesPerElement : 1);
    ok = ok && ex_put_block(exoid, EX_ELEM_BLOCK, b.id, b.type.c_str(), count, b.nodesPerElement, 0, 0, 0) >= 0;
    if (count > 0) ok = ok && ex_put_conn(exoid, EX_ELEM_BLOCK, b.id, b.connectivity.data(), nullptr, nullptr) >= 0;
    if (!b.name.empty()) ok = ok && ex_put_name(exoid, EX_ELEM_BLOCK, b.id, b.name.c_str()) >= 0;
  }
  if (!variables.empty()) {
    ok = ok && ex_put_variable_param(exoid, EX_NODAL, static_cast<int>(variables.size())) >= 0;
    std::vector<char*> names;
    for (const ExodusVariableToWrite& v : variables) names.push_back(const_cast<char*>(v.name.c_str()));
    ok = ok && ex_put_variable_names(exoid, EX_NODAL, static_cast<int>(names.size()), names.data()) >= 0;
    for (std::size_t step = 0; step < variables[0].steps.size(); ++step) {
      const double time = 0.5 * static_cast<double>(step + 1);
      ok = ok && ex_put_time(exoid, static_cast<int>(step) + 1, &time) >= 0;
      for (std::size_t v = 0; v < variables.size(); ++v) {
        ok = ok && ex_put_var(exoid, static_cast<int>(step) + 1, EX_NODAL, static_cast<int>(v) + 1, 1, numNodes,
                              variables[v].steps[step].data()) >= 0;
      }
    }
  }
  return ex_close(exoid) >= 0 && ok;
}

}  // namespace invmap::testing
