#include "fem/extraction_cells.h"

#include <cmath>

#include "fem/lagrange_cells.h"
#include "io/input_error.h"

namespace invmap::fem {

Patch EmptyCellsPatch() {
  Patch patch;
  patch.kind = Patch::Kind::BezierCells;
  patch.cellOffsets.push_back(0);
  return patch;
}

int ExtractedDimension(const ExtractedSpline& spline, const std::vector<ExtractionElement>& elements) {
  bool anyVolume = false;
  for (const ExtractionElement& e : elements) anyVolume = anyVolume || ParamDimOf(e.type) == 3;
  return GeometryDimension(spline.points, anyVolume);
}

void AddExtractedCell(const ExtractedSpline& spline, const ExtractionElement& element, int dim,
                      const std::string& file, Patch* patch) {
  const auto fail = [&](const std::string& what) { throw io::InputError(file, 0, element.where + ": " + what); };
  const int directions = ParamDimOf(element.type);
  std::size_t bernstein = 1;
  for (int d = 0; d < directions; ++d) {
    if (element.degrees[d] < 1 || element.degrees[d] > 8) {
      fail("degree " + std::to_string(element.degrees[d]) + " not in 1..8");
    }
    bernstein *= static_cast<std::size_t>(element.degrees[d] + 1);
  }
  if (element.points.size() != element.coefficientVectors.size()) {
    fail(std::to_string(element.points.size()) + " control points but " +
         std::to_string(element.coefficientVectors.size()) + " coefficient vectors");
  }
  const std::size_t numPoints = spline.points.size() / 3;
  const bool rational = !spline.weights.empty();
  std::vector<double> homogeneous(bernstein * 4, 0.0);  // sum_i C_ij w_i (P_i, 1)
  for (std::size_t i = 0; i < element.points.size(); ++i) {
    const std::int64_t p = element.points[i];
    const std::int64_t v = element.coefficientVectors[i];
    if (p < 0 || static_cast<std::size_t>(p) >= numPoints) {
      fail("control point " + std::to_string(p) + " out of range [0, " + std::to_string(numPoints) + ")");
    }
    if (v < 0 || static_cast<std::size_t>(v) >= spline.coefficientVectors.size()) {
      fail("coefficient vector " + std::to_string(v) + " out of range [0, " +
           std::to_string(spline.coefficientVectors.size()) + ")");
    }
    const std::vector<double>& c = spline.coefficientVectors[static_cast<std::size_t>(v)];
    if (c.size() != bernstein) {
      fail("coefficient vector " + std::to_string(v) + " has " + std::to_string(c.size()) +
           " components, the element's degrees need " + std::to_string(bernstein));
    }
    const double w = rational ? spline.weights[static_cast<std::size_t>(p)] : 1.0;
    const double* x = spline.points.data() + 3 * p;
    for (std::size_t j = 0; j < bernstein; ++j) {
      const double cw = c[j] * w;
      for (int k = 0; k < 3; ++k) homogeneous[4 * j + k] += cw * x[k];
      homogeneous[4 * j + 3] += cw;
    }
  }
  for (std::size_t j = 0; j < bernstein; ++j) {
    const double weight = homogeneous[4 * j + 3];
    if (rational && (!(weight > 0.0) || !std::isfinite(weight))) {
      fail("Bezier control point " + std::to_string(j) + " has weight " + std::to_string(weight) +
           " (the extraction gives a non-positive weight)");
    }
    // A polynomial spline's coefficient vectors form a partition of unity,
    // so its weights are 1 up to rounding: divide only a rational one.
    for (int k = 0; k < dim; ++k) patch->points.push_back(homogeneous[4 * j + k] / (rational ? weight : 1.0));
    if (rational) patch->weights.push_back(weight);
  }
  patch->cellTypes.push_back(element.type);
  patch->cellDegrees.insert(patch->cellDegrees.end(), {element.degrees[0], element.degrees[1], element.degrees[2]});
  patch->cellOffsets.push_back(patch->cellOffsets.back() + static_cast<std::int64_t>(bernstein));
}

}  // namespace invmap::fem
