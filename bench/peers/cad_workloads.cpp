// The CAD workloads of the peer comparison: scans of CAD models, the use
// the CAD support is for (scan-to-CAD deviation), and points in a box.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

#include "bench/peers/workloads.h"
#include "cad/sample_part.h"

namespace invmap::bench {

void AddCadCases(const WorkloadOptions& options, std::vector<GeometryCase>* cases) {
  const struct {
    const char* name;
    std::string path;
    const char* what;
    bool box;  ///< Also points uniform in the model's box grown by a tenth.
  } models[] = {
      {"cad bracket", std::string(INVMAP_SOURCE_DIR) + "/examples/data/bracket.step",
       "the demo's bracket (examples/data/bracket.step)", true},
      {"cad screw", "/usr/share/opencascade/data/step/screw.step", "OpenCascade's sample screw.step", false},
      {"cad bearing", "/usr/share/opencascade/data/iges/bearing.iges", "OpenCascade's sample bearing.iges", false},
  };
  for (const auto& model : models) {
    if (!options.only.empty() && std::string(model.name).find(options.only) == std::string::npos) continue;
    cad::LoadResult loaded = cad::Model::Load(model.path);
    if (!loaded.error.empty()) {
      std::fprintf(stderr, "invmap_bench_peers: skipping '%s': %s: %s\n", model.name, model.path.c_str(),
                   loaded.error.c_str());
      continue;
    }
    GeometryCase c;
    c.name = model.name;
    c.kind = CaseKind::CadModel;
    c.cadPath = model.path;
    c.geometry = loaded.model->geometry();
    const cad::ModelInfo info = loaded.model->Info();
    double size2 = 0.0;
    for (int k = 0; k < 3; ++k) size2 += (info.boundsHi[k] - info.boundsLo[k]) * (info.boundsHi[k] - info.boundsLo[k]);
    const double size = std::sqrt(size2);
    std::ostringstream d;
    d << model.what << ", " << info.faces << " faces";
    c.description = d.str();
    // A scan: points on the faces, grown by up to 5e-4 of the size toward
    // the top, noise 1e-4 of the size, 0.2 % outliers (cad::SimulateScan).
    cad::ScanOptions scan;
    scan.count = options.points;
    scan.noise = 1e-4 * size;
    scan.warp = 5e-4 * size;
    scan.outlierReach = 1e-2 * size;
    PointSet scanSet;
    scanSet.name = "scan";
    scanSet.coords = cad::SimulateScan(*loaded.model, scan);
    c.pointSets.push_back(std::move(scanSet));
    if (model.box) {
      PointSet box;
      box.name = "box";
      std::mt19937_64 rng(61);
      std::uniform_real_distribution<double> unit(0.0, 1.0);
      for (std::int64_t i = 0; i < options.points; ++i) {
        for (int k = 0; k < 3; ++k) {
          const double pad = 0.1 * (info.boundsHi[k] - info.boundsLo[k]);
          box.coords.push_back(info.boundsLo[k] - pad + unit(rng) * (info.boundsHi[k] - info.boundsLo[k] + 2 * pad));
        }
      }
      c.pointSets.push_back(std::move(box));
    }
    // What a user would export to a mesh tool: a coarse and a fine tessellation.
    for (const double share : {1e-3, 1e-5}) {
      GeometryCase::Tessellation t;
      t.deflection = share * size;
      t.mesh = cad::Tessellate(*loaded.model, t.deflection);
      c.tessellations.push_back(std::move(t));
    }
    cases->push_back(std::move(c));
  }
}

}  // namespace invmap::bench
