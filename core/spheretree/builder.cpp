#include "core/spheretree/builder.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Min_sphere_of_spheres_d.h>
#include <CGAL/Min_sphere_of_spheres_d_traits_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <queue>
#include <sstream>
#include <unordered_map>
#include <utility>

#include "core/spheretree/mesh_oracle.h"
#include "core/spheretree/random.h"

namespace sulcus {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

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

using detail::Uniform;

// A flat piece of the surface; the cover works on these. A sphere that holds a
// piece's three corners holds the whole piece.
struct Piece {
  Vector3 v[3];
  Vector3 centroid;
};

Piece MakePiece(const Vector3& a, const Vector3& b, const Vector3& c) {
  Piece p;
  p.v[0] = a;
  p.v[1] = b;
  p.v[2] = c;
  p.centroid = (a + b + c) / 3.0;
  return p;
}

// Farthest corner of a piece from c (squared).
double FarCorner2(const Piece& p, const Vector3& c) {
  return std::max({(p.v[0] - c).squaredNorm(), (p.v[1] - c).squaredNorm(),
                   (p.v[2] - c).squaredNorm()});
}

// Splits every face into n^2 similar pieces, n chosen so that edges are <= h.
std::vector<Piece> Subdivide(const TriangleMesh& mesh, double h,
                             std::vector<Vector3>* normals, double orientation) {
  std::vector<Piece> pieces;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const auto& face = mesh.faces()[f];
    const Vector3 a = mesh.vertices()[face[0]], b = mesh.vertices()[face[1]],
                  c = mesh.vertices()[face[2]];
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const int n = std::max(1, static_cast<int>(std::ceil(longest / h)));
    const Vector3 normal = orientation * mesh.FaceNormal(f);
    auto at = [&](int i, int j) {
      return Vector3(a + (b - a) * i / n + (c - a) * j / n);
    };
    for (int i = 0; i < n; ++i) {
      for (int j = 0; i + j < n; ++j) {
        pieces.push_back(MakePiece(at(i, j), at(i + 1, j), at(i, j + 1)));
        normals->push_back(normal);
        if (i + j + 1 < n) {
          pieces.push_back(MakePiece(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)));
          normals->push_back(normal);
        }
      }
    }
  }
  return pieces;
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
    BuildInto(0, 0, static_cast<std::int32_t>(pieces.size()));
  }

  // Calls fn(piece) for every piece whose three corners are within `radius` of c.
  template <typename Fn>
  void ForEachEnclosed(const Vector3& c, double radius, Fn&& fn) const {
    if (nodes_.empty()) return;
    const double r2 = radius * radius;
    std::int32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes_[stack[--top]];
      const Vector3 near = c.cwiseMax(n.box.min).cwiseMin(n.box.max);
      if ((near - c).squaredNorm() > r2) continue;
      const Vector3 far = (c - n.box.min).cwiseAbs().cwiseMax((c - n.box.max).cwiseAbs());
      if (far.squaredNorm() <= r2) {  // the whole box is inside the ball
        for (std::int32_t i = n.begin; i < n.end; ++i) fn(order_[i]);
        continue;
      }
      if (n.left < 0) {
        for (std::int32_t i = n.begin; i < n.end; ++i) {
          const Piece& p = pieces_[order_[i]];
          if (FarCorner2(p, c) <= r2) fn(order_[i]);
        }
        continue;
      }
      stack[top++] = n.left;
      stack[top++] = n.left + 1;
    }
  }

 private:
  static constexpr std::int32_t kLeafSize = 8;
  struct Node {
    Aabb box;
    std::int32_t begin, end, left;  // left < 0: a leaf; children at left, left + 1
  };

  void BuildInto(std::int32_t slot, std::int32_t begin, std::int32_t end) {
    Aabb box;
    for (std::int32_t i = begin; i < end; ++i) {
      for (const Vector3& v : pieces_[order_[i]].v) box.Extend(v);
    }
    nodes_[slot] = {box, begin, end, -1};
    if (end - begin <= kLeafSize) return;
    int axis;
    box.extent().maxCoeff(&axis);
    const std::int32_t mid = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](std::int32_t a, std::int32_t b) {
                       return pieces_[a].centroid[axis] < pieces_[b].centroid[axis];
                     });
    // Children are allocated as a pair so that the right one is left + 1.
    const auto left = static_cast<std::int32_t>(nodes_.size());
    nodes_.push_back({});
    nodes_.push_back({});
    BuildInto(left, begin, mid);
    BuildInto(left + 1, mid, end);
    nodes_[slot].left = left;
  }

  const std::vector<Piece>& pieces_;
  std::vector<std::int32_t> order_;
  std::vector<Node> nodes_;
};

// A medial sphere candidate: centre inside the solid and its depth (distance to
// the surface). A leaf centred there with radius R protrudes at most R - depth.
struct Candidate {
  Vector3 c;
  double depth;
};

// Keeps the deepest candidate in each cell of a grid `cell` wide, in the input's
// order.
std::vector<Candidate> ThinCandidates(std::vector<Candidate> cands, double cell) {
  std::unordered_map<std::uint64_t, std::size_t> best;
  best.reserve(cands.size());
  auto key = [&](const Vector3& p) {
    std::uint64_t k = 0;
    for (int a = 0; a < 3; ++a) {
      const auto i = static_cast<std::int64_t>(std::floor(p[a] / cell));
      k = k * 2097152u + static_cast<std::uint64_t>(i & 0x1FFFFF);  // 21 bits per axis
    }
    return k;
  };
  for (std::size_t i = 0; i < cands.size(); ++i) {
    auto [it, fresh] = best.emplace(key(cands[i].c), i);
    if (!fresh && cands[i].depth > cands[it->second].depth) it->second = i;
  }
  std::vector<char> keep(cands.size(), 0);
  for (const auto& entry : best) keep[entry.second] = 1;
  std::vector<Candidate> out;
  out.reserve(best.size());
  for (std::size_t i = 0; i < cands.size(); ++i) {
    if (keep[i]) out.push_back(cands[i]);
  }
  return out;
}

// Centre of the sphere through four points; false for a (nearly) flat tetrahedron,
// whose circumcentre is at or near infinity.
bool Circumcenter(const Vector3 (&p)[4], Vector3* center) {
  const Vector3 a = p[1] - p[0], b = p[2] - p[0], c = p[3] - p[0];
  const double den = 2.0 * a.dot(b.cross(c));
  if (!(std::abs(den) > 1e-12 * a.norm() * b.norm() * c.norm())) return false;
  *center = p[0] + (a.squaredNorm() * b.cross(c) + b.squaredNorm() * c.cross(a) +
                    c.squaredNorm() * a.cross(b)) /
                       den;
  return center->allFinite();
}

// Candidate centres: the inner Voronoi pole of each surface sample (the farthest
// Voronoi vertex of its cell on the inner side, Amenta's pole), plus points on
// the way from each sample to its pole, so that thin and sharp regions have
// shallow spheres too. Only centres inside the solid are kept.
std::vector<Candidate> MedialCandidates(const std::vector<Vector3>& samples,
                                        const std::vector<Vector3>& normals, double diag,
                                        double thin_cell, const MeshOracle& oracle,
                                        const Reporter& report) {
  using Vb = CGAL::Triangulation_vertex_base_with_info_3<std::int32_t, K>;
  using Tds = CGAL::Triangulation_data_structure_3<Vb>;
  using Delaunay = CGAL::Delaunay_triangulation_3<K, Tds>;
  std::vector<std::pair<K::Point_3, std::int32_t>> points;
  points.reserve(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    points.emplace_back(K::Point_3(samples[i].x(), samples[i].y(), samples[i].z()),
                        static_cast<std::int32_t>(i));
  }
  const Delaunay dt(points.begin(), points.end());
  report("medial axis: Delaunay done", 0.25);

  std::vector<double> best(samples.size(), 0.0);
  std::vector<Vector3> pole(samples.size(), Vector3::Zero());
  const double max2 = diag * diag;
  for (auto cell : dt.finite_cell_handles()) {
    Vector3 corner[4];
    for (int k = 0; k < 4; ++k) {
      const K::Point_3& q = cell->vertex(k)->point();
      corner[k] = Vector3(q.x(), q.y(), q.z());
    }
    Vector3 center;
    if (!Circumcenter(corner, &center)) continue;  // a flat sliver: no Voronoi vertex
    for (int k = 0; k < 4; ++k) {
      const std::int32_t s = cell->vertex(k)->info();
      const Vector3 d = center - samples[s];
      const double d2 = d.squaredNorm();
      if (d.dot(normals[s]) < 0 && d2 > best[s] && d2 < max2) {
        best[s] = d2;
        pole[s] = center;
      }
    }
  }

  // Each with its distance to the sample it came from, an upper bound of its
  // depth, until the mesh is asked.
  std::vector<Candidate> points_to_try;
  points_to_try.reserve(samples.size() * 3);
  for (std::size_t s = 0; s < samples.size(); ++s) {
    if (best[s] > 0) {
      const double reach = std::sqrt(best[s]);
      points_to_try.push_back({pole[s], reach});
      for (double f : {0.15, 0.45})
        points_to_try.push_back({samples[s] + f * (pole[s] - samples[s]), f * reach});
    }
  }
  // The deepest-looking point in each cell of the grid: neighbours that close
  // enclose nearly the same pieces, and fewer candidates make the cover lists
  // shorter and the mesh queries fewer.
  points_to_try = ThinCandidates(std::move(points_to_try), thin_cell);

  std::vector<Candidate> out;
  out.reserve(points_to_try.size());
  const double min_depth = 1e-7 * diag;
  for (std::size_t i = 0; i < points_to_try.size(); ++i) {
    if (i % 2048 == 0)
      report("medial axis: depths", 0.25 + 0.75 * i / points_to_try.size());
    const Vector3& p = points_to_try[i].c;
    if (!oracle.Inside(p)) continue;
    const double depth = oracle.Distance(p);
    if (depth > min_depth) out.push_back({p, depth});
  }
  return out;
}

// For each candidate, the pieces it can enclose with a protrusion bound of at most
// `eps_max`, sorted by the bound each needs (CSR form). A cover at any eps <=
// eps_max then uses a prefix of every list, so the bisection over eps reuses them.
struct CoverLists {
  std::vector<std::int64_t> start;
  std::vector<std::int32_t> items;
  std::vector<float> need;  // protrusion bound needed for the item, ascending per list
};

CoverLists ComputeCovers(const std::vector<Candidate>& cands,
                         const std::vector<Piece>& pieces, const PieceBvh& bvh,
                         double eps_max) {
  CoverLists lists;
  lists.start.reserve(cands.size() + 1);
  lists.start.push_back(0);
  std::vector<std::pair<float, std::int32_t>> found;
  for (const Candidate& c : cands) {
    found.clear();
    bvh.ForEachEnclosed(c.c, c.depth + eps_max, [&](std::int32_t p) {
      const double r2 = FarCorner2(pieces[p], c.c);
      // Rounded up so that a prefix never claims a piece it does not enclose.
      found.push_back(
          {std::nextafter(static_cast<float>(std::sqrt(r2) - c.depth), 1e30f), p});
    });
    std::sort(found.begin(), found.end());
    for (const auto& [need, p] : found) {
      lists.items.push_back(p);
      lists.need.push_back(need);
    }
    lists.start.push_back(static_cast<std::int64_t>(lists.items.size()));
  }
  return lists;
}

// Lazy greedy set cover using, for each candidate, the pieces it encloses within
// eps, or within limit[piece] where that is larger (pieces whose best possible
// bound is above eps). Returns the chosen candidates, or nothing when the pieces
// cannot be covered or need more than `budget` spheres.
std::vector<std::int32_t> GreedyCover(const CoverLists& lists, double eps,
                                      std::size_t num_pieces, std::size_t budget,
                                      const std::vector<float>* limit = nullptr) {
  const auto n = static_cast<std::int32_t>(lists.start.size() - 1);
  // The usable part of each list, in CSR form.
  std::vector<std::int64_t> start(n + 1, 0);
  std::vector<std::int32_t> items;
  items.reserve(lists.items.size() / 2);
  const auto feps = static_cast<float>(eps);
  for (std::int32_t i = 0; i < n; ++i) {
    for (std::int64_t k = lists.start[i]; k < lists.start[i + 1]; ++k) {
      const float need = lists.need[k];
      if (need <= feps) {
        items.push_back(lists.items[k]);
      } else if (limit == nullptr) {
        break;  // sorted: nothing further fits
      } else if (need <= (*limit)[lists.items[k]]) {
        items.push_back(lists.items[k]);
      }
    }
    start[i + 1] = static_cast<std::int64_t>(items.size());
  }
  std::vector<char> covered(num_pieces, 0);
  std::size_t uncovered = num_pieces;
  using Entry =
      std::pair<std::int64_t, std::int32_t>;  // (count, -index): ties -> lower index
  std::priority_queue<Entry> heap;
  for (std::int32_t i = 0; i < n; ++i) {
    if (start[i + 1] > start[i]) heap.push({start[i + 1] - start[i], -i});
  }
  std::vector<std::int32_t> chosen;
  while (uncovered > 0) {
    if (heap.empty() || chosen.size() >= budget) return {};
    const auto [stale, neg] = heap.top();
    heap.pop();
    const std::int32_t i = -neg;
    std::int64_t fresh = 0;
    for (std::int64_t k = start[i]; k < start[i + 1]; ++k) fresh += !covered[items[k]];
    if (fresh == 0) continue;
    if (!heap.empty() && fresh < heap.top().first) {
      heap.push({fresh, neg});
      continue;
    }
    chosen.push_back(i);
    for (std::int64_t k = start[i]; k < start[i + 1]; ++k) {
      uncovered -= !covered[items[k]];
      covered[items[k]] = 1;
    }
  }
  return chosen;
}

// The least protrusion bound with which any candidate encloses each piece.
std::vector<float> PieceFloors(const CoverLists& lists, std::size_t num_pieces) {
  std::vector<float> floor(num_pieces, std::numeric_limits<float>::infinity());
  for (std::size_t k = 0; k < lists.items.size(); ++k) {
    floor[lists.items[k]] = std::min(floor[lists.items[k]], lists.need[k]);
  }
  return floor;
}

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

constexpr float kFloorSlack = 1.3f;

// `reach_eps` > 0 is a bound at which every piece was reachable before (the
// previous round's lists): the bracket starts there.
MinMaxCover CoverWithBudget(const std::vector<Candidate>& cands,
                            const std::vector<Piece>& pieces, std::size_t budget,
                            double start_eps, double reach_eps, double diag,
                            const std::function<void()>& tick) {
  const PieceBvh bvh(pieces);
  MinMaxCover out;
  auto attempt = [&](double eps) {
    tick();
    if (eps > out.lists_eps) {
      out.lists = ComputeCovers(cands, pieces, bvh, eps);
      out.lists_eps = eps;
      out.limits = PieceFloors(out.lists, pieces.size());
      for (float& f : out.limits)
        f = std::nextafter(kFloorSlack * f, std::numeric_limits<float>::infinity());
    }
    return GreedyCover(out.lists, eps, pieces.size(), budget, &out.limits);
  };
  // Bracket: grow until every piece is reachable and the cover fits.
  double hi = reach_eps > 0 ? reach_eps : start_eps;
  const double grow = reach_eps > 0 ? 1.25 : 2.0;
  while ((out.chosen = attempt(hi)).empty()) {
    hi *= grow;
    if (hi > 4 * diag) throw SphereTreeError("no cover found (is the mesh a solid?)");
  }
  // Bisect below it with the same lists. A failure in the bracket may have been
  // an unreachable piece, which the lists now reach, so the search starts at 0.
  double lo = 0;
  for (int i = 0; i < 14 && hi - lo > 2e-2 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    auto c = attempt(mid);
    if (c.empty()) {
      lo = mid;
    } else {
      hi = mid;
      out.chosen = std::move(c);
    }
  }
  out.eps = hi;
  return out;
}

// Splits the marked pieces into four at their edge midpoints.
std::vector<Piece> SplitPieces(const std::vector<Piece>& pieces,
                               const std::vector<char>& split) {
  std::vector<Piece> out;
  out.reserve(pieces.size() + 3 * std::count(split.begin(), split.end(), 1));
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const Piece& p = pieces[i];
    if (!split[i]) {
      out.push_back(p);
      continue;
    }
    const Vector3 a = 0.5 * (p.v[0] + p.v[1]), b = 0.5 * (p.v[1] + p.v[2]),
                  c = 0.5 * (p.v[2] + p.v[0]);
    out.push_back(MakePiece(p.v[0], a, c));
    out.push_back(MakePiece(p.v[1], b, a));
    out.push_back(MakePiece(p.v[2], c, b));
    out.push_back(MakePiece(a, b, c));
  }
  return out;
}

// Protrusion bound of a sphere centred at c (depth d) that encloses the pieces.
double CoverError(const Vector3& c, double depth, const std::vector<Piece>& pieces,
                  const std::vector<std::int32_t>& members) {
  double r2 = 0;
  for (std::int32_t p : members) r2 = std::max(r2, FarCorner2(pieces[p], c));
  return std::sqrt(r2) - depth;
}

// CoverError when it is below `limit`; otherwise some value >= limit, found as
// soon as one piece shows it.
double CoverErrorBelow(const Vector3& c, double depth, const std::vector<Piece>& pieces,
                       const std::vector<std::int32_t>& members, double limit) {
  const double stop2 = (limit + depth) * (limit + depth);
  double r2 = 0;
  for (std::int32_t p : members) {
    r2 = std::max(r2, FarCorner2(pieces[p], c));
    if (r2 >= stop2) return limit;
  }
  return std::sqrt(r2) - depth;
}

struct Leaf {
  Vector3 c;
  double depth;
  std::vector<std::int32_t> pieces;
};

// Gives each piece to the leaf that encloses it with the smallest protrusion bound.
void AssignPieces(std::vector<Leaf>* leaves, const std::vector<Piece>& pieces) {
  for (Leaf& l : *leaves) l.pieces.clear();
  for (std::size_t p = 0; p < pieces.size(); ++p) {
    const Piece& piece = pieces[p];
    double best = std::numeric_limits<double>::infinity();
    std::size_t best_leaf = 0;
    for (std::size_t i = 0; i < leaves->size(); ++i) {
      const Leaf& l = (*leaves)[i];
      // Lower bound from the centroid first; most leaves are far away.
      if ((piece.centroid - l.c).norm() - l.depth >= best) continue;
      const double e = std::sqrt(FarCorner2(piece, l.c)) - l.depth;
      if (e < best) {
        best = e;
        best_leaf = i;
      }
    }
    (*leaves)[best_leaf].pieces.push_back(static_cast<std::int32_t>(p));
  }
  std::erase_if(*leaves, [](const Leaf& l) { return l.pieces.empty(); });
}

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

// Moves a leaf's centre to the candidate (or, with toward_ball, a point toward
// the smallest ball around its pieces, which costs mesh queries) that encloses
// the same pieces with the least protrusion. Sorts its pieces, farthest first.
void RefineLeaf(Leaf* leaf, const std::vector<Piece>& pieces, const CandidateIndex& index,
                const MeshOracle& oracle, bool toward_ball) {
  using MTraits = CGAL::Min_sphere_of_spheres_d_traits_3<K, double, CGAL::Tag_true>;
  using MinSphere = CGAL::Min_sphere_of_spheres_d<MTraits>;
  Leaf& l = *leaf;
  // Farthest pieces first: a centre that cannot beat the current one usually
  // fails on them, after a few corners.
  std::sort(l.pieces.begin(), l.pieces.end(), [&](std::int32_t a, std::int32_t b) {
    const double da = FarCorner2(pieces[a], l.c), db = FarCorner2(pieces[b], l.c);
    return da != db ? da > db : a < b;
  });
  double best = CoverError(l.c, l.depth, pieces, l.pieces);
  const Vector3 any = pieces[l.pieces.front()].v[0];
  // Centres farther than the current radius from the current one are not tried.
  const Vector3 from = l.c;
  index.ForEachNear(from, best + l.depth, [&](const Candidate& c) {
    if ((any - c.c).norm() - c.depth >= best) return;  // cannot beat the current error
    const double e = CoverErrorBelow(c.c, c.depth, pieces, l.pieces, best);
    if (e < best) {
      best = e;
      l.c = c.c;
      l.depth = c.depth;
    }
  });
  if (!toward_ball) return;
  // Toward the smallest enclosing ball of the pieces' corners.
  std::vector<MTraits::Sphere> corners;
  for (std::int32_t p : l.pieces) {
    for (const Vector3& v : pieces[p].v)
      corners.emplace_back(K::Point_3(v.x(), v.y(), v.z()), 0.0);
  }
  MinSphere ms(corners.begin(), corners.end());
  auto it = ms.center_cartesian_begin();
  Vector3 mb;
  mb.x() = *it++;
  mb.y() = *it++;
  mb.z() = *it;
  const Vector3 start = l.c;
  for (double t : {0.2, 0.4, 0.6, 0.8, 1.0}) {
    const Vector3 p = start + t * (mb - start);
    if (!oracle.Inside(p)) continue;
    const double depth = oracle.Distance(p);
    const double e = CoverError(p, depth, pieces, l.pieces);
    if (e < best) {
      best = e;
      l.c = p;
      l.depth = depth;
    }
  }
}

void RefineLeaves(std::vector<Leaf>* leaves, const std::vector<Piece>& pieces,
                  const CandidateIndex& index, const MeshOracle& oracle,
                  bool toward_ball = true) {
  for (Leaf& l : *leaves) RefineLeaf(&l, pieces, index, oracle, toward_ball);
}

// Each leaf's radius (its bound at depth 0), with a hair for round-off.
std::vector<double> LeafRadii(const std::vector<Leaf>& leaves,
                              const std::vector<Piece>& pieces) {
  std::vector<double> radius(leaves.size());
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    radius[i] = CoverError(leaves[i].c, 0.0, pieces, leaves[i].pieces) * (1 + 1e-12);
  }
  return radius;
}

// Tightens a cover without adding leaves or losing coverage (a leaf left with no
// pieces is dropped, for SplitLeavesInTwo to spend again). Each
// round: splits the pieces that set a leaf's radius (so its region's border can
// move at a finer grain), hands every piece to the leaf that already encloses it
// with the widest margin (so no leaf grows and the ones whose far pieces are
// taken shrink), then re-centres the leaves on their pieces. Every step keeps
// each piece inside its leaf, so coverage stays complete.
void ShrinkLeaves(std::vector<Leaf>* leaves, std::vector<Piece>* pieces,
                  const CandidateIndex& index, const MeshOracle& oracle,
                  std::size_t max_pieces, int rounds) {
  for (int round = 0; round < rounds; ++round) {
    const std::vector<double> radius = LeafRadii(*leaves, *pieces);
    // 1. Split the pieces near each leaf's radius.
    std::vector<std::int32_t> owner(pieces->size(), -1);
    std::vector<char> split(pieces->size(), 0);
    std::size_t n_split = 0;
    for (std::size_t i = 0; i < leaves->size(); ++i) {
      const Leaf& l = (*leaves)[i];
      for (std::int32_t p : l.pieces) {
        owner[p] = static_cast<std::int32_t>(i);
        const Piece& piece = (*pieces)[p];
        const double edge =
            std::max({(piece.v[1] - piece.v[0]).norm(), (piece.v[2] - piece.v[1]).norm(),
                      (piece.v[0] - piece.v[2]).norm()});
        if (std::sqrt(FarCorner2(piece, l.c)) >= radius[i] - 0.5 * edge) {
          split[p] = 1;
          ++n_split;
        }
      }
    }
    if (n_split > 0 && pieces->size() + 3 * n_split <= max_pieces) {
      std::vector<std::int32_t> new_owner;
      new_owner.reserve(pieces->size() + 3 * n_split);
      for (std::size_t p = 0; p < pieces->size(); ++p) {
        for (int k = 0; k < (split[p] ? 4 : 1); ++k) new_owner.push_back(owner[p]);
      }
      *pieces = SplitPieces(*pieces, split);
      owner = std::move(new_owner);
    }
    // 2. Each piece to the enclosing leaf with the widest margin.
    std::vector<double> best_margin(pieces->size());
    for (std::size_t p = 0; p < pieces->size(); ++p) {
      best_margin[p] =
          radius[owner[p]] - std::sqrt(FarCorner2((*pieces)[p], (*leaves)[owner[p]].c));
    }
    const PieceBvh bvh(*pieces);
    for (std::size_t i = 0; i < leaves->size(); ++i) {
      const Vector3 c = (*leaves)[i].c;
      bvh.ForEachEnclosed(c, radius[i], [&](std::int32_t p) {
        const double margin = radius[i] - std::sqrt(FarCorner2((*pieces)[p], c));
        if (margin > best_margin[p]) {
          best_margin[p] = margin;
          owner[p] = static_cast<std::int32_t>(i);
        }
      });
    }
    for (Leaf& l : *leaves) l.pieces.clear();
    for (std::size_t p = 0; p < pieces->size(); ++p)
      (*leaves)[owner[p]].pieces.push_back(static_cast<std::int32_t>(p));
    std::erase_if(*leaves, [](const Leaf& l) { return l.pieces.empty(); });
    // 3. Re-centre.
    RefineLeaves(leaves, *pieces, index, oracle);
  }
}

// Cuts a leaf in two across the longest side of its pieces' box, then (three
// times) re-centres both halves and gives each piece to the half that encloses it
// with the smaller bound. `e` gets the halves' bounds.
void SplitInTwo(const Leaf& leaf, const std::vector<Piece>& pieces,
                const CandidateIndex& index, const MeshOracle& oracle,
                std::vector<Leaf>* out, double e[2], bool toward_ball = true) {
  std::vector<Leaf>& halves = *out;
  Aabb box;
  for (std::int32_t p : leaf.pieces) box.Extend(pieces[p].centroid);
  int axis;
  box.extent().maxCoeff(&axis);
  std::vector<std::int32_t> order = leaf.pieces;
  const auto mid = order.begin() + static_cast<std::ptrdiff_t>(order.size() / 2);
  std::nth_element(order.begin(), mid, order.end(), [&](std::int32_t a, std::int32_t b) {
    return pieces[a].centroid[axis] != pieces[b].centroid[axis]
               ? pieces[a].centroid[axis] < pieces[b].centroid[axis]
               : a < b;
  });
  halves.clear();
  halves.push_back({leaf.c, leaf.depth, {order.begin(), mid}});
  halves.push_back({leaf.c, leaf.depth, {mid, order.end()}});
  RefineLeaves(&halves, pieces, index, oracle, toward_ball);
  for (int it = 0; it < 3; ++it) {
    std::vector<std::int32_t> mine[2];
    for (std::int32_t p : leaf.pieces) {
      const double e0 = std::sqrt(FarCorner2(pieces[p], halves[0].c)) - halves[0].depth;
      const double e1 = std::sqrt(FarCorner2(pieces[p], halves[1].c)) - halves[1].depth;
      mine[e1 < e0 ? 1 : 0].push_back(p);
    }
    if (mine[0].empty() || mine[1].empty()) break;
    halves[0].pieces = std::move(mine[0]);
    halves[1].pieces = std::move(mine[1]);
    RefineLeaves(&halves, pieces, index, oracle, toward_ball);
  }
  for (int k = 0; k < 2; ++k)
    e[k] = CoverError(halves[k].c, halves[k].depth, pieces, halves[k].pieces);
}

// For each leaf, the other leaves that could take one of its pieces with a bound
// of at most `cap`: those whose spheres, grown by cap, meet its own.
std::vector<std::vector<std::int32_t>> NeighbourLists(const std::vector<Leaf>& leaves,
                                                      const std::vector<double>& radius,
                                                      double cap) {
  std::vector<std::vector<std::int32_t>> near(leaves.size());
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    for (std::size_t j = i + 1; j < leaves.size(); ++j) {
      if ((leaves[i].c - leaves[j].c).norm() < radius[i] + radius[j] + cap) {
        near[i].push_back(static_cast<std::int32_t>(j));
        near[j].push_back(static_cast<std::int32_t>(i));
      }
    }
  }
  return near;
}

// The neighbour (an index into `near`) that takes piece q for the least growth
// of its radius (new_r, per neighbour), none past a bound of `cap`; false when
// none can. Also gives the piece's far-corner distance from that neighbour.
bool CheapestTaker(const Piece& q, const std::vector<Leaf>& leaves,
                   const std::vector<std::int32_t>& near,
                   const std::vector<double>& new_r, double cap, std::size_t* at,
                   double* growth, double* dist) {
  *growth = std::numeric_limits<double>::infinity();
  for (std::size_t a = 0; a < near.size(); ++a) {
    const Leaf& l = leaves[near[a]];
    // The centroid's distance is a lower bound on the far corner's.
    const double lower = (q.centroid - l.c).norm();
    if (lower - l.depth > cap || lower - new_r[a] >= *growth) continue;
    const double d = std::sqrt(FarCorner2(q, l.c));
    if (d - l.depth > cap) continue;
    const double g = std::max(0.0, d - new_r[a]);
    if (g < *growth) {
      *growth = g;
      *dist = d;
      *at = a;
    }
  }
  return *growth < std::numeric_limits<double>::infinity();
}

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
                std::size_t budget, int rounds) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  struct Removal {
    double cost = kInf;
    double gave_up_at = kInf;          // planning stopped once the cost passed this
    std::vector<std::int32_t> target;  // per piece of the leaf, the neighbour taking it
    std::vector<std::int32_t> receivers;  // the distinct targets, sorted
  };
  struct Cut {
    bool known = false;  // false: the leaf changed since
    double gain = -kInf;
    std::vector<Leaf> halves;
  };
  std::vector<Removal> plan;
  std::vector<Cut> cuts;
  std::vector<char> stale;  // the plan must be recomputed
  std::vector<std::vector<std::int32_t>> near;
  for (int round = 0; round < rounds; ++round) {
    const std::size_t n = leaves->size();
    plan.resize(n);
    cuts.resize(n);
    stale.resize(n, 1);
    const std::vector<double> radius = LeafRadii(*leaves, pieces);
    std::vector<double> bound(n);
    for (std::size_t i = 0; i < n; ++i) bound[i] = radius[i] - (*leaves)[i].depth;
    const std::vector<std::vector<std::int32_t>> old_near = std::move(near);
    near = NeighbourLists(*leaves, radius, cap);
    // Cuts first: no removal costing more than the best gain is worth planning.
    double best_gain = 0;
    for (std::size_t i = 0; i < n; ++i) {
      Cut& c = cuts[i];
      if (!c.known) {
        c = Cut{true, -kInf, {}};
        if ((*leaves)[i].pieces.size() >= 2) {
          double e[2];
          SplitInTwo((*leaves)[i], pieces, index, oracle, &c.halves, e, false);
          c.gain = bound[i] - e[0] - e[1];
        }
      }
      best_gain = std::max(best_gain, c.gain);
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (!stale[i] && !(plan[i].gave_up_at < best_gain)) continue;
      stale[i] = 0;
      Removal& r = plan[i];
      r = Removal{};
      if (near[i].empty()) continue;
      std::vector<double> new_r(near[i].size());
      for (std::size_t a = 0; a < near[i].size(); ++a) new_r[a] = radius[near[i][a]];
      double cost = -bound[i];  // it only grows as pieces are placed
      bool placed = true;
      for (std::int32_t q : (*leaves)[i].pieces) {
        std::size_t at = 0;
        double growth = 0, dist = 0;
        if (!CheapestTaker(pieces[q], *leaves, near[i], new_r, cap, &at, &growth,
                           &dist)) {
          placed = false;
          break;
        }
        cost += growth;
        new_r[at] = std::max(new_r[at], dist);
        r.target.push_back(near[i][at]);
        if (cost >= best_gain) {
          r.gave_up_at = best_gain;
          placed = false;
          break;
        }
      }
      if (!placed) {
        r.target.clear();
        continue;
      }
      r.cost = cost;
      r.receivers = r.target;
      std::sort(r.receivers.begin(), r.receivers.end());
      r.receivers.erase(std::unique(r.receivers.begin(), r.receivers.end()),
                        r.receivers.end());
    }
    std::vector<std::int32_t> by_cost(n), by_gain(n);
    std::iota(by_cost.begin(), by_cost.end(), 0);
    std::iota(by_gain.begin(), by_gain.end(), 0);
    std::sort(by_cost.begin(), by_cost.end(), [&](std::int32_t a, std::int32_t b) {
      return plan[a].cost != plan[b].cost ? plan[a].cost < plan[b].cost : a < b;
    });
    std::sort(by_gain.begin(), by_gain.end(), [&](std::int32_t a, std::int32_t b) {
      return cuts[a].gain != cuts[b].gain ? cuts[a].gain > cuts[b].gain : a < b;
    });
    std::vector<char> touched(n, 0);
    std::size_t swaps = 0;
    auto cut = [&](std::int32_t k, std::int32_t slot) {  // slot < 0: a new leaf
      touched[k] = 1;
      std::vector<Leaf>& halves = cuts[k].halves;
      (*leaves)[k] = std::move(halves[0]);
      if (slot < 0) {
        leaves->push_back(std::move(halves[1]));
      } else {
        (*leaves)[slot] = std::move(halves[1]);
      }
      ++swaps;
    };
    for (std::int32_t k : by_gain) {
      if (n + swaps >= budget || !(cuts[k].gain > 0)) break;
      cut(k, -1);
    }
    std::size_t next_gain = 0;
    for (std::int32_t i : by_cost) {
      const Removal& r = plan[i];
      if (!(r.cost < kInf)) break;
      if (touched[i]) continue;
      bool conflict = false;
      for (std::int32_t j : r.receivers) conflict |= touched[j] != 0;
      if (conflict) continue;
      while (next_gain < n && touched[by_gain[next_gain]]) ++next_gain;
      // The best cut that is neither this leaf nor one of its receivers.
      std::int32_t k = -1;
      for (std::size_t g = next_gain; g < n && k < 0; ++g) {
        const std::int32_t c = by_gain[g];
        if (!touched[c] && c != i &&
            !std::binary_search(r.receivers.begin(), r.receivers.end(), c))
          k = c;
      }
      if (k < 0 || cuts[k].gain <= r.cost + 1e-9 * radius[i]) break;
      touched[i] = 1;
      for (std::int32_t j : r.receivers) touched[j] = 1;
      for (std::size_t a = 0; a < r.target.size(); ++a) {
        (*leaves)[r.target[a]].pieces.push_back((*leaves)[i].pieces[a]);
      }
      cut(k, i);  // the new half takes the removed leaf's slot
    }
    if (swaps == 0) break;
    // The changed leaves re-centre on what they now hold; every leaf near a
    // changed one gets a new plan next round.
    for (std::size_t i = 0; i < n; ++i) {
      if (!touched[i]) continue;
      RefineLeaf(&(*leaves)[i], pieces, index, oracle, false);
      cuts[i].known = false;
    }
    for (std::size_t i = 0; i < n; ++i) {
      bool s = touched[i] != 0;
      for (std::int32_t j : near[i]) s |= touched[j] != 0;
      if (i < old_near.size()) {
        for (std::int32_t j : old_near[i]) s |= touched[j] != 0;
      }
      stale[i] = s;
    }
  }
}

// Moves leaf borders where that lowers the sum of radii: each leaf in turn
// gives its farthest pieces to the neighbours that take them for the least
// growth, as many as pay (its shrink, to the next farthest piece, above the
// neighbours' total growth). No neighbour grows past `cap` (a bound); every
// piece stays inside the leaf that holds it, so coverage stays complete.
void TradePieces(std::vector<Leaf>* leaves, const std::vector<Piece>& pieces,
                 const CandidateIndex& index, const MeshOracle& oracle, double cap,
                 int rounds) {
  const std::size_t n = leaves->size();
  for (int round = 0; round < rounds; ++round) {
    std::vector<double> radius = LeafRadii(*leaves, pieces);
    const std::vector<std::vector<std::int32_t>> near =
        NeighbourLists(*leaves, radius, cap);
    std::vector<char> changed(n, 0);
    double total_gain = 0;
    for (std::size_t i = 0; i < n; ++i) {
      Leaf& leaf = (*leaves)[i];
      if (leaf.pieces.size() < 2 || near[i].empty()) continue;
      std::vector<std::pair<double, std::int32_t>> by_far;
      by_far.reserve(leaf.pieces.size());
      for (std::int32_t q : leaf.pieces)
        by_far.push_back({std::sqrt(FarCorner2(pieces[q], leaf.c)), q});
      std::sort(by_far.begin(), by_far.end(), std::greater<>());
      // Give the farthest pieces away one by one, each to its cheapest taker;
      // remember the best prefix.
      std::vector<double> new_r(near[i].size());
      for (std::size_t a = 0; a < near[i].size(); ++a) new_r[a] = radius[near[i][a]];
      struct Move {
        std::size_t at;
        double dist;
      };
      std::vector<Move> moves;
      double growth = 0, best_net = 0;
      std::size_t best_k = 0;
      for (std::size_t k = 0; k < by_far.size() / 3; ++k) {
        Move m{};
        double g = 0;
        if (!CheapestTaker(pieces[by_far[k].second], *leaves, near[i], new_r, cap, &m.at,
                           &g, &m.dist))
          break;
        growth += g;
        new_r[m.at] = std::max(new_r[m.at], m.dist);
        moves.push_back(m);
        const double net = (by_far[0].first - by_far[k + 1].first) - growth;
        if (net > best_net) {
          best_net = net;
          best_k = k + 1;
        }
      }
      if (best_k == 0) continue;
      for (std::size_t k = 0; k < best_k; ++k) {
        const std::int32_t j = near[i][moves[k].at];
        (*leaves)[j].pieces.push_back(by_far[k].second);
        radius[j] = std::max(radius[j], moves[k].dist);
        changed[j] = 1;
      }
      leaf.pieces.clear();
      for (std::size_t k = best_k; k < by_far.size(); ++k)
        leaf.pieces.push_back(by_far[k].second);
      radius[i] = by_far[best_k].first;
      changed[i] = 1;
      total_gain += best_net;
    }
    if (total_gain == 0) break;
    for (std::size_t i = 0; i < n; ++i) {
      if (changed[i]) RefineLeaf(&(*leaves)[i], pieces, index, oracle, false);
    }
  }
}

// Spends the leaf budget on the leaves with the largest protrusion bound, each
// cut by SplitInTwo. A cut that does not lower the bound by 5 % is not made; a
// round patch rarely gains from two spheres, so this mostly splits long ones.
void SplitLeavesInTwo(std::vector<Leaf>* leaves, std::size_t budget,
                      const std::vector<Piece>& pieces, const CandidateIndex& index,
                      const MeshOracle& oracle) {
  std::vector<double> error(leaves->size());
  std::vector<char> final_leaf(leaves->size(), 0);
  for (std::size_t i = 0; i < leaves->size(); ++i) {
    error[i] =
        CoverError((*leaves)[i].c, (*leaves)[i].depth, pieces, (*leaves)[i].pieces);
  }
  while (leaves->size() < budget) {
    std::size_t worst = leaves->size();
    for (std::size_t i = 0; i < leaves->size(); ++i) {
      if (!final_leaf[i] && (worst == leaves->size() || error[i] > error[worst]))
        worst = i;
    }
    if (worst == leaves->size()) break;
    const Leaf& leaf = (*leaves)[worst];
    if (leaf.pieces.size() < 2) {
      final_leaf[worst] = 1;
      continue;
    }
    std::vector<Leaf> halves;
    double e[2];
    SplitInTwo(leaf, pieces, index, oracle, &halves, e);
    if (std::max(e[0], e[1]) > 0.95 * error[worst]) {
      final_leaf[worst] = 1;
      continue;
    }
    (*leaves)[worst] = std::move(halves[0]);
    error[worst] = e[0];
    leaves->push_back(std::move(halves[1]));
    error.push_back(e[1]);
    final_leaf.push_back(0);
  }
}

// Splits items (indices into centres) into at most `parts` groups by recursive
// bisection along the longest axis of their bounding box, sizes proportional.
void SplitGroup(std::vector<std::int32_t> items, int parts,
                const std::vector<Vector3>& centers,
                std::vector<std::vector<std::int32_t>>* out) {
  if (items.empty()) return;
  if (parts <= 1 || items.size() == 1) {
    out->push_back(std::move(items));
    return;
  }
  Aabb box;
  for (std::int32_t i : items) box.Extend(centers[i]);
  int axis;
  box.extent().maxCoeff(&axis);
  std::sort(items.begin(), items.end(), [&](std::int32_t a, std::int32_t b) {
    return centers[a][axis] != centers[b][axis] ? centers[a][axis] < centers[b][axis]
                                                : a < b;
  });
  const int left_parts = parts / 2;
  const std::size_t cut = items.size() * left_parts / parts;
  SplitGroup({items.begin(), items.begin() + cut}, left_parts, centers, out);
  SplitGroup({items.begin() + cut, items.end()}, parts - left_parts, centers, out);
}

}  // namespace

SphereTree BuildTreeFromLeaves(const std::vector<Vector3>& centers,
                               const std::vector<double>& radii, int levels,
                               int branching) {
  if (centers.empty() || centers.size() != radii.size()) {
    throw SphereTreeError("a tree needs at least one leaf, with one radius per centre");
  }
  const std::size_t capacity = LeafCapacity(levels, branching);
  if (centers.size() > capacity) {
    throw SphereTreeError(std::to_string(centers.size()) + " leaves do not fit in " +
                          std::to_string(levels) + " levels of " +
                          std::to_string(branching));
  }
  Aabb bounds;
  for (const Vector3& c : centers) bounds.Extend(c);
  const double extent =
      std::max(bounds.LargestExtent(), *std::max_element(radii.begin(), radii.end()));
  SphereTree tree;
  tree.levels = levels;
  tree.branching = branching;
  std::vector<std::int32_t> all(centers.size());
  std::iota(all.begin(), all.end(), 0);
  // Each node records the leaves below it; children are appended level by level
  // so that every node's children are contiguous (breadth-first order).
  std::vector<std::vector<std::int32_t>> below;
  tree.AddNode(Vector3::Zero(), 1.0, 0);
  below.push_back(all);
  for (std::size_t node = 0; node < below.size(); ++node) {
    const int lvl = tree.level[node];
    if (below[node].size() == 1 || lvl == levels - 1) continue;  // a leaf
    // As many children as allowed: balanced groups of n / branching leaves each
    // fit a child subtree, since n <= branching * capacity.
    const int parts =
        static_cast<int>(std::min<std::size_t>(branching, below[node].size()));
    std::vector<std::vector<std::int32_t>> groups;
    SplitGroup(below[node], parts, centers, &groups);
    tree.first_child[node] = static_cast<std::int32_t>(tree.size());
    tree.child_count[node] = static_cast<std::uint8_t>(groups.size());
    for (auto& g : groups) {
      tree.AddNode(Vector3::Zero(), 1.0, lvl + 1);
      below.push_back(std::move(g));
    }
  }
  // Leaves take their spheres; parents bound their children, deepest first.
  using MTraits = CGAL::Min_sphere_of_spheres_d_traits_3<K, double, CGAL::Tag_true>;
  using MinSphere = CGAL::Min_sphere_of_spheres_d<MTraits>;
  const double slack = 1e-12 * extent;  // round-off in the containment test
  for (std::size_t n = tree.size(); n-- > 0;) {
    if (tree.IsLeaf(n)) {
      const std::int32_t leaf = below[n].front();
      tree.x[n] = centers[leaf].x();
      tree.y[n] = centers[leaf].y();
      tree.z[n] = centers[leaf].z();
      tree.r[n] = radii[leaf];
      continue;
    }
    std::vector<MTraits::Sphere> kids;
    const std::int32_t first = tree.first_child[n], count = tree.child_count[n];
    for (std::int32_t c = first; c < first + count; ++c) {
      kids.emplace_back(K::Point_3(tree.x[c], tree.y[c], tree.z[c]), tree.r[c]);
    }
    MinSphere ms(kids.begin(), kids.end());
    auto it = ms.center_cartesian_begin();
    const Vector3 center(*it, *(it + 1), *(it + 2));
    double radius = 0;
    for (std::int32_t c = first; c < first + count; ++c) {
      radius = std::max(radius, (tree.center(c) - center).norm() + tree.r[c]);
    }
    tree.x[n] = center.x();
    tree.y[n] = center.y();
    tree.z[n] = center.z();
    tree.r[n] = radius * (1 + 1e-12) + slack;
  }
  return tree;
}

std::size_t LeafCapacity(int levels, int branching) {
  std::size_t capacity = 1;
  for (int l = 1; l < levels; ++l) capacity *= static_cast<std::size_t>(branching);
  return capacity;
}

std::string SphereTreeParams::ToString() const {
  std::ostringstream s;
  s.precision(17);
  s << "levels=" << levels << " branch=" << branching << " leaves=" << leaves
    << " target_error_mm=" << target_error_mm << " samples=" << samples
    << " seed=" << seed << " spend=" << (spend == Spend::kMean ? "mean" : "worst");
  return s.str();
}

SphereTree BuildSphereTree(const TriangleMesh& mesh, const SphereTreeParams& params,
                           const BuildProgress& progress, SphereTreeBuildStats* stats) {
  const auto t0 = Clock::now();
  const Reporter report(progress);
  if (params.levels < 1 || params.levels > 8) {
    throw SphereTreeError("levels " + std::to_string(params.levels) +
                          " is out of range (expected 1 to 8)");
  }
  if (params.branching < 2 || params.branching > 32) {
    throw SphereTreeError("branching " + std::to_string(params.branching) +
                          " is out of range (expected 2 to 32)");
  }
  const std::size_t capacity =
      std::min<std::size_t>(LeafCapacity(params.levels, params.branching), kMaxLeaves);
  if (params.target_error_mm < 0 || !std::isfinite(params.target_error_mm) ||
      (params.target_error_mm > 0 && params.target_error_mm < kMinTargetErrorMm)) {
    throw SphereTreeError("target error must be 0 (a leaf budget) or at least " +
                          std::to_string(kMinTargetErrorMm) + " mm");
  }
  if (params.target_error_mm == 0 &&
      (params.leaves < 1 || static_cast<std::size_t>(params.leaves) > capacity)) {
    throw SphereTreeError("leaf budget " + std::to_string(params.leaves) +
                          " does not fit in " + std::to_string(params.levels) +
                          " levels of " + std::to_string(params.branching) +
                          " (at most " + std::to_string(capacity) + " leaves)");
  }
  const MeshReport check = mesh.Check();
  if (!check.closed() || !check.manifold()) {
    throw SphereTreeError("the mesh must be a closed, manifold surface (" +
                          std::to_string(check.boundary_edges) + " boundary and " +
                          std::to_string(check.nonmanifold_edges) +
                          " non-manifold edges)");
  }
  const double extent = check.bounds.LargestExtent();
  const double diag = check.bounds.extent().norm();
  if (!(extent > 0) || std::abs(check.volume) <= 1e-9 * extent * extent * extent) {
    throw SphereTreeError("the mesh encloses no volume (it is flat or degenerate)");
  }
  const double orientation = check.volume > 0 ? 1.0 : -1.0;  // inward meshes still work

  // 1. Pieces and samples.
  const std::size_t budget = params.target_error_mm > 0 ? capacity : params.leaves;
  const int wanted = params.samples > 0
                         ? params.samples
                         : std::min(60000, std::max(3000, 8 * static_cast<int>(budget)));
  double h = std::sqrt(check.area / (0.433 * wanted));
  std::vector<Vector3> normals;
  std::vector<Piece> pieces = Subdivide(mesh, h, &normals, orientation);
  // Long thin faces: coarser pieces, down to one per face (a mesh of more faces
  // than that keeps one piece each).
  while (pieces.size() > 4u * static_cast<std::size_t>(wanted) &&
         pieces.size() > mesh.num_faces()) {
    h *= 1.5;
    normals.clear();
    pieces = Subdivide(mesh, h, &normals, orientation);
  }
  report("sampling", 0.02);
  std::uint64_t rng = params.seed;
  std::vector<Vector3> samples;
  samples.reserve(pieces.size());
  for (const Piece& p : pieces) {
    double u = Uniform(rng), v = Uniform(rng);
    if (u + v > 1) {
      u = 1 - u;
      v = 1 - v;
    }
    samples.push_back(p.v[0] + u * (p.v[1] - p.v[0]) + v * (p.v[2] - p.v[0]));
  }

  // 2. Medial axis candidates.
  const MeshOracle oracle(mesh);
  const Reporter medial_report([&](std::string_view stage, double f) {
    return !progress || progress(stage, 0.02 + 0.38 * f);
  });
  const std::vector<Candidate> cands =
      MedialCandidates(samples, normals, diag, 0.25 * h, oracle, medial_report);
  if (cands.empty())
    throw SphereTreeError("no point of the medial axis was found inside the mesh");
  const double seconds_medial = Seconds(t0);

  // 3. Cover. With a budget: the smallest bound whose greedy cover fits it,
  // pieces no candidate encloses that well held at (nearly) their own best, so
  // that one hard spot does not hold the whole surface to its bound; one round
  // splits those pieces and covers again.
  const auto t_cover = Clock::now();
  int runs = 0;
  auto tick = [&] { report("cover", 0.4 + 0.3 * std::min(1.0, runs++ / 40.0)); };
  MinMaxCover cover;
  const std::size_t max_pieces = 6 * static_cast<std::size_t>(wanted);
  // Pieces whose best possible bound is above `limit` are split.
  auto refine_binding = [&](const CoverLists& lists, double limit) {
    const std::vector<float> floor = PieceFloors(lists, pieces.size());
    std::vector<char> split(pieces.size(), 0);
    std::size_t n_split = 0;
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      split[i] = floor[i] > limit;
      n_split += split[i];
    }
    if (n_split == 0 || pieces.size() + 3 * n_split > max_pieces) return false;
    pieces = SplitPieces(pieces, split);
    return true;
  };
  if (params.target_error_mm > 0) {
    const double eps = params.target_error_mm;
    cover.eps = eps;
    for (int round = 0;; ++round) {
      tick();
      cover.lists = ComputeCovers(cands, pieces, PieceBvh(pieces), eps);
      if (round == 3 || !refine_binding(cover.lists, 0.6 * eps)) break;
    }
    cover.chosen = GreedyCover(cover.lists, eps, pieces.size(), capacity);
    if (cover.chosen.empty()) {
      throw SphereTreeError(
          "a protrusion of at most " + std::to_string(eps) +
          " mm needs more leaves than " + std::to_string(params.levels) + " levels of " +
          std::to_string(params.branching) + " hold (" + std::to_string(capacity) +
          "); allow more levels or a larger error");
    }
  } else {
    cover = CoverWithBudget(cands, pieces, budget, 0.02 * h, 0.0, diag, tick);
    if (refine_binding(cover.lists, 0.6 * cover.eps)) {
      cover =
          CoverWithBudget(cands, pieces, budget, 0.02 * h, cover.lists_eps, diag, tick);
    }
  }

  // 4. Leaves: each piece to the leaf that encloses it best, leaves re-centred,
  // then tightened (and, with a budget, the leaves that frees spent).
  const CandidateIndex index(cands, 0.5 * h);
  auto make_leaves = [&](const std::vector<std::int32_t>& chosen,
                         std::vector<Piece>* work) {
    std::vector<Leaf> out;
    out.reserve(budget);
    for (std::int32_t i : chosen) out.push_back({cands[i].c, cands[i].depth, {}});
    AssignPieces(&out, *work);
    RefineLeaves(&out, *work, index, oracle);
    AssignPieces(&out, *work);
    const bool budgeted = params.target_error_mm == 0;
    const bool trade = budgeted && params.spend == SphereTreeParams::Spend::kMean;
    // Three tightening passes, or one before trading.
    for (int pass = 0; pass < (trade ? 1 : 3); ++pass) {
      ShrinkLeaves(&out, work, index, oracle, 4 * max_pieces, 2);
      if (budgeted) SplitLeavesInTwo(&out, budget, *work, index, oracle);
    }
    if (!trade) return out;
    // Then trade leaves, and the pieces at their borders, where that lowers the
    // sum of bounds most, no leaf beyond the worst one now.
    double worst = 0;
    for (const Leaf& l : out)
      worst = std::max(worst, CoverError(l.c, l.depth, *work, l.pieces));
    SwapLeaves(&out, *work, index, oracle, worst, budget, 40);
    TradePieces(&out, *work, index, oracle, worst, 10);
    SwapLeaves(&out, *work, index, oracle, worst, budget, 40);
    RefineLeaves(&out, *work, index, oracle);
    return out;
  };
  report("tighten", 0.72);
  const std::vector<Piece> cover_pieces = pieces;
  std::vector<Leaf> leaves = make_leaves(cover.chosen, &pieces);
  // When every piece is covered at (nearly) its own best bound with leaves to
  // spare, the pieces are what limits the fit (smooth, coarsely meshed solids):
  // cover again on pieces a quarter the size, if that gives more leaves.
  if (params.target_error_mm == 0 && leaves.size() < budget * 9 / 10 &&
      cover_pieces.size() <= max_pieces) {
    report("tighten", 0.85);
    std::vector<Piece> work =
        SplitPieces(cover_pieces, std::vector<char>(cover_pieces.size(), 1));
    const MinMaxCover finer =
        CoverWithBudget(cands, work, budget, 0.02 * h, cover.lists_eps, diag, tick);
    std::vector<Leaf> trial = make_leaves(finer.chosen, &work);
    if (trial.size() > leaves.size()) {
      leaves = std::move(trial);
      pieces = std::move(work);
    }
  }
  std::vector<Vector3> centers;
  std::vector<double> radii;
  double bound = 0;
  for (const Leaf& l : leaves) {
    const double r = CoverError(l.c, 0.0, pieces, l.pieces) * (1 + 1e-12) +
                     1e-12 * extent;  // at depth 0: the radius
    centers.push_back(l.c);
    radii.push_back(r);
    bound = std::max(bound, r - l.depth);
  }
  const double seconds_cover = Seconds(t_cover);
  // 4. Hierarchy.
  report("hierarchy", 0.95);
  const auto t_tree = Clock::now();
  SphereTree tree = BuildTreeFromLeaves(centers, radii, params.levels, params.branching);
  tree.Validate();
  report("done", 1.0);
  if (stats != nullptr) {
    stats->surface_pieces = pieces.size();
    stats->medial_candidates = cands.size();
    stats->leaves = leaves.size();
    stats->error_bound_mm = bound;
    stats->seconds_medial = seconds_medial;
    stats->seconds_cover = seconds_cover;
    stats->seconds_hierarchy = Seconds(t_tree);
    stats->seconds_total = Seconds(t0);
  }
  return tree;
}

}  // namespace sulcus
