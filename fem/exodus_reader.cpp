#include "fem/exodus_reader.h"

#include <map>
#include <memory>

#include "fem/exodus_bex.h"
#include "fem/exodus_elements.h"
#include "fem/exodus_file.h"
#include "fem/lagrange_cells.h"
#include "io/input_error.h"

namespace invmap::fem {
namespace {

/// "element block 7 (HEX20)" for messages.
std::string BlockName(const ExodusBlock& block) {
  return "element block " + std::to_string(block.id) + " (" + block.typeName + ")";
}

/// The time step to read: options.timeStep, or the last one.
int ChooseTimeStep(const ExodusFile& file, const io::FieldReadOptions& options) {
  const int steps = file.NumTimeSteps();
  if (options.timeStep == 0) return steps;
  if (options.timeStep < 1 || options.timeStep > steps) {
    file.Fail("time step " + std::to_string(options.timeStep) + " requested, the file has " + std::to_string(steps) +
              (steps == 1 ? " time step" : " time steps"));
  }
  return static_cast<int>(options.timeStep);
}

}  // namespace

FieldGeometry ReadExodus(const std::string& path, const io::FieldReadOptions& options) {
  const ExodusFile file(path);
  const std::vector<ExodusBlock> blocks = file.Blocks();
  for (const ExodusBlock& block : blocks) {
    if (block.typeName.rfind("BEX_", 0) == 0) return ReadExodusBezierExtraction(file, blocks);
  }
  const std::vector<double> nodes = file.Coordinates();
  std::map<std::string, std::unique_ptr<io::LagrangeToBernstein>> converters;
  std::vector<LagrangePatchBuilder> builders;
  bool anyVolume = false;
  std::vector<std::int64_t> elementNodes;
  for (const ExodusBlock& block : blocks) {
    LagrangePatchBuilder& builder = builders.emplace_back(nodes);
    if (block.numElements == 0) continue;
    ExodusElementType type;
    if (!FindExodusElementType(block.typeName, block.nodesPerElement, &type)) {
      file.Fail(BlockName(block) + ": " + std::to_string(block.nodesPerElement) +
                "-node elements of this type are not read (invmap reads BAR2/3, TRI3/6, QUAD4/8/9, TET4/10, "
                "HEX8/20/27 and WEDGE6/15)");
    }
    std::unique_ptr<io::LagrangeToBernstein>& converter = converters[type.name];
    if (!converter) {
      converter = std::make_unique<io::LagrangeToBernstein>(type.cell, type.degree, ExodusReferenceNodes(type),
                                                            ExodusSerendipityMonomials(type));
    }
    const std::vector<int> connectivity = file.Connectivity(block);
    elementNodes.resize(static_cast<std::size_t>(type.numNodes));
    for (std::int64_t e = 0; e < block.numElements; ++e) {
      for (int j = 0; j < type.numNodes; ++j) {
        const int node = connectivity[static_cast<std::size_t>(e * type.numNodes + j)];
        if (node < 1 || node > file.numNodes()) {
          file.Fail(BlockName(block) + ", element " + std::to_string(e) + " of the block: node " + std::to_string(node) +
                    " out of range [1, " + std::to_string(file.numNodes()) + "]");
        }
        elementNodes[j] = node - 1;
      }
      builder.AddElement(type.cell, type.degree, *converter, elementNodes.data());
    }
    anyVolume = anyVolume || ParamDimOf(type.cell) == 3;
  }
  if (file.numNodes() == 0 || blocks.empty()) file.Fail("no elements");

  FieldGeometry out;
  out.geometry.dimension = GeometryDimension(nodes, anyVolume);
  for (const LagrangePatchBuilder& builder : builders) out.geometry.patches.push_back(builder.MakePatch(out.geometry.dimension));

  const std::vector<std::string> names = file.NodalVariableNames();
  if (names.empty()) return out;
  const int step = ChooseTimeStep(file, options);
  if (step < 1) return out;  // variables declared, none written
  for (std::size_t v = 0; v < names.size(); ++v) {
    const std::vector<double> nodal = file.NodalVariable(static_cast<int>(v) + 1, step);
    NodeField field;
    field.name = names[v].empty() ? "nodal_variable_" + std::to_string(v + 1) : names[v];
    for (const LagrangePatchBuilder& builder : builders) field.patchValues.push_back(builder.ConvertField(nodal, 1));
    out.fields.push_back(std::move(field));
  }
  return out;
}

}  // namespace invmap::fem
