#include "tests/fem/extraction_model.h"

#include <exodusII.h>
#include <netcdf.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "tests/support/bspline_reference.h"

namespace invmap::testing {
namespace {

double Binomial(int n, int k) {
  double b = 1.0;
  for (int i = 1; i <= k; ++i) b = b * (n - k + i) / i;
  return b;
}

double Bernstein(int p, int j, double s) { return Binomial(p, j) * std::pow(s, j) * std::pow(1.0 - s, p - j); }

/// Bernstein coefficients over span `span` of the degree-p functions
/// span-p .. span of `knots`: row k for function span - p + k.
std::vector<std::vector<double>> SpanExtraction(const std::vector<double>& knots, int p, int span) {
  const double a = knots[span], b = knots[span + 1];
  Eigen::MatrixXd bernstein(p + 1, p + 1), values(p + 1, p + 1);
  for (int m = 0; m <= p; ++m) {
    const double s = (m + 0.5) / (p + 1);
    const std::vector<double> n = CoxDeBoorBasis(knots, p, span, a + s * (b - a));
    for (int j = 0; j <= p; ++j) bernstein(m, j) = Bernstein(p, j, s);
    for (int k = 0; k <= p; ++k) values(m, k) = n[span - p + k];
  }
  const Eigen::MatrixXd c = bernstein.fullPivLu().solve(values);  // c(j, k)
  std::vector<std::vector<double>> rows(p + 1, std::vector<double>(p + 1));
  for (int k = 0; k <= p; ++k) {
    for (int j = 0; j <= p; ++j) rows[k][j] = std::abs(c(j, k)) < 1e-15 ? 0.0 : c(j, k);
  }
  return rows;
}

std::string Number(double x) {
  char text[40];
  std::snprintf(text, sizeof(text), "%.17g", x);
  return text;
}

}  // namespace

std::array<double, 3> TestSpline::Evaluate(const std::array<int, 3>& spans, const std::array<double, 3>& t) const {
  std::vector<double> basis[3] = {{1.0}, {1.0}, {1.0}};
  for (std::size_t d = 0; d < degrees.size(); ++d) basis[d] = CoxDeBoorBasis(knots[d], degrees[d], spans[d], t[d]);
  double sum[4] = {0, 0, 0, 0};
  std::size_t i = 0;
  for (double nw : basis[2]) {
    for (double nv : basis[1]) {
      for (double nu : basis[0]) {
        const double b = nu * nv * nw * (weights.empty() ? 1.0 : weights[i]);
        for (int k = 0; k < 3; ++k) sum[k] += b * points[i][k];
        sum[3] += b;
        ++i;
      }
    }
  }
  return {sum[0] / sum[3], sum[1] / sum[3], sum[2] / sum[3]};
}

std::array<double, 3> TestModel::KnotValues(const TestElement& e, const std::array<double, 3>& s) const {
  const TestSpline& spline = splines[e.spline];
  std::array<double, 3> t{0, 0, 0};
  for (std::size_t d = 0; d < spline.degrees.size(); ++d) {
    const double a = spline.knots[d][e.spans[d]], b = spline.knots[d][e.spans[d] + 1];
    t[d] = a + s[d] * (b - a);
  }
  return t;
}

TestModel Extract(const std::vector<TestSpline>& splines) {
  TestModel model;
  model.splines = splines;
  bool anyRational = false;
  for (const TestSpline& s : splines) anyRational = anyRational || !s.weights.empty();
  for (std::size_t si = 0; si < splines.size(); ++si) {
    const TestSpline& s = splines[si];
    const int first = static_cast<int>(model.points.size());
    model.points.insert(model.points.end(), s.points.begin(), s.points.end());
    if (anyRational) {
      for (std::size_t i = 0; i < s.points.size(); ++i) model.weights.push_back(s.weights.empty() ? 1.0 : s.weights[i]);
    }
    const int dims = static_cast<int>(s.degrees.size());
    std::vector<int> spans[3] = {{0}, {0}, {0}};
    for (int d = 0; d < dims; ++d) {
      spans[d].clear();
      for (int k = s.degrees[d]; k < s.counts[d]; ++k) {
        if (s.knots[d][k] < s.knots[d][k + 1]) spans[d].push_back(k);
      }
    }
    for (int w : spans[2]) {
      for (int v : spans[1]) {
        for (int u : spans[0]) {
          TestElement e;
          e.spline = static_cast<int>(si);
          e.spans = {u, v, w};
          std::vector<std::vector<double>> rows[3] = {{{1.0}}, {{1.0}}, {{1.0}}};
          for (int d = 0; d < dims; ++d) rows[d] = SpanExtraction(s.knots[d], s.degrees[d], e.spans[d]);
          const int nu = static_cast<int>(rows[0].size()), nv = static_cast<int>(rows[1].size());
          const int nw = static_cast<int>(rows[2].size());
          for (int kw = 0; kw < nw; ++kw) {
            for (int kv = 0; kv < nv; ++kv) {
              for (int ku = 0; ku < nu; ++ku) {
                const int gu = dims > 0 ? u - s.degrees[0] + ku : 0;
                const int gv = dims > 1 ? v - s.degrees[1] + kv : 0;
                const int gw = dims > 2 ? w - s.degrees[2] + kw : 0;
                const int cu = s.counts[0], cv = dims > 1 ? s.counts[1] : 1;
                e.points.push_back(first + gu + cu * (gv + cv * gw));
                std::vector<double> vector;
                for (double bw : rows[2][kw]) {
                  for (double bv : rows[1][kv]) {
                    for (double bu : rows[0][ku]) vector.push_back(bu * bv * bw);
                  }
                }
                e.vectors.push_back(static_cast<int>(model.vectors.size()));
                model.vectors.push_back(vector);
              }
            }
          }
          model.elements.push_back(e);
        }
      }
    }
  }
  return model;
}

std::string BextText(const TestModel& model) {
  std::ostringstream out;
  out << "B E X T 2.0\n$#BLOCK 1 - PATCH\n$#   pid      nn      ne     ncv     wfl\n";
  out << 1 << " " << model.points.size() << " " << model.elements.size() << " " << model.vectors.size() << " "
      << (model.weights.empty() ? 0 : 1) << "\n$#BLOCK 2 - NODES\n";
  for (std::size_t i = 0; i < model.points.size(); ++i) {
    out << Number(model.points[i][0]) << " " << Number(model.points[i][1]) << " " << Number(model.points[i][2]) << " "
        << Number(model.weights.empty() ? 1.0 : model.weights[i]) << "\n";
  }
  out << "$#BLOCK 3 - ELEMENTS\n" << model.splines.size() << "\n";
  for (std::size_t s = 0; s < model.splines.size(); ++s) {
    int count = 0, functions = 1;
    for (const TestElement& e : model.elements) count += e.spline == static_cast<int>(s);
    for (int p : model.splines[s].degrees) functions *= p + 1;
    out << "1 " << count << " " << functions << " " << functions;
    for (int p : model.splines[s].degrees) out << " " << p;
    out << "\n";
  }
  // Ids 1-based, at most 10 a line.
  const auto ids = [&](const std::vector<int>& values) {
    for (std::size_t i = 0; i < values.size(); ++i) out << values[i] + 1 << ((i % 10 == 9 || i + 1 == values.size()) ? "\n" : " ");
  };
  for (const TestElement& e : model.elements) {
    ids(e.points);
    ids(e.vectors);
  }
  out << "$#BLOCK 4 - COEFFICIENT VECTORS\n";
  // One dense block per run of vectors of one length, in order, so that
  // the vectors keep the ids the elements use.
  std::vector<std::pair<std::size_t, std::size_t>> runs;  // (count, length)
  for (const std::vector<double>& v : model.vectors) {
    if (runs.empty() || runs.back().second != v.size()) runs.emplace_back(0, v.size());
    ++runs.back().first;
  }
  out << runs.size() << " 0\n";
  for (const auto& [count, length] : runs) out << count << " " << length << "\n";
  for (const std::vector<double>& c : model.vectors) {
    for (std::size_t i = 0; i < c.size(); ++i) out << Number(c[i]) << ((i % 5 == 4 || i + 1 == c.size()) ? "\n" : " ");
  }
  out << "$#END FILE\n";
  return out.str();
}

std::string CubitJsonText(const TestModel& model) {
  std::ostringstream out;
  out << "{\n  \"patch_id\": 0,\n  \"dim\": " << model.splines[0].degrees.size() << ",\n  \"num_elems\": "
      << model.elements.size() << ",\n  \"is_rational\": " << (model.weights.empty() ? "false" : "true")
      << ",\n  \"num_nodes\": " << model.points.size() << ",\n  \"nodes\": [\n";
  for (std::size_t i = 0; i < model.points.size(); ++i) {
    out << "    [ " << Number(model.points[i][0]) << ", " << Number(model.points[i][1]) << ", "
        << Number(model.points[i][2]) << ", " << Number(model.weights.empty() ? 1.0 : model.weights[i]) << " ]"
        << (i + 1 < model.points.size() ? ",\n" : "\n");
  }
  out << "  ],\n  \"elements\": {\n    \"num_elem_blocks\": " << model.splines.size() << ",\n    \"element_block_info\": [";
  for (std::size_t s = 0; s < model.splines.size(); ++s) {
    int count = 0, functions = 1;
    for (const TestElement& e : model.elements) count += e.spline == static_cast<int>(s);
    const std::vector<int>& p = model.splines[s].degrees;
    for (int d : p) functions *= d + 1;
    out << (s ? ", " : " ") << "{ \"element_type\": \"Cube\", \"num_elems\": " << count << ", \"num_nodes\": " << functions
        << ", \"num_coefficient_vectors\": " << functions << ", \"deg_s\": " << p[0]
        << ", \"deg_t\": " << (p.size() > 1 ? p[1] : -1) << ", \"deg_u\": " << (p.size() > 2 ? p[2] : -1) << " }";
  }
  out << " ],\n    \"element_blocks\": [";
  for (std::size_t e = 0; e < model.elements.size(); ++e) {
    out << (e ? ",\n      " : " ") << "{ \"us_cid\": " << 100 + e << ", \"node_ids\": [";
    for (std::size_t i = 0; i < model.elements[e].points.size(); ++i) out << (i ? ", " : " ") << model.elements[e].points[i];
    out << " ], \"coeff_vector_ids\": [";
    for (std::size_t i = 0; i < model.elements[e].vectors.size(); ++i) out << (i ? ", " : " ") << model.elements[e].vectors[i];
    out << " ] }";
  }
  out << " ]\n  },\n  \"coefficients\": {\n    \"num_dense_coeff_blocks\": 1,\n    \"num_sparse_coeff_blocks\": 0,\n"
      << "    \"dense_coefficient_vectors\": [";
  for (std::size_t v = 0; v < model.vectors.size(); ++v) {
    out << (v ? ",\n      " : " ") << "{ \"components\": [";
    for (std::size_t i = 0; i < model.vectors[v].size(); ++i) out << (i ? ", " : " ") << Number(model.vectors[v][i]);
    out << " ] }";
  }
  out << " ],\n    \"sparse_coefficient_vectors\": [ ]\n  },\n  \"block_elem_map\": [";
  for (std::size_t s = 0; s < model.splines.size(); ++s) {
    out << (s ? ", " : " ") << "{ \"block_id\": " << s + 1 << ", \"block_name\": \"block " << s + 1 << "\", \"elem_ids\": [";
    bool first = true;
    for (std::size_t e = 0; e < model.elements.size(); ++e) {
      if (model.elements[e].spline != static_cast<int>(s)) continue;
      out << (first ? " " : ", ") << 100 + e;
      first = false;
    }
    out << " ] }";
  }
  out << " ]\n}\n";
  return out.str();
}

bool WriteExodusBex(const std::string& path, const TestModel& model) {
  ex_opts(EX_DEFAULT);
  int cpuWordSize = 8, ioWordSize = 8;
  const int exoid = ex_create(path.c_str(), EX_CLOBBER, &cpuWordSize, &ioWordSize);
  if (exoid < 0) return false;
  const int numNodes = static_cast<int>(model.points.size());
  bool ok = ex_put_init(exoid, "bex", 3, numNodes, static_cast<int>(model.elements.size()),
                        static_cast<int>(model.splines.size()), 0, 0) >= 0;
  // Control points are stored multiplied by their weight.
  std::vector<double> x, y, z;
  for (int i = 0; i < numNodes; ++i) {
    const double w = model.weights.empty() ? 1.0 : model.weights[i];
    x.push_back(model.points[i][0] * w);
    y.push_back(model.points[i][1] * w);
    z.push_back(model.points[i][2] * w);
  }
  ok = ok && ex_put_coord(exoid, x.data(), y.data(), z.data()) >= 0;
  for (std::size_t s = 0; s < model.splines.size(); ++s) {
    const std::size_t dims = model.splines[s].degrees.size();
    const char* type = dims == 1 ? "BEX_CURVE" : dims == 2 ? "BEX_QUAD" : "BEX_HEX";
    std::vector<int> connectivity;
    int count = 0, n = 0;
    for (const TestElement& e : model.elements) {
      if (e.spline != static_cast<int>(s)) continue;
      ++count;
      n = static_cast<int>(e.points.size());
      for (int p : e.points) connectivity.push_back(p + 1);
      for (int v : e.vectors) connectivity.push_back(v + 1);
    }
    ok = ok && ex_put_block(exoid, EX_ELEM_BLOCK, static_cast<int>(s) + 1, type, count, 2 * n, 0, 0, 0) >= 0;
    ok = ok && ex_put_conn(exoid, EX_ELEM_BLOCK, static_cast<int>(s) + 1, connectivity.data(), nullptr, nullptr) >= 0;
  }
  ok = ok && ex_put_time(exoid, 1, std::vector<double>{0.0}.data()) >= 0;
  // What this Exodus version cannot write: Exodus 8's block attribute and
  // blob, and the nodal attribute, as Cubit lays them out.
  ok = ok && nc_redef(exoid) == NC_NOERR;
  for (std::size_t s = 0; s < model.splines.size(); ++s) {
    int var = -1;
    ok = ok && nc_inq_varid(exoid, ("connect" + std::to_string(s + 1)).c_str(), &var) == NC_NOERR;
    ok = ok && nc_put_att_int(exoid, var, "bex_elem_degrees", NC_INT, model.splines[s].degrees.size(),
                              model.splines[s].degrees.data()) == NC_NOERR;
  }
  std::vector<double> all;
  std::vector<int> info;
  for (const std::vector<double>& v : model.vectors) {
    if (info.empty() || info.back() != static_cast<int>(v.size())) info.insert(info.end(), {0, static_cast<int>(v.size())});
    info[info.size() - 2] += 1;
    all.insert(all.end(), v.begin(), v.end());
  }
  int dimBlob, dimValues, dimVars, dimName, dimTime, dimNodes, dimAttributes;
  ok = ok && nc_def_dim(exoid, "num_blob", 1, &dimBlob) == NC_NOERR;
  ok = ok && nc_def_dim(exoid, "num_values_blob1", all.size(), &dimValues) == NC_NOERR;
  ok = ok && nc_def_dim(exoid, "num_blob_var", 1, &dimVars) == NC_NOERR;
  ok = ok && nc_inq_dimid(exoid, "len_name", &dimName) == NC_NOERR;
  ok = ok && nc_inq_dimid(exoid, "time_step", &dimTime) == NC_NOERR;
  ok = ok && nc_inq_dimid(exoid, "num_nodes", &dimNodes) == NC_NOERR;
  ok = ok && nc_def_dim(exoid, "num_att_in_nblk", 1, &dimAttributes) == NC_NOERR;
  int blob, names, values, attributes, attributeNames;
  ok = ok && nc_def_var(exoid, "blob_entity1", NC_INT, 1, &dimBlob, &blob) == NC_NOERR;
  const int id = 1;
  ok = ok && nc_put_att_int(exoid, blob, "_id", NC_INT, 1, &id) == NC_NOERR;
  ok = ok && nc_put_att_text(exoid, blob, "_name", 11, "bex_cv_blob") == NC_NOERR;
  ok = ok && nc_put_att_int(exoid, blob, "bex_dense_cv_info", NC_INT, info.size(), info.data()) == NC_NOERR;
  const int nameDims[2] = {dimVars, dimName}, valueDims[2] = {dimTime, dimValues};
  const int attributeDims[2] = {dimNodes, dimAttributes}, attributeNameDims[2] = {dimAttributes, dimName};
  ok = ok && nc_def_var(exoid, "name_blob_var", NC_CHAR, 2, nameDims, &names) == NC_NOERR;
  ok = ok && nc_def_var(exoid, "vals_blob_var1blob1", NC_DOUBLE, 2, valueDims, &values) == NC_NOERR;
  ok = ok && nc_def_var(exoid, "nattrb", NC_DOUBLE, 2, attributeDims, &attributes) == NC_NOERR;
  ok = ok && nc_def_var(exoid, "nattrib_name", NC_CHAR, 2, attributeNameDims, &attributeNames) == NC_NOERR;
  ok = ok && nc_enddef(exoid) == NC_NOERR;
  std::size_t nameLength = 0;
  nc_inq_dimlen(exoid, dimName, &nameLength);
  std::string name(nameLength, '\0');
  name.replace(0, 19, "bex_dense_cv_blocks");
  ok = ok && nc_put_var_text(exoid, names, name.data()) == NC_NOERR;
  const std::size_t start[2] = {0, 0}, count[2] = {1, all.size()};
  ok = ok && nc_put_vara_double(exoid, values, start, count, all.data()) == NC_NOERR;
  std::vector<double> weights(model.points.size(), 1.0);
  if (!model.weights.empty()) weights = model.weights;
  ok = ok && nc_put_var_double(exoid, attributes, weights.data()) == NC_NOERR;
  std::string attributeName(nameLength, '\0');
  attributeName.replace(0, 10, "bex_weight");
  ok = ok && nc_put_var_text(exoid, attributeNames, attributeName.data()) == NC_NOERR;
  return ex_close(exoid) >= 0 && ok;
}

}  // namespace invmap::testing
