// The solids of a model of several, each as a model of its own, to tell
// whether a point is inside a given one. In an assembly two solids may
// touch (coincident faces) or nest, so the face nearest a point, whose
// normal signs it, may belong to a solid other than the one holding the
// point. A point inside solid S has its closest point on the whole model
// within S's closure, so only the solids whose box holds that closest
// point can hold the point; each of those is asked on its own: the point
// inverted on that solid's faces alone and signed by its pseudo-normals,
// which is exact for one solid (cad/pseudo_normals.h).
#pragma once

#include <Bnd_Box.hxx>
#include <TopoDS_Shape.hxx>

#include <cstddef>
#include <memory>
#include <mutex>
#include <vector>

namespace invmap::cad {

struct ConvertedModel;

class SolidParts {
 public:
  SolidParts();
  ~SolidParts();
  SolidParts(const SolidParts&) = delete;
  SolidParts& operator=(const SolidParts&) = delete;

  /// Records the solids and their boxes, grown by 1e-7 of the model's size
  /// for the gaps between coincident faces; the solids' own models are
  /// built when first asked about, from `whole`'s converted faces (the
  /// model's, which must outlive this), or converted again when solids
  /// share edges.
  void Build(const std::vector<TopoDS_Shape>& solids, const ConvertedModel& whole);

  std::size_t Count() const { return solids_.size(); }
  /// False when solid `solid` certainly does not hold the point whose
  /// closest point on the model is `closest`.
  bool MayHold(int solid, const double* closest) const;

  /// For `xyz` (3 per point): -1 for the points inside solid `solid`, +1
  /// outside, NaN where its own inversion found none. Thread-safe.
  std::vector<double> Signs(int solid, const std::vector<double>& xyz, int threads) const;

 private:
  struct Part;
  /// The part of `solid`, built on first use (nullptr when it cannot be
  /// built; Signs then asks OpenCascade's classifier).
  const Part* PartOf(int solid) const;

  const ConvertedModel* whole_ = nullptr;
  std::vector<TopoDS_Shape> solids_;
  std::vector<Bnd_Box> boxes_;
  double size_ = 1.0;
  mutable std::vector<std::once_flag> built_;
  mutable std::vector<std::unique_ptr<Part>> parts_;
};

}  // namespace invmap::cad
