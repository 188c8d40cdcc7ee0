#pragma once
// The sphere-tree builder's stages, shared by its .cpp files only (private to
// core/spheretree; no CGAL type here). BuildSphereTree (builder.cpp) runs them in
// order: surface pieces (surface_pieces.cpp), medial candidates
// (medial_candidates.cpp), the cover (cover.cpp), leaf refinement
// (leaf_refine.cpp), and the hierarchy (hierarchy.cpp).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numeric>
#include <string_view>
#include <utility>
#include <vector>

#include "core/geometry/mesh.h"
#include "core/spheretree/builder.h"

namespace sulcus {
class MeshOracle;
}

namespace sulcus::tree_build {

// Reports progress and turns a "stop" answer into BuildCancelled.
// Progress never runs backwards: a stage met again (a second, finer cover after
// the first tightening) reports where the build already was.
class Reporter {
 public:
  explicit Reporter(BuildProgress fn) : fn_(std::move(fn)) {}
  void operator()(std::string_view stage, double fraction) const {
    last_ = std::max(last_, std::clamp(fraction, 0.0, 1.0));
    if (fn_ && !fn_(stage, last_)) throw BuildCancelled();
  }

 private:
  BuildProgress fn_;
  mutable double last_ = 0;
};

// ---- Surface pieces (surface_pieces.cpp) ----

// A flat piece of the surface; the cover works on these. A sphere that holds a
// piece's three corners holds the whole piece.
struct Piece {
  Vector3 v[3];
  Vector3 centroid;
};

Piece MakePiece(const Vector3& a, const Vector3& b, const Vector3& c);

// Farthest corner of a piece from c (squared).
inline double FarCorner2(const Piece& p, const Vector3& c) {
  const double a = (p.v[0] - c).squaredNorm(), b = (p.v[1] - c).squaredNorm(),
               d = (p.v[2] - c).squaredNorm();
  return std::max(std::max(a, b), d);
}

// Splits every face into n^2 similar pieces, n chosen so that edges are <= h.
// Each piece's face normal, turned by `orientation` (+1 or -1), goes to `normals`.
std::vector<Piece> Subdivide(const TriangleMesh& mesh, double h,
                             std::vector<Vector3>* normals, double orientation);

// FarCorner2 of a piece whose three corners are the 9 coordinates at v, summed
// in this order: the cover's query and the tests that must agree with it
// exactly compute it so.
inline double FarCorner2Of(const double* v, double cx, double cy, double cz) {
  double m = 0;
  for (int k = 0; k < 3; ++k, v += 3) {
    const double dx = v[0] - cx, dy = v[1] - cy, dz = v[2] - cz;
    m = std::max(m, dx * dx + dy * dy + dz * dz);
  }
  return m;
}

// Builds a binary hierarchy over order[begin, end) into nodes[slot] and the
// nodes after it: make(begin, end) gives a node over those items (its `box`
// and what else it keeps, `left` = -1); one of more than `bucket` items is
// ordered about its middle along its box's longest axis by point(i) and gets
// two children, at `left` and `left` + 1. The two hierarchies here (over
// pieces, and over balls' centres) are built so.
template <typename Node, typename Make, typename Point>
void BuildMedianTree(std::vector<std::int32_t>* order, std::vector<Node>* nodes,
                     std::int32_t slot, std::int32_t begin, std::int32_t end,
                     std::int32_t bucket, const Make& make, const Point& point) {
  (*nodes)[slot] = make(begin, end);
  if (end - begin <= bucket) return;
  int axis;
  (*nodes)[slot].box.extent().maxCoeff(&axis);
  const std::int32_t mid = begin + (end - begin) / 2;
  std::nth_element(
      order->begin() + begin, order->begin() + mid, order->begin() + end,
      [&](std::int32_t a, std::int32_t b) { return point(a)[axis] < point(b)[axis]; });
  const auto left = static_cast<std::int32_t>(nodes->size());
  nodes->emplace_back();
  nodes->emplace_back();
  BuildMedianTree(order, nodes, left, begin, mid, bucket, make, point);
  BuildMedianTree(order, nodes, left + 1, mid, end, bucket, make, point);
  (*nodes)[slot].left = left;
}

// Depth first over a hierarchy that BuildMedianTree made (the root first, a
// node's children at left and left + 1, none when left < 0), the right child
// first: `visit(node)` says whether to go on into its children (a leaf's
// items are the visitor's to go through).
template <typename Node, typename Visit>
void VisitNodes(const std::vector<Node>& nodes, Visit&& visit) {
  if (nodes.empty()) return;
  std::int32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes[stack[--top]];
    if (!visit(n) || n.left < 0) continue;
    stack[top++] = n.left;
    stack[top++] = n.left + 1;
  }
}

// A bounding-volume hierarchy over pieces (boxes around their corners), for
// "which pieces lie wholly inside this ball" queries: only nodes whose box meets
// the ball are visited, and a node whose box is inside the ball is taken whole.
class PieceBvh {
 public:
  explicit PieceBvh(const std::vector<Piece>& pieces) : pieces_(pieces) {
    order_.resize(pieces.size());
    std::iota(order_.begin(), order_.end(), 0);
    nodes_.reserve(2 * pieces.size() / kLeafSize + 2);
    if (pieces.empty()) return;
    nodes_.push_back({});
    BuildMedianTree(
        &order_, &nodes_, 0, 0, static_cast<std::int32_t>(pieces.size()), kLeafSize,
        [&](std::int32_t begin, std::int32_t end) {
          Aabb box;
          for (std::int32_t i = begin; i < end; ++i)
            for (const Vector3& v : pieces_[order_[i]].v) box.Extend(v);
          return Node{box, begin, end, -1};
        },
        [&](std::int32_t i) { return pieces_[i].centroid; });
    // The corners again, in the hierarchy's order: a query reads them in a row.
    corners_.reserve(9 * pieces.size());
    for (const std::int32_t i : order_)
      for (const Vector3& v : pieces[i].v)
        corners_.insert(corners_.end(), {v.x(), v.y(), v.z()});
  }

  // Calls fn(piece, r2) for every piece whose three corners are within
  // `radius` of c, r2 being FarCorner2(piece, c).
  template <typename Fn>
  void ForEachEnclosed(const Vector3& c, double radius, Fn&& fn) const {
    const double r2 = radius * radius;
    const double cx = c.x(), cy = c.y(), cz = c.z();
    auto far2 = [&](std::int32_t i) {
      return FarCorner2Of(&corners_[9 * static_cast<std::size_t>(i)], cx, cy, cz);
    };
    VisitNodes(nodes_, [&](const Node& n) {
      const Vector3 near = c.cwiseMax(n.box.min).cwiseMin(n.box.max);
      if ((near - c).squaredNorm() > r2) return false;
      const Vector3 far = (c - n.box.min).cwiseAbs().cwiseMax((c - n.box.max).cwiseAbs());
      if (far.squaredNorm() <= r2) {  // the whole box is inside the ball
        for (std::int32_t i = n.begin; i < n.end; ++i) fn(order_[i], far2(i));
        return false;
      }
      if (n.left < 0) {
        for (std::int32_t i = n.begin; i < n.end; ++i) {
          const double d2 = far2(i);
          if (d2 <= r2) fn(order_[i], d2);
        }
      }
      return true;
    });
  }

 private:
  static constexpr std::int32_t kLeafSize = 8;
  struct Node {
    Aabb box;
    std::int32_t begin, end, left;  // left < 0: a leaf; children at left, left + 1
  };

  const std::vector<Piece>& pieces_;
  std::vector<std::int32_t> order_;
  std::vector<Node> nodes_;
  std::vector<double> corners_;  // 9 per piece, in order_
};

// ---- Medial candidates (medial_candidates.cpp) ----

// A medial sphere candidate: centre inside the solid and its depth (distance to
// the surface). A leaf centred there with radius R protrudes at most R - depth.
struct Candidate {
  Vector3 c;
  double depth;
};

// Candidate centres: the inner Voronoi pole of each surface sample (the farthest
// Voronoi vertex of its cell on the inner side, Amenta's pole), plus points on
// the way from each sample to its pole, so that thin and sharp regions have
// shallow spheres too. Only centres inside the solid are kept.
std::vector<Candidate> MedialCandidates(const std::vector<Vector3>& samples,
                                        const std::vector<Vector3>& normals, double diag,
                                        double thin_cell, const MeshOracle& oracle,
                                        const Reporter& report);

// ---- The cover (cover.cpp) ----

// For each candidate, the pieces it can enclose with a protrusion bound of at most
// `eps_max`, sorted by the bound each needs (CSR form). A cover at any eps <=
// eps_max then uses a prefix of every list, so the bisection over eps reuses them.
struct CoverLists {
  std::vector<std::int64_t> start;
  std::vector<std::int32_t> items;
  std::vector<float> need;  // protrusion bound needed for the item, ascending per list
};

CoverLists ComputeCovers(const std::vector<Candidate>& cands, const PieceBvh& bvh,
                         double eps_max);

// Lazy greedy set cover using, for each candidate, the pieces it encloses within
// eps, or within limit[piece] where that is larger (pieces whose best possible
// bound is above eps). Returns the chosen candidates, or nothing when the pieces
// cannot be covered or need more than `budget` spheres.
std::vector<std::int32_t> GreedyCover(const CoverLists& lists, double eps,
                                      std::size_t num_pieces, std::size_t budget,
                                      const std::vector<float>* limit = nullptr);

// The least protrusion bound with which any candidate encloses each piece.
std::vector<float> PieceFloors(const CoverLists& lists, std::size_t num_pieces);

// The greedy cover at the smallest protrusion bound (to 2 %) that fits the
// budget, with the cover lists it was computed from. Pieces whose best bound
// (over all candidates) is above the bound may use kFloorSlack times their best
// instead, so that a few hard pieces do not set the bound for the whole surface.
struct MinMaxCover {
  std::vector<std::int32_t> chosen;
  double eps = 0;
  CoverLists lists;      // computed at lists_eps >= eps
  double lists_eps = 0;  // every piece has an entry: the lists can be reused below it
  std::vector<float> limits;  // per piece: kFloorSlack times its best bound
};

// `reach_eps` > 0 is a bound at which every piece was reachable before (the
// previous round's lists): the bracket starts there.
MinMaxCover CoverWithBudget(const std::vector<Candidate>& cands,
                            const std::vector<Piece>& pieces, std::size_t budget,
                            double start_eps, double reach_eps, double diag,
                            const std::function<void()>& tick);

// Splits the marked pieces into four at their edge midpoints.
std::vector<Piece> SplitPieces(const std::vector<Piece>& pieces,
                               const std::vector<char>& split);

// Protrusion bound of a sphere centred at c (depth d) that encloses the pieces.
double CoverError(const Vector3& c, double depth, const std::vector<Piece>& pieces,
                  const std::vector<std::int32_t>& members);

// CoverError when it is below `limit`; otherwise some value >= limit, found as
// soon as one piece shows it.
double CoverErrorBelow(const Vector3& c, double depth, const std::vector<Piece>& pieces,
                       const std::vector<std::int32_t>& members, double limit);

// ---- Leaf refinement (leaf_refine.cpp) ----

struct Leaf {
  Vector3 c;
  double depth;
  std::vector<std::int32_t> pieces;
};

// Balls (anything with a centre c and a depth: leaves, candidates) in a k-d
// tree of their centres, each node with the deepest ball under it: a node
// whose box is farther from a piece than the best bound found plus that depth
// holds no better ball (AssignPieces, and the pieces' first reach in the
// cover's bracket).
template <typename Ball>
class CentreKdTree {
 public:
  explicit CentreKdTree(const std::vector<Ball>& balls) : balls_(balls) {
    order_.resize(balls.size());
    std::iota(order_.begin(), order_.end(), 0);
    if (balls.empty()) return;
    nodes_.reserve(2 * balls.size() / kBucket + 2);
    nodes_.push_back({});
    BuildMedianTree(
        &order_, &nodes_, 0, 0, static_cast<std::int32_t>(balls.size()), kBucket,
        [&](std::int32_t begin, std::int32_t end) {
          Node n;
          n.begin = begin;
          n.end = end;
          n.max_depth = -std::numeric_limits<double>::infinity();
          for (std::int32_t k = begin; k < end; ++k) {
            n.box.Extend(balls_[order_[k]].c);
            n.max_depth = std::max(n.max_depth, balls_[order_[k]].depth);
          }
          return n;
        },
        [&](std::int32_t i) { return balls_[i].c; });
  }

  // The ball with the smallest bound sqrt(FarCorner2(piece, c)) - depth,
  // the lowest index among equals (as a scan in index order finds it).
  std::size_t Best(const Piece& piece) const {
    double best = std::numeric_limits<double>::infinity();
    std::size_t best_ball = 0;
    const Vector3& x = piece.centroid;
    std::int32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes_[stack[--top]];
      const Vector3 near = x.cwiseMax(n.box.min).cwiseMin(n.box.max);
      // (a margin for rounding: a node is passed over only when clearly worse)
      const double lower = (near - x).norm() - n.max_depth;
      if (lower > best + 1e-9 * (1 + std::abs(best))) continue;
      if (n.left < 0) {
        for (std::int32_t k = n.begin; k < n.end; ++k) {
          const auto i = static_cast<std::size_t>(order_[k]);
          const Ball& l = balls_[i];
          // The centroid's distance is a lower bound on the far corner's.
          if ((x - l.c).norm() - l.depth > best) continue;
          const double e = std::sqrt(FarCorner2(piece, l.c)) - l.depth;
          if (e < best || (e == best && i < best_ball)) {
            best = e;
            best_ball = i;
          }
        }
        continue;
      }
      // The nearer child on top, searched first.
      const Node& a = nodes_[n.left];
      const bool left_near =
          (x.cwiseMax(a.box.min).cwiseMin(a.box.max) - x).squaredNorm() <=
          (x.cwiseMax(nodes_[n.left + 1].box.min).cwiseMin(nodes_[n.left + 1].box.max) -
           x)
              .squaredNorm();
      stack[top++] = left_near ? n.left + 1 : n.left;
      stack[top++] = left_near ? n.left : n.left + 1;
    }
    return best_ball;
  }

  // The indices of the balls whose bound from x, |x - c| - depth, is at most
  // `bound` (and a few within rounding of it), in increasing order: every
  // ball that can enclose a piece of centroid x within the protrusion
  // `bound`, since no point of a piece lies further from a centre than its
  // farthest corner.
  void Within(const Vector3& x, double bound, std::vector<std::int32_t>* out) const {
    out->clear();
    const double slack = bound + 1e-9 * (1 + std::abs(bound));
    VisitNodes(nodes_, [&](const Node& n) {
      const Vector3 near = x.cwiseMax(n.box.min).cwiseMin(n.box.max);
      if ((near - x).norm() - n.max_depth > slack) return false;
      if (n.left < 0) {
        for (std::int32_t k = n.begin; k < n.end; ++k) {
          const Ball& l = balls_[order_[k]];
          if ((x - l.c).norm() - l.depth <= slack) out->push_back(order_[k]);
        }
      }
      return true;
    });
    std::sort(out->begin(), out->end());
  }

 private:
  static constexpr std::int32_t kBucket = 8;
  struct Node {
    Aabb box;  // of the centres
    double max_depth = 0;
    std::int32_t begin = 0, end = 0, left = -1;
  };

  const std::vector<Ball>& balls_;
  std::vector<std::int32_t> order_;
  std::vector<Node> nodes_;
};

// Gives each piece to the leaf that encloses it with the smallest protrusion bound.
void AssignPieces(std::vector<Leaf>* leaves, const std::vector<Piece>& pieces);

// Medial candidates bucketed in a uniform grid, for "candidates near this
// point" queries.
class CandidateIndex {
 public:
  CandidateIndex(const std::vector<Candidate>& cands, double cell_hint) : cands_(cands) {
    for (const Candidate& c : cands) box_.Extend(c.c);
    const Vector3 extent = box_.extent();
    // At most about 64^3 cells, at least cell_hint wide.
    cell_ = std::max({cell_hint, extent.maxCoeff() / 64.0, 1e-9});
    for (int k = 0; k < 3; ++k) dims_[k] = static_cast<int>(extent[k] / cell_) + 1;
    const std::size_t cells = static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2];
    start_.assign(cells + 1, 0);
    std::vector<std::int64_t> cell_of(cands.size());
    for (std::size_t i = 0; i < cands.size(); ++i) {
      cell_of[i] = CellOf(cands[i].c);
      ++start_[cell_of[i] + 1];
    }
    std::partial_sum(start_.begin(), start_.end(), start_.begin());
    items_.resize(cands.size());
    std::vector<std::int64_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < cands.size(); ++i)
      items_[fill[cell_of[i]]++] = static_cast<std::int32_t>(i);
  }

  const std::vector<Candidate>& cands() const { return cands_; }

  // Calls fn(candidate) for the candidates within `radius` of p (and a few more).
  template <typename Fn>
  void ForEachNear(const Vector3& p, double radius, Fn&& fn) const {
    int lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
      lo[k] =
          std::clamp(static_cast<int>(std::floor((p[k] - radius - box_.min[k]) / cell_)),
                     0, dims_[k] - 1);
      hi[k] =
          std::clamp(static_cast<int>(std::floor((p[k] + radius - box_.min[k]) / cell_)),
                     0, dims_[k] - 1);
    }
    for (int x = lo[0]; x <= hi[0]; ++x) {
      for (int y = lo[1]; y <= hi[1]; ++y) {
        for (int z = lo[2]; z <= hi[2]; ++z) {
          const std::int64_t cell =
              (static_cast<std::int64_t>(z) * dims_[1] + y) * dims_[0] + x;
          for (std::int64_t i = start_[cell]; i < start_[cell + 1]; ++i)
            fn(cands_[items_[i]]);
        }
      }
    }
  }

 private:
  std::int64_t CellOf(const Vector3& p) const {
    int idx[3];
    for (int k = 0; k < 3; ++k) {
      idx[k] =
          std::clamp(static_cast<int>((p[k] - box_.min[k]) / cell_), 0, dims_[k] - 1);
    }
    return (static_cast<std::int64_t>(idx[2]) * dims_[1] + idx[1]) * dims_[0] + idx[0];
  }

  const std::vector<Candidate>& cands_;
  Aabb box_;
  double cell_ = 1;
  int dims_[3] = {1, 1, 1};
  std::vector<std::int64_t> start_;
  std::vector<std::int32_t> items_;
};

// Re-centres every leaf (RefineLeaf on each).
void RefineLeaves(std::vector<Leaf>* leaves, const std::vector<Piece>& pieces,
                  const CandidateIndex& index, const MeshOracle& oracle,
                  bool toward_ball = true);

// Tightens a cover without adding leaves or losing coverage (a leaf left with no
// pieces is dropped, for SplitLeavesInTwo to spend again). Each
// round: splits the pieces that set a leaf's radius (so its region's border can
// move at a finer grain), hands every piece to the leaf that already encloses it
// with the widest margin (so no leaf grows and the ones whose far pieces are
// taken shrink), then re-centres the leaves on their pieces. Every step keeps
// each piece inside its leaf, so coverage stays complete.
void ShrinkLeaves(std::vector<Leaf>* leaves, std::vector<Piece>* pieces,
                  const CandidateIndex& index, const MeshOracle& oracle,
                  std::size_t max_pieces, int rounds);

// Local search on the sum of the leaves' protrusion bounds (the mean the fit
// is judged by) at a fixed leaf count. Removing a leaf costs the growth of the
// neighbours that take its pieces, less its own bound; cutting a leaf in two
// gains its bound less its halves'. Each round pairs the cheapest removals with
// the best cuts, every leaf in at most one swap, and makes a swap only when the
// cut gains more than the removal costs; free slots in the budget go to cuts
// that gain. No leaf grows past `cap`, and a removed leaf's pieces all go to
// neighbours grown to hold them, so coverage stays complete. Plans and cuts
// are kept from round to round for the leaves whose neighbourhood did not change.
void SwapLeaves(std::vector<Leaf>* leaves, const std::vector<Piece>& pieces,
                const CandidateIndex& index, const MeshOracle& oracle, double cap,
                std::size_t budget, int rounds);

// Moves leaf borders where that lowers the sum of radii: each leaf in turn
// gives its farthest pieces to the neighbours that take them for the least
// growth, as many as pay (its shrink, to the next farthest piece, above the
// neighbours' total growth). No neighbour grows past `cap` (a bound); every
// piece stays inside the leaf that holds it, so coverage stays complete.
void TradePieces(std::vector<Leaf>* leaves, const std::vector<Piece>& pieces,
                 const CandidateIndex& index, const MeshOracle& oracle, double cap,
                 int rounds);

// Spends the leaf budget on the leaves with the largest protrusion bound, each
// cut by SplitInTwo. A cut that does not lower the bound by 5 % is not made; a
// round patch rarely gains from two spheres, so this mostly splits long ones.
void SplitLeavesInTwo(std::vector<Leaf>* leaves, std::size_t budget,
                      const std::vector<Piece>& pieces, const CandidateIndex& index,
                      const MeshOracle& oracle);

}  // namespace sulcus::tree_build
