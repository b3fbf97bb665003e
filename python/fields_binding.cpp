#include "python/fields_binding.h"

#include <pybind11/numpy.h>

#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "python/byte_state.h"
#include "python/errors.h"

namespace py = pybind11;

namespace invmap::python {
namespace {

/// "invmapF" plus the format version: a state with fields.
constexpr char kModelMagic[8] = {'i', 'n', 'v', 'm', 'a', 'p', 'F', '1'};

}  // namespace

std::string SerializeModel(const std::string& geometryState, const std::vector<NodeField>& fields) {
  if (fields.empty()) return geometryState;
  std::string out(kModelMagic, sizeof kModelMagic);
  StateWriter w(&out);
  w.Vector(std::vector<char>(geometryState.begin(), geometryState.end()));
  w.Value<std::uint64_t>(fields.size());
  for (const NodeField& field : fields) {
    w.Vector(std::vector<char>(field.name.begin(), field.name.end()));
    w.Value<std::int32_t>(field.components);
    w.Value<std::uint64_t>(field.patchValues.size());
    for (const std::vector<double>& values : field.patchValues) w.Vector(values);
  }
  return out;
}

void ParseModel(const std::string& state, std::string* geometryState, std::vector<NodeField>* fields) {
  fields->clear();
  if (state.size() < sizeof kModelMagic || std::memcmp(state.data(), kModelMagic, sizeof kModelMagic) != 0) {
    *geometryState = state;
    return;
  }
  StateReader r(state.data() + sizeof kModelMagic, state.size() - sizeof kModelMagic, "manifold state");
  const std::vector<char> geometry = r.Vector<char>();
  geometryState->assign(geometry.begin(), geometry.end());
  const std::uint64_t count = r.Value<std::uint64_t>();
  for (std::uint64_t f = 0; f < count; ++f) {
    NodeField field;
    const std::vector<char> name = r.Vector<char>();
    field.name.assign(name.begin(), name.end());
    field.components = r.Value<std::int32_t>();
    if (field.components < 1) throw std::invalid_argument("manifold state: bad field components");
    const std::uint64_t patches = r.Value<std::uint64_t>();
    for (std::uint64_t p = 0; p < patches; ++p) field.patchValues.push_back(r.Vector<double>());
    fields->push_back(std::move(field));
  }
  if (!r.AtEnd()) throw std::invalid_argument("manifold state: unexpected bytes after the fields");
}

py::dict ProbeFieldsDict(const FieldGeometry* model, const Results& results,
                         const std::optional<std::vector<std::string>>& names, int threads) {
  if (model == nullptr || model->fields.empty()) {
    throw InputError("probe: this manifold has no node fields (they come from gmsh $NodeData, VTU point data and "
                     "Exodus nodal variables)");
  }
  std::vector<const NodeField*> selected;
  if (!names) {
    for (const NodeField& field : model->fields) selected.push_back(&field);
  } else {
    for (const std::string& name : *names) {
      const NodeField* found = nullptr;
      for (const NodeField& field : model->fields) {
        if (field.name == name) found = &field;
      }
      if (found == nullptr) {
        std::string known;
        for (const NodeField& field : model->fields) known += (known.empty() ? "" : ", ") + field.name;
        throw InputError("probe: no field '" + name + "' (the fields: " + known + ")");
      }
      selected.push_back(found);
    }
  }
  std::vector<double> values;
  std::string message;
  Error error;
  {
    py::gil_scoped_release noGil;
    error = ProbeFields(model->geometry, selected, results, &values, &message, threads);
  }
  if (error != Error::Ok) throw std::runtime_error(message);
  const auto n = static_cast<py::ssize_t>(results.status.size());
  const std::size_t width = static_cast<std::size_t>(FieldWidth(selected));
  py::dict out;
  std::size_t column = 0;
  for (const NodeField* field : selected) {
    const py::ssize_t components = field->components;
    py::array_t<double> array = components == 1 ? py::array_t<double>(n) : py::array_t<double>({n, components});
    double* data = array.mutable_data();
    for (py::ssize_t i = 0; i < n; ++i) {
      for (py::ssize_t k = 0; k < components; ++k) data[i * components + k] = values[i * width + column + k];
    }
    out[py::str(field->name)] = array;
    column += static_cast<std::size_t>(components);
  }
  return out;
}

py::dict FieldComponents(const FieldGeometry* model) {
  py::dict out;
  if (model == nullptr) return out;
  for (const NodeField& field : model->fields) out[py::str(field.name)] = field.components;
  return out;
}

}  // namespace invmap::python
