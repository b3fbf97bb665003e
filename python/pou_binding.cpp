// invmap.manifold and Manifold.chart_points: partition-of-unity surfaces from
// Python (docs/manifold.md, docs/python.md).
#include "python/pou_binding.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "invmap/pou.h"
#include "python/errors.h"
#include "python/numpy_points.h"
#include "python/py_manifold.h"

namespace py = pybind11;

namespace invmap::python {
namespace {

PouBase ParseBase(const std::string& base) {
  if (base == "flat") return PouBase::Flat;
  if (base == "pn") return PouBase::PnTriangles;
  if (base == "loop") return PouBase::Loop;
  throw InputError("base: '" + base + "', expected flat, pn or loop");
}

PyManifold BuildManifold(const py::handle& vertices, const py::handle& triangles, const std::string& base,
                         std::optional<int> degree) {
  PouOptions options;
  options.base = ParseBase(base);
  if (degree) {
    if (*degree < 1 || *degree > 8) throw InputError("degree: " + std::to_string(*degree) + ", expected 1 to 8");
    options.degree = *degree;
  }
  const auto vertexArray = RealArray(vertices, "vertices");
  if (vertexArray.ndim() != 2 || vertexArray.shape(1) != 3) {
    throw InputError("vertices: shape " + ShapeText(vertexArray) + ", expected (V, 3)");
  }
  const auto triangleArray = IndexArray(triangles, "triangles");
  if (triangleArray.ndim() != 2 || triangleArray.shape(1) != 3) {
    throw InputError("triangles: shape " + ShapeText(triangleArray) + ", expected (T, 3)");
  }
  CheckUnsignedIndices(py::array::ensure(triangles), "manifold: triangles", vertexArray.shape(0));
  const std::vector<double> xyz = CopyElements(vertexArray);
  const std::vector<std::int64_t> corners = CopyElements(triangleArray);
  py::gil_scoped_release noGil;
  Geometry geometry;
  geometry.dimension = 3;
  Patch& patch = geometry.patches.emplace_back();
  const std::string error = BuildPouManifold(xyz.data(), static_cast<std::int64_t>(xyz.size() / 3), corners.data(),
                                             static_cast<std::int64_t>(corners.size() / 3), options, &patch);
  if (!error.empty()) throw InputError("manifold: " + error);
  return PyManifold(geometry, "manifold");
}

py::object ChartPoints(const PyManifold& self, const py::handle& cells, const py::handle& uv, bool derivatives,
                       int patch) {
  const PouCharts* charts = patch >= 0 ? self.charts(static_cast<std::size_t>(patch)) : nullptr;
  if (!charts) throw InputError("patch " + std::to_string(patch) + ": not a pou_manifold patch");
  const auto cellArray = IndexArray(cells, "cells");
  const auto uvArray = RealArray(uv, "uv");
  if (cellArray.ndim() != 1) throw InputError("cells: shape " + ShapeText(cellArray) + ", expected (N,)");
  if (uvArray.ndim() != 2 || uvArray.shape(0) != cellArray.shape(0) || uvArray.shape(1) != 2) {
    throw InputError("uv: shape " + ShapeText(uvArray) + ", expected (" + std::to_string(cellArray.shape(0)) + ", 2)");
  }
  const py::ssize_t n = cellArray.shape(0);
  const std::int64_t* chart = cellArray.data();
  for (py::ssize_t i = 0; i < n; ++i) {
    if (chart[i] < 0 || chart[i] >= charts->NumCharts()) {
      throw InputError("cells[" + std::to_string(i) + "]: chart " + std::to_string(chart[i]) +
                       " does not exist (the patch has charts 0 to " + std::to_string(charts->NumCharts() - 1) +
                       ")");
    }
  }
  const char* names[] = {"point", "du", "dv", "duu", "duv", "dvv"};
  const int outputs = derivatives ? 6 : 1;
  std::vector<py::array_t<double>> out;
  for (int k = 0; k < outputs; ++k) out.emplace_back(std::vector<py::ssize_t>{n, 3});
  std::vector<double*> data;
  for (auto& array : out) data.push_back(array.mutable_data());
  const double* at = uvArray.data();
  {
    py::gil_scoped_release noGil;
    for (py::ssize_t i = 0; i < n; ++i) {
      ChartJet jet;
      const bool inside = charts->Evaluate(chart[i], at[2 * i], at[2 * i + 1], &jet);
      const double* values[] = {jet.point, jet.du, jet.dv, jet.duu, jet.duv, jet.dvv};
      for (int k = 0; k < outputs; ++k)
        for (int c = 0; c < 3; ++c) data[k][3 * i + c] = inside ? values[k][c] : std::numeric_limits<double>::quiet_NaN();
    }
  }
  if (!derivatives) return std::move(out[0]);
  py::dict result;
  for (int k = 0; k < outputs; ++k) result[names[k]] = out[k];
  return std::move(result);
}

}  // namespace

void RegisterPou(py::module_& m) {
  m.def("manifold", &BuildManifold, py::arg("vertices"), py::arg("triangles"), py::arg("base") = "loop",
        py::arg("degree") = py::none(), R"doc(
The C-infinity partition-of-unity surface over a closed triangle mesh, as a
Manifold with one pou_manifold patch (docs/manifold.md), as `invmap manifold`
builds it.

vertices: (V, 3) real array. triangles: (T, 3) integer array of 0-based
  vertex indices; the mesh must be closed, consistently oriented and
  manifold, every vertex of valence 3 or more.
base: the surface the charts are fitted to: "flat" (the mesh), "pn" (PN
  triangles) or "loop" (the Loop subdivision limit surface).
degree: bidegree of every chart's shape function, 1 to 8; None chooses
  min(valence + 1, 7) per chart.

invert reports patch 0, the cell of the vertex whose chart has the largest
bump at the answer, and params (u, v, NaN) in that chart. Raises InputError
naming the vertex, edge or triangle that makes the mesh unfit.
)doc");
  py::class_<PyManifold> manifold = m.attr("Manifold");
  manifold.def("chart_points", &ChartPoints, py::arg("cells"), py::arg("uv"), py::arg("derivatives") = false,
               py::arg("patch") = 0, R"doc(
The charts of a pou_manifold patch evaluated at local coordinates.

cells: (N,) integer array of charts (vertices); uv: (N, 2) real array of
  coordinates in each chart's p-domain (the disk of radius cos(pi / valence)).
Returns an (N, 3) array of points, or with derivatives=True a dict of (N, 3)
arrays: point, du, dv, duu, duv, dvv. Rows outside the p-domain are NaN.
Raises InputError when the patch is not a pou_manifold, or naming the first
entry of cells that is not a chart of the patch.
)doc");
}

}  // namespace invmap::python
