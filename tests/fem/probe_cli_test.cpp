// `invmap probe` end to end: the columns of the contract, every output
// format, --fields, --max-distance, --time-step, exit codes and messages for
// bad input, on VTU and Exodus files written by VTK and the Exodus library.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "tests/fem/exodus_writer.h"
#include "tests/fem/vtk_test_cells.h"
#include "tests/io/io_scratch.h"

namespace invmap::testing {
namespace {

using io::scratch::ReadAll;
using io::scratch::ScratchDir;

/// Runs the invmap command; returns its exit code, its output in `out`.
int RunInvmap(const ScratchDir& dir, const std::string& args, std::string* out = nullptr) {
  const std::string log = dir.Path("run.log");
  const int status = std::system((std::string(INVMAP_CLI_PATH) + " " + args + " > " + log + " 2>&1").c_str());
  if (out != nullptr) *out = ReadAll(log);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

double Quadratic(double x, double y, double z) { return 1 + x - y + 0.5 * z + x * y - z * z; }

/// Two straight-sided quadratic tets sharing a face, with point data f (a
/// quadratic) and v (a vector), written by VTK's writer.
std::string WriteTets(const ScratchDir& dir) {
  const double corners[5][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  const int tets[2][4] = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  const int edges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};  // VTK_QUADRATIC_TETRA order
  vtkNew<vtkUnstructuredGrid> grid;
  vtkNew<vtkPoints> points;
  vtkNew<vtkDoubleArray> f, v;
  f->SetName("f");
  v->SetName("v");
  v->SetNumberOfComponents(3);
  const auto add = [&](const double* x) {
    points->InsertNextPoint(x);
    f->InsertNextValue(Quadratic(x[0], x[1], x[2]));
    const double vector[3] = {x[0], 2 * x[1], x[0] + x[2]};
    v->InsertNextTuple(vector);
    return points->GetNumberOfPoints() - 1;
  };
  for (const auto& tet : tets) {
    vtkIdType ids[10];
    for (int k = 0; k < 4; ++k) ids[k] = add(corners[tet[k]]);
    for (int e = 0; e < 6; ++e) {
      double mid[3];
      for (int k = 0; k < 3; ++k) mid[k] = 0.5 * (corners[tet[edges[e][0]]][k] + corners[tet[edges[e][1]]][k]);
      ids[4 + e] = add(mid);
    }
    grid->InsertNextCell(VTK_QUADRATIC_TETRA, 10, ids);
  }
  grid->SetPoints(points);
  grid->GetPointData()->AddArray(f);
  grid->GetPointData()->AddArray(v);
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  const std::string path = dir.Path("tets.vtu");
  writer->SetFileName(path.c_str());
  writer->SetInputData(grid);
  EXPECT_EQ(writer->Write(), 1);
  return path;
}

/// CSV rows split into fields, header first.
std::vector<std::vector<std::string>> Csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string>& row = rows.emplace_back();
    std::string field;
    std::istringstream fields(line);
    while (std::getline(fields, field, ',')) row.push_back(field);
    if (!line.empty() && line.back() == ',') row.push_back("");
  }
  return rows;
}

TEST(ProbeCli, ColumnsValuesAndFormats) {
  const ScratchDir dir;
  const std::string geometry = WriteTets(dir);
  // Inside points, and one far away (not found with --max-distance 0.5).
  const double p[4][3] = {{0.1, 0.2, 0.3}, {0.6, 0.5, 0.55}, {0.2, 0.2, 0.1}, {5, 5, 5}};
  std::ofstream(dir.Path("p.xyz")) << "0.1 0.2 0.3\n0.6 0.5 0.55\n0.2 0.2 0.1\n5 5 5\n";
  ASSERT_EQ(RunInvmap(dir, "probe -q -g " + geometry + " -p " + dir.Path("p.xyz") + " -o " + dir.Path("r.csv") +
                         " --max-distance 0.5"),
            0);
  const auto rows = Csv(ReadAll(dir.Path("r.csv")));
  ASSERT_EQ(rows.size(), 5u);
  const std::string header = "index,status,patch,cell,u,v,w,x,y,z,distance,f,v_0,v_1,v_2\n";
  EXPECT_EQ(ReadAll(dir.Path("r.csv")).substr(0, header.size()), header);
  for (int i = 0; i < 3; ++i) {
    ASSERT_EQ(rows[i + 1].size(), 15u);
    EXPECT_EQ(rows[i + 1][1], "found");
    EXPECT_NEAR(std::stod(rows[i + 1][11]), Quadratic(p[i][0], p[i][1], p[i][2]), 1e-12) << "row " << i;
    EXPECT_NEAR(std::stod(rows[i + 1][12]), p[i][0], 1e-12);
    EXPECT_NEAR(std::stod(rows[i + 1][13]), 2 * p[i][1], 1e-12);
    EXPECT_NEAR(std::stod(rows[i + 1][14]), p[i][0] + p[i][2], 1e-12);
  }
  EXPECT_EQ(rows[4][1], "none");
  ASSERT_EQ(rows[4].size(), 15u);
  for (int k = 11; k < 15; ++k) EXPECT_EQ(rows[4][k], "");

  // --fields picks and orders; npy has 11 + 3 columns.
  ASSERT_EQ(RunInvmap(dir, "probe -q -g " + geometry + " -p " + dir.Path("p.xyz") + " -o " + dir.Path("r.npy") +
                         " --fields v"),
            0);
  const std::string npy = ReadAll(dir.Path("r.npy"));
  EXPECT_NE(npy.find("'shape': (4, 14)"), std::string::npos);
  ASSERT_EQ(RunInvmap(dir, "probe -q -g " + geometry + " -p " + dir.Path("p.xyz") + " -o " + dir.Path("r.ply") +
                         " --fields v,f"),
            0);
  const std::string ply = ReadAll(dir.Path("r.ply"));
  EXPECT_NE(ply.find("property double v_2\nproperty double f\nend_header"), std::string::npos);
}

TEST(ProbeCli, ExitCodesAndMessages) {
  const ScratchDir dir;
  const std::string geometry = WriteTets(dir);
  std::ofstream(dir.Path("p.xyz")) << "0.1 0.2 0.3\n";
  std::string out;
  EXPECT_EQ(RunInvmap(dir, "probe -g " + geometry + " -p " + dir.Path("p.xyz") + " -o " + dir.Path("r.csv") + " --fields w",
                &out),
            2);
  EXPECT_NE(out.find("has no field 'w' (its fields: f, v)"), std::string::npos) << out;
  EXPECT_EQ(RunInvmap(dir, "probe -g " + geometry + " -p " + dir.Path("p.xyz") + " -o " + dir.Path("r.csv") +
                         " --time-step 2",
                &out),
            2);
  EXPECT_NE(out.find("--time-step applies to Exodus files"), std::string::npos) << out;
  std::ofstream(dir.Path("g.json")) << R"({"format": "invmap-geometry", "version": 1, "dimension": 3, "patches": [
      {"kind": "mesh", "cell": "tet", "vertices": [[0,0,0],[1,0,0],[0,1,0],[0,0,1]], "cells": [[0,1,2,3]]}]})";
  EXPECT_EQ(RunInvmap(dir, "probe -g " + dir.Path("g.json") + " -p " + dir.Path("p.xyz") + " -o " + dir.Path("r.csv"), &out),
            3);
  EXPECT_NE(out.find(dir.Path("g.json") + ": no node fields to probe"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir.Path("r.csv")));
  // A bad Exodus element: the file, the block and the element.
  const std::vector<double> xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  ASSERT_TRUE(WriteExodus(dir.Path("bad.exo"), 3, xyz, {{5, "TETRA", 4, {1, 2, 3, 4, 1, 2, 3, 7}, ""}}, {}));
  EXPECT_EQ(RunInvmap(dir, "probe -g " + dir.Path("bad.exo") + " -p " + dir.Path("p.xyz") + " -o " + dir.Path("r.csv"), &out),
            3);
  EXPECT_NE(out.find(dir.Path("bad.exo") + ": element block 5 (TETRA), element 1 of the block: node 7"),
            std::string::npos)
      << out;
  EXPECT_FALSE(std::filesystem::exists(dir.Path("r.csv")));
}

/// A quarter circle of radius 2 in the plane z = 0.5 as one rational
/// quadratic VTK Bezier curve, with point data X (each node's x) and weight
/// `middleWeight` at the interior control point.
std::string WriteRationalArc(const ScratchDir& dir, const std::string& name, double middleWeight) {
  vtkNew<vtkUnstructuredGrid> grid;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkDoubleArray> x, w;
  x->SetName("X");
  w->SetName("W");
  const double nodes[3][3] = {{2, 0, 0.5}, {0, 2, 0.5}, {2, 2, 0.5}};  // VTK's order: ends, then the middle
  for (int i = 0; i < 3; ++i) {
    points->InsertNextPoint(nodes[i]);
    x->InsertNextValue(nodes[i][0]);
    w->InsertNextValue(i == 2 ? middleWeight : 1.0);
  }
  grid->SetPoints(points);
  const vtkIdType ids[3] = {0, 1, 2};
  grid->InsertNextCell(VTK_BEZIER_CURVE, 3, ids);
  grid->GetPointData()->AddArray(x);
  grid->GetPointData()->SetRationalWeights(w);
  const std::string path = dir.Path(name);
  EXPECT_TRUE(Write(grid, path, Encoding::Appended));
  return path;
}

// A rational Bezier curve end to end: the field of the nodes' x, interpolated
// with the cell's rational basis, is the x of the exact circle at the
// closest point; a weight out of range is exit code 3 naming the cell and point.
TEST(ProbeCli, RationalVtuBezierCells) {
  const ScratchDir dir;
  const std::string arc = WriteRationalArc(dir, "arc.vtu", std::sqrt(0.5));
  const double theta = 0.4;
  std::ofstream(dir.Path("p.xyz")) << std::setprecision(17) << 3 * std::cos(theta) << " " << 3 * std::sin(theta)
                                  << " 0.5\n";
  ASSERT_EQ(RunInvmap(dir, "probe -q -g " + arc + " -p " + dir.Path("p.xyz") + " -o " + dir.Path("r.csv")), 0);
  const auto rows = Csv(ReadAll(dir.Path("r.csv")));
  ASSERT_EQ(rows.size(), 2u);
  ASSERT_EQ(rows[0].back(), "X");
  EXPECT_NEAR(std::stod(rows[1][10]), 1.0, 1e-12);                   // distance to the circle of radius 2
  EXPECT_NEAR(std::stod(rows[1].back()), 2 * std::cos(theta), 1e-12);  // X at the closest point
  std::string out;
  const std::string bad = WriteRationalArc(dir, "bad.vtu", -1.0);
  EXPECT_EQ(RunInvmap(dir, "probe -g " + bad + " -p " + dir.Path("p.xyz") + " -o " + dir.Path("s.csv"), &out), 3);
  EXPECT_NE(out.find(bad + ": cell 0 (VTK_BEZIER_CURVE): point 2 has rational weight -1"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir.Path("s.csv")));
}

TEST(ProbeCli, ExodusTimeSteps) {
  const ScratchDir dir;
  const std::vector<double> xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  ASSERT_TRUE(WriteExodus(dir.Path("t.exo"), 3, xyz, {{1, "TET4", 4, {1, 2, 3, 4}, ""}},
                          {{"T", {{0, 1, 2, 3}, {10, 11, 12, 13}, {20, 21, 22, 23}}}}));
  std::ofstream(dir.Path("p.xyz")) << "0.25 0.25 0.25\n";
  const auto probe = [&](const std::string& options) {
    EXPECT_EQ(RunInvmap(dir, "probe -q -g " + dir.Path("t.exo") + " -p " + dir.Path("p.xyz") + " -o " + dir.Path("r.csv") +
                           options),
              0);
    return std::stod(Csv(ReadAll(dir.Path("r.csv")))[1][11]);
  };
  EXPECT_NEAR(probe(""), 21.5, 1e-12);
  EXPECT_NEAR(probe(" --time-step 1"), 1.5, 1e-12);
  EXPECT_NEAR(probe(" --time-step 2"), 11.5, 1e-12);
  std::string out;
  EXPECT_EQ(RunInvmap(dir, "probe -g " + dir.Path("t.exo") + " -p " + dir.Path("p.xyz") + " -o " + dir.Path("r.csv") +
                         " --time-step 4",
                &out),
            3);
  EXPECT_NE(out.find("time step 4 requested, the file has 3 time steps"), std::string::npos) << out;
  EXPECT_EQ(RunInvmap(dir, "probe -g " + dir.Path("t.exo") + " -p " + dir.Path("p.xyz") + " -o " + dir.Path("r.csv") +
                         " --time-step 0",
                &out),
            2);
  EXPECT_NE(out.find("--time-step: '0' is not a whole number >= 1"), std::string::npos) << out;
}

// The new formats are geometry files for every command.
TEST(ProbeCli, InvertAndInfoReadTheNewFormats) {
  const ScratchDir dir;
  const std::string geometry = WriteTets(dir);
  std::string out;
  ASSERT_EQ(RunInvmap(dir, "info -g " + geometry, &out), 0);
  EXPECT_NE(out.find("tet 2"), std::string::npos) << out;
  std::ofstream(dir.Path("p.xyz")) << "0.1 0.2 0.3\n";
  ASSERT_EQ(RunInvmap(dir, "invert -q -g " + geometry + " -p " + dir.Path("p.xyz") + " -o " + dir.Path("r.csv")), 0);
  EXPECT_EQ(Csv(ReadAll(dir.Path("r.csv")))[1].size(), 11u);
}

}  // namespace
}  // namespace invmap::testing
