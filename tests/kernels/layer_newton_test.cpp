// The layers of a heavy weight (kernels/layer_newton.h): degree-2 rational
// tetrahedra with one weight near 1e10 or 1e12, found by black-box QA with
// an mpmath reference. At each query the cell's closest point lies within
// 1e-5 to 1e-26 of a face or edge, where the map depends on a product of
// small coordinates; the active-set solve alone stopped short along that
// valley (up to 0.013 farther than the reference), or stopped at a point the
// KKT test passed only because one column of the Jacobian, 1e12 times the
// others, set its scale, and the search ran out of budget or certified it. The reference answers are kept as witnesses: points of the cell
// (reference coordinates), evaluated here by the test's own multinomial
// evaluator, so invmap may never be farther than they are.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "kernels/cell_charts.h"
#include "kernels/cell_solver.h"
#include "kernels/kkt_point.h"
#include "kernels/layer_newton.h"
#include "kernels/local_solver.h"
#include "tests/support/reference_cell.h"

namespace {

using invmap::kernels::CellCharts;
using invmap::kernels::CellSolver;
using invmap::kernels::CellSolveResult;
using invmap::kernels::CellType;
using invmap::kernels::EvaluateMap;
using invmap::kernels::IsKktPoint;
using invmap::kernels::JetOrder;
using invmap::kernels::LayerNewton;
using invmap::kernels::MapJet;
using invmap::kernels::SolveWorkspace;
using invmap::testing::RefCell;
using invmap::testing::RefEvaluate;

/// A query and a point of the cell at least as near as the true answer
/// (QA's reference, 30 digits), in the cell's reference coordinates.
struct Witnessed {
  std::array<double, 3> query;
  std::array<double, 3> witness;
};

struct LayerCase {
  const char* name;
  RefCell cell;
  std::vector<Witnessed> queries;
};

RefCell QuadraticTet(std::vector<double> points, std::vector<double> weights) {
  RefCell cell;
  cell.type = CellType::Tet;
  cell.degrees = {2, 0, 0};
  cell.points = std::move(points);
  cell.weights = std::move(weights);
  return cell;
}

std::vector<LayerCase> Cases() {
  return {
      {"weight 8.9e11 on the edge (0, 1)",
       QuadraticTet({0.051720739744448, -0.12761044512490732, -0.03222165307356337, 0.8290190387162254,
                     -0.10540554779349956, 0.00777389054890963, 1.0293770800805022, -0.2558378983597249,
                     -0.09973415132792228, -0.07828883808645526, 0.3985059084672847, -0.05746717472157368,
                     0.29425812476055735, 0.4643527824549961, 0.03527930000604399, -0.05497162535865221,
                     1.1447975730361362, 0.03535738444901701, 0.10532130293059724, 0.16140794829500363,
                     0.38169286220649623, 0.380618387464404, -0.04508344731539127, 0.5892332835524504,
                     -0.1481882949783053, 0.34065253140173263, 0.19706563813990158, 0.21916760383620848,
                     0.07722096734375854, 0.7669672651716134},
                    {1.050090065311501, 888260805720.3263, 1.374935503952516, 1.1371973850211505, 1.2338356229894547,
                     0.8827672731985774, 1.2421917320257871, 1.1648018000604983, 0.9350470987767011,
                     0.7783791668056732}),
       {{{0.9699664226603719, 0.13894755575366208, 0.1657407787154314},
         {5.1806326076358145e-06, 0.9999937010278441, 2.794215368283931e-18}},
        {{0.74634175236014, -0.09608835465126547, -0.0453604982224289},
         {5.649541532370339e-12, 0.10524070731311166, 1.735726045696136e-27}},
        {{0.3470837022041861, 0.5818186004371717, -0.01275241403951042},
         {9.066902907192359e-07, 0.9999986408519902, 0.0}},
        {{0.45421327427252683, 1.0871963058165903, -0.983088050589825}, {4.77014078072846e-07, 0.999999203672018, 0.0}},
        {{2.1504013020477712, 2.057460667712303, -1.1354299532840841},
         {7.728733865755668e-07, 0.9999988678072372, 0.0}}}},
      {"weight 7.4e9 on the edge (2, 3)",
       QuadraticTet({-0.0831001301163075, -0.09834134884137954, 0.02434255890589321, 0.48544621925241616,
                     -0.08131155862881675, -0.06730186802943292, 1.2839085437845492, 0.026494335246588258,
                     0.1515324491242106, -0.08772790337198577, 0.7344583548484622, 0.241440748131672,
                     0.3734859223118713, 0.4693727344599753, -0.05389584706822982, 0.05754970557427476,
                     0.8682858969784861, -0.08375082096285133, -0.06254405300380866, -0.06175966438086572,
                     0.6327420403843265, 0.8665145253950672, 0.3055450680407764, 0.5841125940358634,
                     -0.008285679969160686, 0.634955480796711, 0.3622171138544882, 0.2648568510128553,
                     0.46759172007149735, 1.0054477438041012},
                    {1.1103419884425505, 0.8976408049650355, 0.9785134744201631, 1.24573104257018, 1.0556495301340358,
                     0.7648131963419019, 0.7994557890118796, 1.2375052129504318, 7448350248.178714,
                     1.0236459263149393}),
       {{{0.40156006484460677, 0.4968398149286389, 0.4499076056347601},
         {0.5404854958723293, 1.9292254658992355e-10, 0.4595145039347482}}}},
      {"weight 1.2e12 on the edge (1, 2)",
       QuadraticTet({0.0436608947306162, -0.06268231709513204, 0.11260575145918914, 0.6348150120515912,
                     -0.09386921923800645, -0.1087174201237522, 1.1027663219674761, 0.16617107698578393,
                     -0.079102958800942, -0.1373422748678252, 0.6458978192896021, 0.06854403008474988,
                     0.43007872727584007, 0.3595892091863875, 0.01385585641418282, 0.05177385290878122,
                     1.1821888005775274, -0.16903149128323017, 0.0018747750149840092, 0.10192055080676231,
                     0.5058233630024864, 0.6023452943997605, 0.11896902911790103, 0.26558800036042374,
                     -0.11897252709965658, 0.3670582345019495, 0.13336118697828014, 0.3256806301067556,
                     -0.19821617191108695, 1.1300908330445374},
                    {0.7908005146798045, 1.3803860700551176, 1.1329033225295324, 1.2863592151772871,
                     1230483290197.4136, 1.3130902029011577, 1.1276876386595107, 1.2469607296925207,
                     1.086026960179615, 1.218570871192179}),
       {{{0.12521639344535207, 0.5108344136847568, -0.04390944612560828},
         {6.50536231965167e-13, 0.4579138638414771, 6.938859192090564e-27}}}},
      {"weight 1.1e12 on the edge (2, 3)",
       QuadraticTet({-0.01183467016128198, -0.06359222778854555, 0.23564388408368767, 0.3389878669732578,
                     0.16257822799531646, 0.03687735484361603, 0.8788800334141488, 0.11828854734812869,
                     0.013484179579668087, 0.010088024702529641, 0.46563566422233355, 0.05778989006898929,
                     0.663570043329004, 0.6170725322297644, 0.20122728168827014, 0.11600447188900964,
                     1.0340702272821236, -0.17359909612055532, -0.12374258242521582, -0.31633207394972157,
                     0.4023613801626831, 0.7457682525800842, 0.1233673250123709, 0.5940312957850438,
                     -0.15662351218366302, 0.5628723891933496, 0.5970277326917596, 0.22068349890057973,
                     0.0905174148005406, 0.9204654974101164},
                    {1.170626609069246, 0.8264348228232881, 0.8167405194962603, 1.0327377086084126, 0.8814961737986139,
                     1.3692905681893843, 0.903309523011217, 0.7005284755794067, 1103772500744.8772,
                     0.9019922851485447}),
       {{{-0.15430376988950145, 0.0720534532850231, 0.4898324420221875},
         {5.689893001203931e-26, 5.780334156732942e-13, 0.4032141584349911}}}},
  };
}

double Distance(const double* a, const double* b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

TEST(LayerNewton, CellSolverIsNeverFartherThanAWitnessInTheLayer) {
  SolveWorkspace ws;
  for (const LayerCase& c : Cases()) {
    const CellSolver solver(c.cell.view());
    for (const Witnessed& w : c.queries) {
      double witnessPoint[3];
      RefEvaluate(c.cell, w.witness.data(), witnessPoint);
      const double witness = Distance(witnessPoint, w.query.data());
      const CellSolveResult r = solver.Solve(w.query.data(), nullptr, &ws);
      EXPECT_LE(r.distance, witness + 1e-9 * solver.size())
          << c.name << ", query " << w.query[0] << " " << w.query[1] << " " << w.query[2] << ": invmap at "
          << r.ref[0] << " " << r.ref[1] << " " << r.ref[2];
      // The reported point is the cell's at the reported parameters (as far
      // as double parameters resolve the layer: 1e-16 of a coordinate moves
      // the map by up to the weight times that).
      double x[3];
      RefEvaluate(c.cell, r.ref, x);
      EXPECT_LE(Distance(x, r.closest), 1e-6 * solver.size()) << c.name;
    }
  }
}

TEST(LayerNewton, CrossesAHyperbolicValleyInAFewSteps) {
  // The first case's first query: its answer lies where s * lambda_0 ~ 6e-12
  // next to the vertex t = 1, on the face r = 0. The active-set solve from
  // (2.2e-5, 0.99997745694, 0), on that valley, took its 100 iterations
  // without reaching the floor.
  const LayerCase c = Cases()[0];
  const Witnessed& w = c.queries[0];
  const CellCharts charts(c.cell.view());
  const double stalled[3] = {2.2283082969612917e-05, 0.99997745694207441, 0.0};
  const int chart = charts.ChartFor(charts.ToBarycentric(0, stalled));
  ASSERT_NE(chart, 0);  // the chart whose free coordinates are s and lambda_0
  double ref[3];
  charts.FromBarycentric(chart, charts.ToBarycentric(0, stalled), ref);
  const int iterations = LayerNewton(charts.view(chart), w.query.data(), c.cell.size(), ref);
  EXPECT_GT(iterations, 0);
  EXPECT_LT(iterations, 20);
  MapJet jet;
  EvaluateMap(charts.view(chart), ref, JetOrder::Value, &jet);
  double witnessPoint[3];
  RefEvaluate(c.cell, w.witness.data(), witnessPoint);
  EXPECT_LE(Distance(jet.x, w.query.data()), Distance(witnessPoint, w.query.data()) + 1e-12);
  // In the domain, still on the face r = 0.
  double back[3];
  charts.FromBarycentric(0, charts.ToBarycentric(chart, ref), back);
  EXPECT_GE(back[0], 0.0);
  EXPECT_GE(back[1], 0.0);
  EXPECT_EQ(back[2], 0.0);
  EXPECT_LE(back[0] + back[1] + back[2], 1.0);
}

TEST(LayerNewton, TheKktTestSeesTheSlopeAlongTheLayer) {
  // The third case's query at the point where the solve used to stop: on
  // the face r = 0, s = 6.4e-13 from the face s = 0 but, next to a weight
  // of 1.2e12, a point of its own (the map moves about 1e12 per unit of s).
  // Along the layer the distance still falls, from 0.0746 there to QA's
  // 0.0640 at t = 0.458; |dx/ds| |r|, 1e11, must not excuse that slope.
  const LayerCase c = Cases()[2];
  const Witnessed& w = c.queries[0];
  const double stopped[3] = {6.390325971012592e-13, 0.3984899207991227, 0.0};
  MapJet jet;
  EvaluateMap(c.cell.view(), stopped, JetOrder::First, &jet);
  EXPECT_FALSE(IsKktPoint(c.cell.view(), jet, w.query.data(), stopped, c.cell.size()));
  // The witness is farther down that slope.
  double witnessPoint[3];
  RefEvaluate(c.cell, w.witness.data(), witnessPoint);
  EXPECT_LT(Distance(witnessPoint, w.query.data()), Distance(jet.x, w.query.data()) - 0.01);
}

TEST(LayerNewton, LeavesAStartOutsideEveryLayerAlone) {
  const LayerCase c = Cases()[0];
  double ref[3] = {0.25, 0.25, 0.25};
  const double point[3] = {0.3, 0.2, 0.1};
  EXPECT_EQ(LayerNewton(c.cell.view(), point, c.cell.size(), ref), 0);
  EXPECT_EQ(ref[0], 0.25);
  EXPECT_EQ(ref[1], 0.25);
  EXPECT_EQ(ref[2], 0.25);
}

}  // namespace
