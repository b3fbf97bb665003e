#include "python/fields_binding.h"

#include <pybind11/numpy.h>

#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "python/errors.h"

namespace py = pybind11;

namespace invmap::python {
namespace {

/// "invmapF" plus the format version: a state with fields.
constexpr char kModelMagic[8] = {'i', 'n', 'v', 'm', 'a', 'p', 'F', '1'};

void AppendBytes(std::string* out, const void* data, std::size_t bytes) {
  out->append(static_cast<const char*>(data), bytes);
}

void AppendSize(std::string* out, std::uint64_t value) { AppendBytes(out, &value, sizeof value); }

/// Reads what the Append functions wrote, checking every length.
class StateReader {
 public:
  explicit StateReader(const std::string& state) : data_(state.data()), left_(state.size()) {}
  std::uint64_t Size() {
    std::uint64_t value = 0;
    Take(&value, sizeof value);
    return value;
  }
  std::string Bytes(std::uint64_t count) {
    if (count > left_) throw std::invalid_argument("manifold state: truncated");
    std::string bytes(data_, static_cast<std::size_t>(count));
    data_ += count;
    left_ -= static_cast<std::size_t>(count);
    return bytes;
  }
  std::vector<double> Doubles() {
    const std::uint64_t count = Size();
    if (count > left_ / sizeof(double)) throw std::invalid_argument("manifold state: truncated");
    std::vector<double> values(static_cast<std::size_t>(count));
    Take(values.data(), values.size() * sizeof(double));
    return values;
  }
  bool AtEnd() const { return left_ == 0; }

 private:
  void Take(void* out, std::size_t bytes) {
    if (bytes > left_) throw std::invalid_argument("manifold state: truncated");
    if (bytes) std::memcpy(out, data_, bytes);
    data_ += bytes;
    left_ -= bytes;
  }
  const char* data_;
  std::size_t left_;
};

}  // namespace

std::string SerializeModel(const std::string& geometryState, const std::vector<NodeField>& fields) {
  if (fields.empty()) return geometryState;
  std::string out(kModelMagic, sizeof kModelMagic);
  AppendSize(&out, geometryState.size());
  out += geometryState;
  AppendSize(&out, fields.size());
  for (const NodeField& field : fields) {
    AppendSize(&out, field.name.size());
    out += field.name;
    AppendSize(&out, static_cast<std::uint64_t>(field.components));
    AppendSize(&out, field.patchValues.size());
    for (const std::vector<double>& values : field.patchValues) {
      AppendSize(&out, values.size());
      AppendBytes(&out, values.data(), values.size() * sizeof(double));
    }
  }
  return out;
}

void ParseModel(const std::string& state, std::string* geometryState, std::vector<NodeField>* fields) {
  fields->clear();
  if (state.size() < sizeof kModelMagic || std::memcmp(state.data(), kModelMagic, sizeof kModelMagic) != 0) {
    *geometryState = state;
    return;
  }
  const std::string body = state.substr(sizeof kModelMagic);
  StateReader r(body);
  *geometryState = r.Bytes(r.Size());
  const std::uint64_t count = r.Size();
  for (std::uint64_t f = 0; f < count; ++f) {
    NodeField field;
    field.name = r.Bytes(r.Size());
    const std::uint64_t components = r.Size();
    if (components < 1 || components > 1000) throw std::invalid_argument("manifold state: bad field components");
    field.components = static_cast<int>(components);
    const std::uint64_t patches = r.Size();
    for (std::uint64_t p = 0; p < patches; ++p) field.patchValues.push_back(r.Doubles());
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
