// invmap._invmap: the compiled half of the Python package (pybind11). The
// package's __init__.py re-exports it and adds the parts that are plain
// Python (load's dispatch on its argument, from_bspline's axis order).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <fstream>
#include <memory>
#include <new>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "cad/register_readers.h"
#include "fem/register_readers.h"
#include "invmap/fields.h"
#include "invmap/invmap.h"
#include "io/field_geometry_file.h"
#include "io/geometry_file.h"
#include "io/geometry_json.h"
#include "io/geometry_source.h"
#include "io/input_error.h"
#include "python/cad_binding.h"
#include "python/errors.h"
#include "python/fields_binding.h"
#include "python/geometry_state.h"
#include "python/grid_binding.h"
#include "python/numpy_points.h"
#include "python/distance_binding.h"
#include "python/point_files_binding.h"
#include "python/pou_binding.h"
#include "python/py_manifold.h"

namespace py = pybind11;

namespace invmap::python {
namespace {

/// Points Manifold.trim inverts at a time: the chunk `invmap trim` reads.
constexpr std::size_t kTrimChunkPoints = std::size_t{1} << 18;

/// True when `path` names a regular file this process can open, i.e. when a
/// read failure is about the content (InputError), not the file (FileError).
bool IsReadableFile(const std::string& path) {
  std::error_code error;
  return std::filesystem::is_regular_file(path, error) && std::ifstream(path).good();
}

/// invmap.load of a path: ReadGeometryFile, then the build, without the GIL.
PyManifold LoadFile(const std::string& path) {
  py::gil_scoped_release noGil;
  if (IsCadPath(path)) return PyManifold(LoadCad(path), path);
  FieldGeometry model;
  io::GeometrySource source;
  try {
    model = io::ReadGeometryWithFields(path, {}, &source);
  } catch (const io::InputError& e) {
    if (!IsReadableFile(path)) throw FileError(e.what());
    throw InputError(e.what());
  }
  return PyManifold(std::move(model), path, &source);
}

/// invmap.load of JSON text (or a dict, dumped to text by __init__.py).
PyManifold LoadJson(const std::string& text, const std::string& nameForMessages) {
  py::gil_scoped_release noGil;
  std::istringstream in(text);
  Geometry geometry;
  io::GeometrySource source;
  try {
    geometry = io::ReadGeometryJson(in, nameForMessages, &source);
  } catch (const io::InputError& e) {
    throw InputError(e.what());
  }
  return PyManifold(std::move(geometry), nameForMessages, &source);
}

/// Unpickling: rebuilds from PyManifold::state().
PyManifold FromState(const py::bytes& state) {
  const std::string bytes = state;
  py::gil_scoped_release noGil;
  if (IsCadState(bytes)) return PyManifold(LoadCadState(bytes), "pickled CAD model");
  FieldGeometry model;
  try {
    std::string geometryState;
    ParseModel(bytes, &geometryState, &model.fields);
    model.geometry = DeserializeGeometry(geometryState);
  } catch (const std::invalid_argument& e) {
    throw InputError(e.what());
  }
  if (std::string problem = CheckFields(model.geometry, model.fields); !problem.empty()) {
    throw InputError("pickled manifold: " + problem);
  }
  return PyManifold(std::move(model), "pickled manifold");
}

/// The cell type called `name` (invmap/cell_type.h).
CellType ParseCell(const std::string& name) {
  CellType type = CellType::Line;
  if (!ParseCellType(name, &type)) throw InputError("cell: '" + name + "', expected " + kCellTypeNames);
  return type;
}

/// invmap.from_mesh: one mesh patch from numpy vertices and cells.
PyManifold FromMesh(const py::handle& vertices, const py::handle& cells, const std::string& cellName) {
  const CellType cell = ParseCell(cellName);
  const int cellVertices = TraitsOf(cell).vertices;
  const auto vertexArray = RealArray(vertices, "vertices");
  if (vertexArray.ndim() != 2 || (vertexArray.shape(1) != 2 && vertexArray.shape(1) != 3)) {
    throw InputError("vertices: shape " + ShapeText(vertexArray) + ", expected (V, 2) or (V, 3)");
  }
  const py::array cellInput = py::array::ensure(cells);
  // Float indices would be truncated silently by a cast.
  if (!cellInput || (cellInput.dtype().kind() != 'i' && cellInput.dtype().kind() != 'u')) {
    throw InputError("cells: expected an array of integer vertex indices");
  }
  if (cellInput.ndim() != 2 || cellInput.shape(1) != cellVertices) {
    throw InputError("cells: shape " + ShapeText(cellInput) + ", a " + cellName + " cell has " +
                     std::to_string(cellVertices) + " vertices");
  }
  CheckUnsignedIndices(cellInput, "from_mesh: patch 0: cells", vertexArray.shape(0));
  const auto cellArray = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(cellInput);
  Geometry geometry;
  geometry.dimension = static_cast<int>(vertexArray.shape(1));
  Patch& patch = geometry.patches.emplace_back();
  patch.kind = Patch::Kind::Mesh;
  patch.cell = cell;
  patch.points = CopyElements(vertexArray);
  patch.cells = CopyElements(cellArray);
  py::gil_scoped_release noGil;
  return PyManifold(std::move(geometry), "from_mesh");
}

/// invmap.from_bspline, once __init__.py has put the control points (and
/// weights) in file order, u fastest.
PyManifold FromBSpline(const py::handle& controlPoints, const std::vector<int>& counts, const std::vector<int>& degrees,
                       const std::vector<std::vector<double>>& knots, const py::handle& weights) {
  const auto pointArray = RealArray(controlPoints, "control_points");
  if (pointArray.ndim() != 2 || (pointArray.shape(1) != 2 && pointArray.shape(1) != 3)) {
    throw InputError("control_points: shape " + ShapeText(pointArray) + ", expected (N, 2) or (N, 3)");
  }
  Geometry geometry;
  geometry.dimension = static_cast<int>(pointArray.shape(1));
  Patch& patch = geometry.patches.emplace_back();
  patch.kind = Patch::Kind::BSpline;
  patch.degrees = degrees;
  patch.knots = knots;
  patch.counts = counts;
  patch.points = CopyElements(pointArray);
  if (!weights.is_none()) patch.weights = CopyElements(RealArray(weights, "weights"));
  py::gil_scoped_release noGil;
  return PyManifold(geometry, "from_bspline");
}

/// Turns a batch-level error of Manifold::Invert into the Python exception.
void ThrowOnError(Error error, const std::string& message) {
  switch (error) {
    case Error::Ok:
      return;
    case Error::InvalidArgument:
      throw InputError(message);
    case Error::OutOfMemory:
      throw std::bad_alloc();
    case Error::Internal:
      break;
  }
  throw std::runtime_error(message);
}

/// A numpy array that owns `values` (moved, not copied): the capsule frees
/// them with the array.
template <typename T>
py::array Adopt(std::vector<T>&& values, std::vector<py::ssize_t> shape, const py::dtype& dtype) {
  auto owned = std::make_unique<std::vector<T>>(std::move(values));
  py::capsule owner(owned.get(), [](void* p) { delete static_cast<std::vector<T>*>(p); });
  const void* data = owned.release()->data();
  return py::array(dtype, std::move(shape), data, owner);
}

/// The options of invert and trim, validated (None means the default).
InversionOptions MakeOptions(std::optional<double> maxDistance, std::optional<std::int64_t> threads, bool pointwise) {
  InversionOptions options;
  options.pointwise = pointwise;
  if (maxDistance) options.maxDistance = CheckedMaxDistance(*maxDistance);
  if (threads) options.threads = CheckedThreads(*threads);
  return options;
}

/// Inverts `points` with the GIL released; the points are read in place
/// where their layout allows (ReadNumpyPoints).
Results InvertPoints(const PyManifold& self, const py::handle& points, const InversionOptions& options) {
  const NumpyPoints view = ReadNumpyPoints(points, self.dimension());
  Results results;
  std::string message;
  Error error;
  {
    py::gil_scoped_release noGil;
    error = self.manifold().Invert(view.view, options, &results, &message);
  }
  ThrowOnError(error, message);
  return results;
}

/// Results as the dict of numpy arrays Manifold.invert returns (see its docstring).
py::dict ResultsDict(Results&& results, int dim) {
  const auto n = static_cast<py::ssize_t>(results.status.size());
  if (dim == 2) {
    // The engine writes z = 0 in 2D; packing the rows in place (the write
    // index never passes the read index) gives (N, 2) without a copy.
    for (py::ssize_t i = 0; i < n; ++i) {
      results.closest[2 * i] = results.closest[3 * i];
      results.closest[2 * i + 1] = results.closest[3 * i + 1];
    }
    results.closest.resize(2 * n);
  }
  // Status is a uint8 enum holding the codes of docs/formats.md section 5: its vector is the uint8 array.
  static_assert(sizeof(Status) == sizeof(std::uint8_t));
  py::dict out;
  out["status"] = Adopt(std::move(results.status), {n}, py::dtype::of<std::uint8_t>());
  out["patch"] = Adopt(std::move(results.patch), {n}, py::dtype::of<std::int32_t>());
  out["cell"] = Adopt(std::move(results.cell), {n}, py::dtype::of<std::int64_t>());
  out["params"] = Adopt(std::move(results.params), {n, 3}, py::dtype::of<double>());
  out["closest"] = Adopt(std::move(results.closest), {n, dim}, py::dtype::of<double>());
  out["distance"] = Adopt(std::move(results.distance), {n}, py::dtype::of<double>());
  return out;
}

/// The signed distances of the points of `results` (the `signed` option of
/// invert and trim): InputError unless the manifold is a CAD model whose
/// shells are closed.
std::vector<double> Signed(const PyManifold& self, const PointsView& view, const Results& results, int threads) {
  if (!self.cad()) throw InputError("signed: needs a CAD model (.step, .stp, .iges, .igs, .brep) with closed solids");
  const std::size_t n = view.count;
  std::vector<double> xyz(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      xyz[3 * i + k] = view.scalar == Scalar::Float64 ? static_cast<const double*>(view.coord[k])[i * view.stride]
                                                      : static_cast<const float*>(view.coord[k])[i * view.stride];
    }
  }
  py::gil_scoped_release noGil;
  return SignedDistances(*self.cad(), xyz.data(), n, results, threads);
}

/// Manifold.invert: the Results as numpy arrays.
py::dict Invert(const PyManifold& self, const py::handle& points, std::optional<double> maxDistance,
                std::optional<std::int64_t> threads, bool pointwise, bool signedDistance) {
  Results results = InvertPoints(self, points, MakeOptions(maxDistance, threads, pointwise));
  if (!signedDistance) return ResultsDict(std::move(results), self.dimension());
  std::vector<double> sd = Signed(self, ReadNumpyPoints(points, self.dimension()).view, results, threads.value_or(0));
  const auto n = static_cast<py::ssize_t>(sd.size());
  py::dict out = ResultsDict(std::move(results), self.dimension());
  out["signed_distance"] = Adopt(std::move(sd), {n}, py::dtype::of<double>());
  return out;
}

/// Manifold.probe: Manifold.invert's dict with "fields" added.
py::dict Probe(const PyManifold& self, const py::handle& points, const std::optional<std::vector<std::string>>& names,
               std::optional<double> maxDistance, std::optional<std::int64_t> threads) {
  const InversionOptions options = MakeOptions(maxDistance, threads, false);
  Results results = InvertPoints(self, points, options);
  py::dict fields = ProbeFieldsDict(self.fields(), results, names, options.threads);
  py::dict out = ResultsDict(std::move(results), self.dimension());
  out["fields"] = fields;
  return out;
}

/// Manifold.trim: the mask of the points `invmap trim` keeps.
/// Rows [first, first + count) of `view`.
PointsView Rows(PointsView view, std::size_t first, std::size_t count) {
  const std::size_t bytes = view.scalar == Scalar::Float64 ? sizeof(double) : sizeof(float);
  for (int k = 0; k < view.dim; ++k) {
    view.coord[k] = static_cast<const char*>(view.coord[k]) + first * view.stride * bytes;
  }
  view.count = count;
  return view;
}

py::array_t<bool> Trim(const PyManifold& self, const py::handle& points, double maxDistance, const std::string& keep,
                       bool pointwise, bool signedDistance) {
  if (keep != "near" && keep != "far") throw InputError("keep: '" + keep + "', expected 'near' or 'far'");
  const bool keepFar = keep == "far";
  InversionOptions options = MakeOptions(maxDistance, std::nullopt, pointwise);
  // As `invmap trim --signed`: near is at most max_distance outside (the
  // inside however deep), so every point needs its side.
  if (signedDistance) options.maxDistance = std::numeric_limits<double>::infinity();
  const NumpyPoints all = ReadNumpyPoints(points, self.dimension());
  py::array_t<bool> mask(static_cast<py::ssize_t>(all.view.count));
  bool* out = mask.mutable_data();
  // The points go in the command's chunks: the same answers as `invmap
  // trim`, and the results of one chunk at a time in memory, whatever the
  // number of points.
  for (std::size_t first = 0; first < all.view.count; first += kTrimChunkPoints) {
    const PointsView chunk = Rows(all.view, first, std::min(kTrimChunkPoints, all.view.count - first));
    Results results;
    std::string message;
    Error error;
    {
      py::gil_scoped_release noGil;
      error = self.manifold().Invert(chunk, options, &results, &message);
    }
    ThrowOnError(error, message);
    if (signedDistance) {
      const std::vector<double> sd = Signed(self, chunk, results, 0);
      for (std::size_t i = 0; i < chunk.count; ++i) {
        out[first + i] = !std::isnan(sd[i]) && (keepFar ? sd[i] > maxDistance : sd[i] <= maxDistance);
      }
      continue;
    }
    // As `invmap trim`: Found means within max_distance, None beyond it;
    // invalid points have no distance and are in neither set.
    for (std::size_t i = 0; i < chunk.count; ++i) {
      out[first + i] = results.status[i] == (keepFar ? Status::None : Status::Found);
    }
  }
  return mask;
}

/// Manifold.info: ManifoldInfo as a dict.
py::dict Info(const PyManifold& self) {
  const ManifoldInfo info = self.manifold().Info();
  py::dict shapes;
  for (const auto& [shape, count] : info.cellsByShape) shapes[py::str(shape)] = count;
  py::list lo, hi;
  for (int k = 0; k < info.dimension; ++k) {
    lo.append(info.boundsLo[k]);
    hi.append(info.boundsHi[k]);
  }
  py::dict out;
  out["dimension"] = info.dimension;
  out["patches"] = info.patches;
  out["cells"] = info.cells;
  out["cells_by_shape"] = shapes;
  out["bounds_lo"] = py::tuple(lo);
  out["bounds_hi"] = py::tuple(hi);
  out["memory_bytes"] = info.memoryBytes;
  if (self.cad()) out["cad"] = CadInfo(*self.cad());
  return out;
}

}  // namespace
}  // namespace invmap::python

PYBIND11_MODULE(_invmap, m) {
  using namespace invmap::python;
  invmap::fem::RegisterFemReaders();
  invmap::cad::RegisterCadReaders();
  m.doc() = "Compiled core of the invmap package; use `import invmap`.";
  m.attr("__version__") = invmap::Version();

  py::register_exception<InputError>(
      m, "InputError", PyExc_ValueError)
      .doc() = "Invalid input: a malformed geometry, points of the wrong shape or type, or bad options. "
               "The message is the one the invmap command prints after 'invmap: '.";
  py::register_exception<FileError>(m, "FileError", PyExc_OSError).doc() =
      "A geometry file that cannot be read (missing, a directory, no permission), with the command line's message.";

  py::class_<PyManifold>(m, "Manifold", R"doc(
An immutable geometry ready for queries: its cells and their BVH, built once.

Made by invmap.load, invmap.from_mesh or invmap.from_bspline. Thread-safe:
invert releases the GIL, so several Python threads may query one manifold
at once. Pickling sends the geometry itself (never a file path); unpickling
rebuilds the BVH.
)doc")
      .def_property_readonly("dimension", &PyManifold::dimension, "Ambient dimension, 2 or 3.")
      .def("info", &Info, R"doc(
Counts describing the manifold, as `invmap info` prints them.

Returns a dict: dimension (int), patches (int), cells (int), cells_by_shape
(dict such as {"quad 3x3": 1024}), bounds_lo and bounds_hi (tuples of
`dimension` floats) and memory_bytes (heap memory of cells, bounds and BVH). A CAD model adds "cad": format, faces,
faces_by_surface, edges, vertices, shells, solids, open_parts,
approximated_faces, approximation_tolerance, approximation_deviation,
model_bounds_lo and model_bounds_hi, as `invmap info` prints them.
)doc")
      .def("invert", &Invert, py::arg("points"), py::arg("max_distance") = py::none(),
           py::arg("threads") = py::none(), py::arg("pointwise") = false, py::arg("signed") = false, R"doc(
Closest point, cell and parameters of every query point.

points: (N, dimension) array-like. float32 and float64 arrays are read in
  place whatever their strides; other real types are converted to float64.
max_distance: gap tolerance; points farther than this from every cell get
  status 1 (none). Default: unlimited.
threads: worker threads, default (None or 0) all cores. Results do not
  depend on it.
pointwise: each answer a function of its point and the geometry only, bit
  for bit whatever batch or chunk the point comes in (by default a point's
  solve starts from its neighbour's answer: the same minimum, but the last
  digits depend on the batch). Slower; see docs/limitations.md.
signed: CAD models with closed solids only: also return signed_distance,
  negative inside a solid (InputError naming the open shell otherwise).

Returns a dict of numpy arrays, one row per point in input order:
  status   (N,) uint8: 0 found, 1 none, 2 invalid (NaN or infinite input)
  patch    (N,) int32, -1 when not found
  cell     (N,) int64, cell index within the patch, -1 when not found
  params   (N, 3) float64: knot values (B-spline) or reference coordinates
           (Bezier, mesh); NaN where the cell has fewer parameters
  closest  (N, dimension) float64, NaN when not found
  distance (N,) float64, NaN when not found
  signed_distance (N,) float64, with signed=True
CAD models (invmap.load of .step, .iges, .brep): patch is the face in
OpenCascade's face-map order, params the face surface's own (u, v)
(docs/cad.md). The GIL is released while the engine works.

Raises InputError for points of the wrong shape or type and for bad options.
)doc")
      .def("probe", &Probe, py::arg("points"), py::arg("names") = py::none(), py::arg("max_distance") = py::none(),
           py::arg("threads") = py::none(), R"doc(
The node fields of the geometry at the closest point of every query point
(as `invmap probe`; docs/fields.md).

points, max_distance, threads: as invert. names: the fields to give, in
order (default: every field of the file: gmsh $NodeData views, VTU point
data arrays, Exodus nodal variables).

Returns invert's dict plus "fields": {name: array}, (N,) for a scalar and
(N, components) for a vector or tensor, each field interpolated with its
cell's basis at the found parameters; NaN where the point is not found.
Raises InputError for an unknown name or a manifold without fields.
)doc")
      .def_property_readonly("fields", [](const PyManifold& self) { return FieldComponents(self.fields()); },
                             "The node fields the manifold carries: {name: components}.")
      .def("trim", &Trim, py::arg("points"), py::arg("max_distance"), py::arg("keep") = "near",
           py::arg("pointwise") = false, py::arg("signed") = false, R"doc(
Boolean mask of the points `invmap trim` keeps: those within max_distance
of the geometry (keep="near") or beyond it (keep="far"). Points with NaN or
infinite coordinates are in neither set. pointwise: as in invert.
signed=True (CAD solids): near is a signed distance <= max_distance (inside
the solid, however deep, or at most max_distance outside), far the rest.
)doc")
      .def("__repr__",
           [](const PyManifold& self) {
             return "<invmap.Manifold dimension=" + std::to_string(self.dimension()) +
                    " patches=" + std::to_string(self.patches()) + " cells=" + std::to_string(self.cells()) + ">";
           })
      .def(py::pickle([](const PyManifold& self) { return py::bytes(self.state()); }, &FromState))
      // Every pickle protocol (and copy) goes through __reduce__ once it is
      // defined: protocols 0 and 1 otherwise rebuild through object.__new__,
      // which a pybind11 class does not allow (the interpreter aborted).
      .def("__reduce__", [](const PyManifold& self) {
        return py::make_tuple(py::module_::import("invmap").attr("_unpickle_manifold"),
                              py::make_tuple(py::bytes(self.state())));
      });

  m.def("_manifold_from_state", &FromState, py::arg("state"),
        "Rebuilds a manifold from its pickled state (see invmap._unpickle_manifold).");
  m.def("_load_file", &LoadFile, py::arg("path"), "Reads and builds a geometry file (see invmap.load).");
  m.def("_load_json", &LoadJson, py::arg("text"), py::arg("name"),
        "Reads and builds geometry JSON text; messages name it `name` (see invmap.load).");
  m.def("from_mesh", &FromMesh, py::arg("vertices"), py::arg("cells"), py::arg("cell") = "tri", R"doc(
A manifold of linear cells sharing vertices (a "mesh" patch, docs/formats.md section 2).

vertices: (V, 2) or (V, 3) real array; the geometry's dimension follows.
cells: (C, k) integer array of 0-based vertex indices in finite-element order,
  k fixed by the cell type (line 2, tri 3, quad 4, tet 4, hex 8, wedge 6).
cell: "line", "tri", "quad", "tet", "hex" or "wedge".
Reported parameters are the cells' reference coordinates.

Raises InputError for a malformed mesh, e.g. an out-of-range vertex index.
)doc");
  m.def("_from_bspline", &FromBSpline, py::arg("control_points"), py::arg("counts"), py::arg("degrees"),
        py::arg("knots"), py::arg("weights"),
        "One B-spline patch from control points in file order, u fastest (see invmap.from_bspline).");
  RegisterGrid(m);
  RegisterDistance(m);
  RegisterPointFiles(m);
  RegisterPou(m);
}
