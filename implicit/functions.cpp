// The built-in implicit functions (include/invmap/implicit.h), positive
// inside, with analytic gradients.
#include <cmath>
#include <cstddef>
#include <utility>

#include "invmap/implicit.h"

namespace invmap::implicit {
namespace {

double Dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

Vec3 Normalized(const Vec3& v) {
  const double length = std::sqrt(Dot(v, v));
  return {v[0] / length, v[1] / length, v[2] / length};
}

/// x relative to an axis through `origin` along the unit vector `axis`: the
/// height along it, the radial vector from it, its length, and the unit
/// radial direction (any unit vector orthogonal to the axis when x is on it).
struct AxisCoordinates {
  double height;
  Vec3 radial;
  double distance;
  Vec3 outward;
};

AxisCoordinates AroundAxis(const Vec3& origin, const Vec3& axis, const Vec3& x) {
  AxisCoordinates c;
  const Vec3 d = {x[0] - origin[0], x[1] - origin[1], x[2] - origin[2]};
  c.height = Dot(d, axis);
  c.radial = {d[0] - c.height * axis[0], d[1] - c.height * axis[1], d[2] - c.height * axis[2]};
  c.distance = std::sqrt(Dot(c.radial, c.radial));
  if (c.distance > 0) {
    c.outward = {c.radial[0] / c.distance, c.radial[1] / c.distance, c.radial[2] / c.distance};
  } else {
    const Vec3 other = std::fabs(axis[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    const double along = Dot(other, axis);
    c.outward = Normalized({other[0] - along * axis[0], other[1] - along * axis[1], other[2] - along * axis[2]});
  }
  return c;
}

// Wraps a per-point evaluator `f(x, gradient) -> value` as a batch EvaluateFn.
template <typename PointFn>
Function MakeFunction(std::string name, PointFn f) {
  Function function;
  function.name = std::move(name);
  function.evaluate = [f](const double* xyz, std::size_t count, double* values, double* gradients) {
    for (std::size_t i = 0; i < count; ++i) {
      const Vec3 x = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
      Vec3 gradient;
      values[i] = f(x, gradient);
      gradients[3 * i] = gradient[0];
      gradients[3 * i + 1] = gradient[1];
      gradients[3 * i + 2] = gradient[2];
    }
  };
  return function;
}

}  // namespace

Function Function::Sphere(const Vec3& center, double radius, bool squared) {
  return MakeFunction("sphere", [center, radius, squared](const Vec3& x, Vec3& gradient) {
    const Vec3 d = {x[0] - center[0], x[1] - center[1], x[2] - center[2]};
    const double d2 = Dot(d, d);
    if (squared) {
      for (int a = 0; a < 3; ++a) gradient[a] = -2 * d[a];
      return radius * radius - d2;
    }
    const double length = std::sqrt(d2);
    // At the centre the distance has no gradient; any unit vector will do.
    for (int a = 0; a < 3; ++a) gradient[a] = length > 0 ? -d[a] / length : (a == 0 ? -1.0 : 0.0);
    return radius - length;
  });
}

Function Function::Cylinder(const Vec3& axisPoint, const Vec3& axisVector, double radius, bool squared) {
  const Vec3 axis = Normalized(axisVector);
  return MakeFunction("cylinder", [axisPoint, axis, radius, squared](const Vec3& x, Vec3& gradient) {
    const AxisCoordinates c = AroundAxis(axisPoint, axis, x);
    if (squared) {
      for (int a = 0; a < 3; ++a) gradient[a] = -2 * c.radial[a];
      return radius * radius - c.distance * c.distance;
    }
    for (int a = 0; a < 3; ++a) gradient[a] = -c.outward[a];
    return radius - c.distance;
  });
}

Function Function::Plane(const Vec3& point, const Vec3& normal) {
  const Vec3 n = Normalized(normal);
  return MakeFunction("plane", [point, n](const Vec3& x, Vec3& gradient) {
    gradient = n;
    return n[0] * (x[0] - point[0]) + n[1] * (x[1] - point[1]) + n[2] * (x[2] - point[2]);
  });
}

Function Function::Torus(const Vec3& center, const Vec3& axisVector, double majorRadius, double minorRadius) {
  const Vec3 axis = Normalized(axisVector);
  return MakeFunction("torus", [center, axis, majorRadius, minorRadius](const Vec3& x, Vec3& gradient) {
    const AxisCoordinates c = AroundAxis(center, axis, x);
    // Distance to the core circle; its gradient is the unit vector from the
    // circle's nearest point to x.
    const double a = c.distance - majorRadius;
    const double tube = std::sqrt(a * a + c.height * c.height);
    for (int k = 0; k < 3; ++k) {
      const double towardX = a * c.outward[k] + c.height * axis[k];
      gradient[k] = tube > 0 ? -towardX / tube : (k == 0 ? -1.0 : 0.0);
    }
    return minorRadius - tube;
  });
}

Function Function::Cone(const Vec3& apex, const Vec3& axisVector, double apexAngle) {
  const Vec3 axis = Normalized(axisVector);
  const double cosAngle = std::cos(apexAngle);
  return MakeFunction("cone", [apex, axis, cosAngle](const Vec3& x, Vec3& gradient) {
    const Vec3 v = {x[0] - apex[0], x[1] - apex[1], x[2] - apex[2]};
    const double length = std::sqrt(Dot(v, v));
    // At the apex the function is not differentiable; the axis will do.
    for (int k = 0; k < 3; ++k) gradient[k] = axis[k] - (length > 0 ? cosAngle * v[k] / length : 0.0);
    return Dot(v, axis) - cosAngle * length;
  });
}

Function Function::Quintic(const Vec3& center) {
  return MakeFunction("quintic", [center](const Vec3& x, Vec3& gradient) {
    const double u = x[0] - center[0];
    const double v = x[1] - center[1];
    const double u3 = u * u * u;
    gradient = {5 * u3 * u + 4 * u3, -4 * v, 0};
    return u3 * u * u + u3 * u - 2 * v * v;
  });
}

Function Function::Gyroid(double period) {
  const double scale = 2 * M_PI / period;
  return MakeFunction("gyroid", [scale](const Vec3& x, Vec3& gradient) {
    const double sx = std::sin(scale * x[0]), cx = std::cos(scale * x[0]);
    const double sy = std::sin(scale * x[1]), cy = std::cos(scale * x[1]);
    const double sz = std::sin(scale * x[2]), cz = std::cos(scale * x[2]);
    gradient = {scale * (cx * cy - sz * sx), scale * (-sx * sy + cy * cz), scale * (-sy * sz + cz * cx)};
    return sx * cy + sy * cz + sz * cx;
  });
}

}  // namespace invmap::implicit
