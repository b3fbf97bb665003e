#include "implicit_io/function_list.h"

#include <algorithm>
#include <cstddef>

#include "implicit_io/json_values.h"
#include "io/file_io.h"
#include "io/input_error.h"

namespace invmap::io {
namespace {

using json::Describe;
using json::ObjectReader;
using json::ParseJsonList;
using json::Value;

/// The function types of the list file, with their fields ("type" and
/// "name" are allowed in every one).
struct FunctionType {
  const char* name;
  std::vector<const char*> fields;
};

/// Every function type, in the order messages list them.
const std::vector<FunctionType>& FunctionTypes() {
  static const std::vector<FunctionType> kTypes = {
      {"sphere", {"type", "name", "center", "radius", "squared"}},
      {"cylinder", {"type", "name", "axis_point", "axis_vector", "radius", "squared"}},
      {"plane", {"type", "name", "point", "normal"}},
      {"torus", {"type", "name", "center", "axis_vector", "major_radius", "minor_radius"}},
      {"cone", {"type", "name", "apex", "axis_vector", "apex_angle"}},
      {"quintic", {"type", "name", "center"}},
      {"gyroid", {"type", "name", "period"}},
  };
  return kTypes;
}

/// "sphere, cylinder, ...": the known types for messages.
std::string FunctionTypeList() {
  std::string list;
  for (const FunctionType& t : FunctionTypes()) list += (list.empty() ? "" : ", ") + std::string(t.name);
  return list;
}

/// Function `index` of the list, from its JSON object.
implicit::Function ReadFunction(const std::string& path, const Value& object, std::size_t index, int dimension) {
  const std::string where = "functions[" + std::to_string(index) + "]";
  if (object.type != Value::Type::Object) {
    throw InputError(path, object.line, where + ": expected a function object, found " + Describe(object));
  }
  const ObjectReader r(path, object, where, dimension);
  const Value& typeValue = r.Required("type", "one of " + FunctionTypeList());
  if (typeValue.type != Value::Type::String) {
    r.FailField(typeValue, "type", "expected a string (" + FunctionTypeList() + "), found " + Describe(typeValue));
  }
  const std::string& type = typeValue.text;
  const auto found = std::find_if(FunctionTypes().begin(), FunctionTypes().end(),
                                  [&](const FunctionType& t) { return type == t.name; });
  if (found == FunctionTypes().end()) {
    r.FailField(typeValue, "type", "unknown function type \"" + type + "\" (known: " + FunctionTypeList() + ")");
  }
  r.CheckKeys(found->fields, "a " + type);

  implicit::Function f;
  if (type == "sphere") {
    const implicit::Vec3 center = r.Point("center");
    f = implicit::Function::Sphere(center, r.Positive("radius"), r.Boolean("squared", false));
  } else if (type == "cylinder") {
    const implicit::Vec3 point = r.Point("axis_point");
    const implicit::Vec3 axis = r.Direction("axis_vector");
    f = implicit::Function::Cylinder(point, axis, r.Positive("radius"), r.Boolean("squared", false));
  } else if (type == "plane") {
    const implicit::Vec3 point = r.Point("point");
    f = implicit::Function::Plane(point, r.Direction("normal"));
  } else if (type == "torus") {
    const implicit::Vec3 center = r.Point("center");
    const implicit::Vec3 axis = r.Direction("axis_vector");
    const double major = r.Positive("major_radius");
    f = implicit::Function::Torus(center, axis, major, r.Positive("minor_radius"));
  } else if (type == "cone") {
    const implicit::Vec3 apex = r.Point("apex");
    const implicit::Vec3 axis = r.Direction("axis_vector");
    const Value& angleValue = r.Required("apex_angle", "the half angle in radians");
    const double angle = r.Number(angleValue, "apex_angle");
    constexpr double kHalfPi = 1.57079632679489661923;
    if (!(angle > 0 && angle < kHalfPi)) {
      r.FailField(angleValue, "apex_angle", angleValue.text + ", expected a half angle in radians in (0, pi/2)");
    }
    f = implicit::Function::Cone(apex, axis, angle);
  } else if (type == "quintic") {
    const Value* center = r.Optional("center");
    f = implicit::Function::Quintic(center != nullptr ? r.Point(*center, "center") : implicit::Vec3{0, 0, 0});
  } else {  // gyroid
    f = implicit::Function::Gyroid(r.Positive("period"));
  }
  if (const Value* name = r.Optional("name")) {
    if (name->type != Value::Type::String) r.FailField(*name, "name", "expected a string, found " + Describe(*name));
    f.name = name->text;
  }
  return f;
}

}  // namespace

std::vector<implicit::Function> ReadFunctionList(const std::string& path, int dimension) {
  return ParseFunctionList(ReadWholeFile(path, json::kMaxImplicitFileBytes), path, dimension);
}

std::vector<implicit::Function> ParseFunctionList(const std::string& text, const std::string& path, int dimension) {
  const Value root = ParseJsonList(text, path, "function object");
  std::vector<implicit::Function> functions;
  functions.reserve(root.items.size());
  for (std::size_t i = 0; i < root.items.size(); ++i) functions.push_back(ReadFunction(path, root.items[i], i, dimension));
  return functions;
}

}  // namespace invmap::io
