// The main job until the invmap command lands: closest points of a point
// cloud on a bundled curved bicubic Bezier patch, with a summary.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "kernels/cell_solver.h"

int main() {
  using namespace invmap::kernels;
  // A wavy bicubic patch over [0, 3]^2: z = 0.6 sin(x) cos(y) at the lattice.
  const CellShape shape(CellType::Quad, {3, 3, 0});
  std::vector<double> points;
  for (int j = 0; j <= 3; ++j) {
    for (int i = 0; i <= 3; ++i) {
      const double x = i, y = j;
      points.insert(points.end(), {x, y, 0.6 * std::sin(2.0 * x) * std::cos(1.5 * y)});
    }
  }
  const CellView cell{shape, 3, points.data(), nullptr};
  const CellSolver solver(cell);

  const int count = 100000;
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> xy(-0.5, 3.5), z(-1.0, 1.0);
  std::vector<double> queries;
  for (int i = 0; i < count; ++i) queries.insert(queries.end(), {xy(rng), xy(rng), z(rng)});

  SolveWorkspace ws;
  std::vector<double> distance(count);
  int interior = 0, boundary = 0, uncertified = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < count; ++i) {
    const CellSolveResult r = solver.Solve(&queries[3 * i], nullptr, &ws);
    distance[i] = r.distance;
    interior += r.status == PointStatus::Converged;
    boundary += r.status == PointStatus::ProjectedToBoundary;
    uncertified += r.status == PointStatus::NotCertified;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::sort(distance.begin(), distance.end());
  std::printf("invmap demo: %d points against one curved bicubic patch (1 thread)\n", count);
  std::printf("  closest point inside the patch: %d, on its boundary: %d, not certified: %d\n", interior, boundary,
              uncertified);
  std::printf("  distance min %.6g  median %.6g  max %.6g\n", distance.front(), distance[count / 2], distance.back());
  std::printf("  %.3f s, %.0f points/s\n", seconds, count / seconds);
  return 0;
}
