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
class Reporter {
 public:
  explicit Reporter(BuildProgress fn) : fn_(std::move(fn)) {}
  void operator()(std::string_view stage, double fraction) const {
    if (fn_ && !fn_(stage, std::clamp(fraction, 0.0, 1.0))) throw BuildCancelled();
  }

 private:
  BuildProgress fn_;
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

// Splits every face into n^2 similar pieces, n chosen so that edges are <= h.
std::vector<Piece> Subdivide(const TriangleMesh& mesh, double h, std::vector<Vector3>* normals,
                             double orientation) {
  std::vector<Piece> pieces;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const auto& face = mesh.faces()[f];
    const Vector3 a = mesh.vertices()[face[0]], b = mesh.vertices()[face[1]],
                  c = mesh.vertices()[face[2]];
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const int n = std::max(1, static_cast<int>(std::ceil(longest / h)));
    const Vector3 normal = orientation * mesh.FaceNormal(f);
    auto at = [&](int i, int j) { return Vector3(a + (b - a) * i / n + (c - a) * j / n); };
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
          if ((p.v[0] - c).squaredNorm() <= r2 && (p.v[1] - c).squaredNorm() <= r2 &&
              (p.v[2] - c).squaredNorm() <= r2) {
            fn(order_[i]);
          }
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

// Centre of the sphere through four points; false for a (nearly) flat tetrahedron,
// whose circumcentre is at or near infinity.
bool Circumcenter(const Vector3 (&p)[4], Vector3* center) {
  const Vector3 a = p[1] - p[0], b = p[2] - p[0], c = p[3] - p[0];
  const double den = 2.0 * a.dot(b.cross(c));
  if (!(std::abs(den) > 1e-12 * a.norm() * b.norm() * c.norm())) return false;
  *center = p[0] + (a.squaredNorm() * b.cross(c) + b.squaredNorm() * c.cross(a) +
                    c.squaredNorm() * a.cross(b)) / den;
  return center->allFinite();
}

// Candidate centres: the inner Voronoi pole of each surface sample (the farthest
// Voronoi vertex of its cell on the inner side, Amenta's pole), plus points on
// the way from each sample to its pole, so that thin and sharp regions have
// shallow spheres too. Only centres inside the solid are kept.
std::vector<Candidate> MedialCandidates(const std::vector<Vector3>& samples,
                                        const std::vector<Vector3>& normals, double diag,
                                        const MeshOracle& oracle, const Reporter& report) {
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

  std::vector<Vector3> points_to_try;
  points_to_try.reserve(samples.size() * 4);
  for (std::size_t s = 0; s < samples.size(); ++s) {
    if (best[s] > 0) {
      points_to_try.push_back(pole[s]);
      for (double f : {0.15, 0.45}) points_to_try.push_back(samples[s] + f * (pole[s] - samples[s]));
    }
  }
  // Poles shared by several samples appear once.
  std::sort(points_to_try.begin(), points_to_try.end(), [](const Vector3& a, const Vector3& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  });
  points_to_try.erase(std::unique(points_to_try.begin(), points_to_try.end()), points_to_try.end());

  std::vector<Candidate> out;
  out.reserve(points_to_try.size());
  const double min_depth = 1e-7 * diag;
  for (std::size_t i = 0; i < points_to_try.size(); ++i) {
    if (i % 2048 == 0) report("medial axis: depths", 0.25 + 0.75 * i / points_to_try.size());
    const Vector3& p = points_to_try[i];
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

CoverLists ComputeCovers(const std::vector<Candidate>& cands, const std::vector<Piece>& pieces,
                         const PieceBvh& bvh, double eps_max) {
  CoverLists lists;
  lists.start.reserve(cands.size() + 1);
  lists.start.push_back(0);
  std::vector<std::pair<float, std::int32_t>> found;
  for (const Candidate& c : cands) {
    found.clear();
    bvh.ForEachEnclosed(c.c, c.depth + eps_max, [&](std::int32_t p) {
      double r2 = 0;
      for (const Vector3& v : pieces[p].v) r2 = std::max(r2, (v - c.c).squaredNorm());
      // Rounded up so that a prefix never claims a piece it does not enclose.
      found.push_back({std::nextafter(static_cast<float>(std::sqrt(r2) - c.depth), 1e30f), p});
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
// eps. Returns the chosen candidates, or nothing when the pieces cannot be
// covered or need more than `budget` spheres.
std::vector<std::int32_t> GreedyCover(const CoverLists& lists, double eps, std::size_t num_pieces,
                                      std::size_t budget) {
  const auto n = static_cast<std::int32_t>(lists.start.size() - 1);
  std::vector<std::int64_t> end(n);
  for (std::int32_t i = 0; i < n; ++i) {
    end[i] = std::upper_bound(lists.need.begin() + lists.start[i], lists.need.begin() + lists.start[i + 1],
                              static_cast<float>(eps)) -
             lists.need.begin();
  }
  std::vector<char> covered(num_pieces, 0);
  std::size_t uncovered = num_pieces;
  using Entry = std::pair<std::int64_t, std::int32_t>;  // (count, -index): ties -> lower index
  std::priority_queue<Entry> heap;
  for (std::int32_t i = 0; i < n; ++i) {
    if (end[i] > lists.start[i]) heap.push({end[i] - lists.start[i], -i});
  }
  std::vector<std::int32_t> chosen;
  while (uncovered > 0) {
    if (heap.empty() || chosen.size() >= budget) return {};
    const auto [stale, neg] = heap.top();
    heap.pop();
    const std::int32_t i = -neg;
    std::int64_t fresh = 0;
    for (std::int64_t k = lists.start[i]; k < end[i]; ++k) fresh += !covered[lists.items[k]];
    if (fresh == 0) continue;
    if (!heap.empty() && fresh < heap.top().first) {
      heap.push({fresh, neg});
      continue;
    }
    chosen.push_back(i);
    for (std::int64_t k = lists.start[i]; k < end[i]; ++k) {
      uncovered -= !covered[lists.items[k]];
      covered[lists.items[k]] = 1;
    }
  }
  return chosen;
}

// The smallest protrusion bound (to 1 %) whose greedy cover fits the budget,
// with the cover lists it was computed from.
struct MinMaxCover {
  std::vector<std::int32_t> chosen;
  double eps = 0;
  CoverLists lists;  // computed at a bound >= eps
};

// `feasible_eps` > 0 is a bound known to fit the budget (the previous round's:
// splitting pieces never makes a cover worse); then no bracketing is needed.
MinMaxCover CoverWithBudget(const std::vector<Candidate>& cands, const std::vector<Piece>& pieces,
                            std::size_t budget, double start_eps, double feasible_eps, double diag,
                            const std::function<void()>& tick) {
  const PieceBvh bvh(pieces);
  MinMaxCover out;
  double lists_eps = -1;
  auto attempt = [&](double eps) {
    tick();
    if (eps > lists_eps) {
      out.lists = ComputeCovers(cands, pieces, bvh, eps);
      lists_eps = eps;
    }
    return GreedyCover(out.lists, eps, pieces.size(), budget);
  };
  // Bracket by doubling (unless a feasible bound is known), then bisect.
  double lo = 0, hi = feasible_eps > 0 ? feasible_eps : start_eps;
  while ((out.chosen = attempt(hi)).empty()) {
    lo = hi;
    hi *= 2;
    if (hi > 4 * diag) throw SphereTreeError("no cover found (is the mesh a solid?)");
  }
  // To 1 % of the bound: finer steps change the tree, not its fit.
  for (int i = 0; i < 14 && hi - lo > 1e-2 * hi; ++i) {
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

// The least protrusion bound with which any candidate encloses each piece.
std::vector<float> PieceFloors(const CoverLists& lists, std::size_t num_pieces) {
  std::vector<float> floor(num_pieces, std::numeric_limits<float>::infinity());
  for (std::size_t k = 0; k < lists.items.size(); ++k) {
    floor[lists.items[k]] = std::min(floor[lists.items[k]], lists.need[k]);
  }
  return floor;
}

// Splits the marked pieces into four at their edge midpoints.
std::vector<Piece> SplitPieces(const std::vector<Piece>& pieces, const std::vector<char>& split) {
  std::vector<Piece> out;
  out.reserve(pieces.size() + 3 * std::count(split.begin(), split.end(), 1));
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const Piece& p = pieces[i];
    if (!split[i]) {
      out.push_back(p);
      continue;
    }
    const Vector3 a = 0.5 * (p.v[0] + p.v[1]), b = 0.5 * (p.v[1] + p.v[2]), c = 0.5 * (p.v[2] + p.v[0]);
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
  for (std::int32_t p : members) {
    for (const Vector3& v : pieces[p].v) r2 = std::max(r2, (v - c).squaredNorm());
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
      double r2 = 0;
      for (const Vector3& v : piece.v) r2 = std::max(r2, (v - l.c).squaredNorm());
      const double e = std::sqrt(r2) - l.depth;
      if (e < best) {
        best = e;
        best_leaf = i;
      }
    }
    (*leaves)[best_leaf].pieces.push_back(static_cast<std::int32_t>(p));
  }
  std::erase_if(*leaves, [](const Leaf& l) { return l.pieces.empty(); });
}

// Moves each leaf's centre to the candidate (or a point toward the smallest ball
// around its pieces) that encloses the same pieces with the least protrusion.
void RefineLeaves(std::vector<Leaf>* leaves, const std::vector<Piece>& pieces,
                  const std::vector<Candidate>& cands, const MeshOracle& oracle) {
  using MTraits = CGAL::Min_sphere_of_spheres_d_traits_3<K, double, CGAL::Tag_true>;
  using MinSphere = CGAL::Min_sphere_of_spheres_d<MTraits>;
  for (Leaf& l : *leaves) {
    double best = CoverError(l.c, l.depth, pieces, l.pieces);
    const Vector3 any = pieces[l.pieces.front()].v[0];
    for (const Candidate& c : cands) {
      if ((any - c.c).norm() - c.depth >= best) continue;  // cannot beat the current error
      const double e = CoverError(c.c, c.depth, pieces, l.pieces);
      if (e < best) {
        best = e;
        l.c = c.c;
        l.depth = c.depth;
      }
    }
    // Toward the smallest enclosing ball of the pieces' corners.
    std::vector<MTraits::Sphere> corners;
    for (std::int32_t p : l.pieces) {
      for (const Vector3& v : pieces[p].v) corners.emplace_back(K::Point_3(v.x(), v.y(), v.z()), 0.0);
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
}

// Spends the leaf budget left after the min-max cover on the worst leaves: each
// is replaced by the two candidates that enclose its pieces with the least
// bound, when that is clearly lower. Lowers the mean protrusion, and the worst
// where the worst leaf can be split.
void SplitWorstLeaves(std::vector<Leaf>* leaves, std::size_t budget, const std::vector<Piece>& pieces,
                      const std::vector<Candidate>& cands, const CoverLists& lists) {
  // Reverse index: piece -> (candidate, need) entries.
  std::vector<std::int64_t> start(pieces.size() + 1, 0);
  for (std::int32_t p : lists.items) ++start[p + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<std::pair<std::int32_t, float>> by_piece(lists.items.size());
  {
    std::vector<std::int64_t> fill(start.begin(), start.end() - 1);
    for (std::size_t c = 0; c + 1 < lists.start.size(); ++c) {
      for (std::int64_t k = lists.start[c]; k < lists.start[c + 1]; ++k) {
        by_piece[fill[lists.items[k]]++] = {static_cast<std::int32_t>(c), lists.need[k]};
      }
    }
  }
  auto error_of = [&](const Leaf& l) { return CoverError(l.c, l.depth, pieces, l.pieces); };
  std::vector<double> error(leaves->size());
  std::vector<char> final_leaf(leaves->size(), 0);
  for (std::size_t i = 0; i < leaves->size(); ++i) error[i] = error_of((*leaves)[i]);
  std::vector<std::int32_t> member_stamp(pieces.size(), -1);
  std::vector<std::int32_t> cand_stamp(cands.size(), -1);
  std::vector<std::int32_t> near;
  int stamp = 0;
  while (leaves->size() < budget) {
    std::size_t worst = leaves->size();
    for (std::size_t i = 0; i < leaves->size(); ++i) {
      if (!final_leaf[i] && (worst == leaves->size() || error[i] > error[worst])) worst = i;
    }
    if (worst == leaves->size()) break;
    const Leaf& leaf = (*leaves)[worst];
    ++stamp;
    near.clear();
    for (std::int32_t p : leaf.pieces) {
      member_stamp[p] = stamp;
      for (std::int64_t k = start[p]; k < start[p + 1]; ++k) {
        const std::int32_t c = by_piece[k].first;
        if (cand_stamp[c] != stamp) {
          cand_stamp[c] = stamp;
          near.push_back(c);
        }
      }
    }
    // Best pair by greedy at a bisected bound below the leaf's error.
    std::vector<char> covered(pieces.size(), 0);
    auto pair_at = [&](double eps, std::int32_t* a, std::int32_t* b) {
      std::int32_t pick[2] = {-1, -1};
      std::size_t left = leaf.pieces.size();
      for (int round = 0; round < 2 && left > 0; ++round) {
        std::size_t best_count = 0;
        for (std::int32_t c : near) {
          std::size_t count = 0;
          for (std::int64_t k = lists.start[c]; k < lists.start[c + 1] && lists.need[k] <= eps; ++k) {
            const std::int32_t p = lists.items[k];
            count += member_stamp[p] == stamp && !covered[p];
          }
          if (count > best_count) {
            best_count = count;
            pick[round] = c;
          }
        }
        if (pick[round] < 0) break;
        for (std::int64_t k = lists.start[pick[round]];
             k < lists.start[pick[round] + 1] && lists.need[k] <= eps; ++k) {
          const std::int32_t p = lists.items[k];
          if (member_stamp[p] == stamp && !covered[p]) {
            covered[p] = 1;
            --left;
          }
        }
      }
      for (std::int32_t p : leaf.pieces) covered[p] = 0;
      *a = pick[0];
      *b = pick[1];
      return left == 0;
    };
    double lo = 0, hi = error[worst];
    std::int32_t best_a = -1, best_b = -1;
    for (int i = 0; i < 10; ++i) {
      const double mid = 0.5 * (lo + hi);
      std::int32_t a, b;
      if (pair_at(mid, &a, &b)) {
        hi = mid;
        best_a = a;
        best_b = b;
      } else {
        lo = mid;
      }
    }
    if (best_a < 0 || hi > 0.9 * error[worst]) {
      final_leaf[worst] = 1;
      continue;
    }
    // Replace the leaf by the pair; each takes the pieces it encloses best.
    Leaf la{cands[best_a].c, cands[best_a].depth, {}};
    Leaf lb = best_b >= 0 ? Leaf{cands[best_b].c, cands[best_b].depth, {}} : Leaf{};
    for (std::int32_t p : leaf.pieces) {
      const double ea = CoverError(la.c, la.depth, pieces, {p});
      const double eb = best_b >= 0 ? CoverError(lb.c, lb.depth, pieces, {p})
                                    : std::numeric_limits<double>::infinity();
      (ea <= eb ? la : lb).pieces.push_back(p);
    }
    (*leaves)[worst] = std::move(la);
    error[worst] = error_of((*leaves)[worst]);
    if (best_b >= 0 && !lb.pieces.empty()) {
      leaves->push_back(std::move(lb));
      error.push_back(error_of(leaves->back()));
      final_leaf.push_back(0);
    }
  }
}

// Splits items (indices into centres) into at most `parts` groups by recursive
// bisection along the longest axis of their bounding box, sizes proportional.
void SplitGroup(std::vector<std::int32_t> items, int parts, const std::vector<Vector3>& centers,
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
    return centers[a][axis] != centers[b][axis] ? centers[a][axis] < centers[b][axis] : a < b;
  });
  const int left_parts = parts / 2;
  const std::size_t cut = items.size() * left_parts / parts;
  SplitGroup({items.begin(), items.begin() + cut}, left_parts, centers, out);
  SplitGroup({items.begin() + cut, items.end()}, parts - left_parts, centers, out);
}

}  // namespace

SphereTree BuildTreeFromLeaves(const std::vector<Vector3>& centers, const std::vector<double>& radii,
                               int levels, int branching) {
  if (centers.empty() || centers.size() != radii.size()) {
    throw SphereTreeError("a tree needs at least one leaf, with one radius per centre");
  }
  std::size_t capacity = 1;
  for (int l = 1; l < levels; ++l) capacity *= branching;
  if (centers.size() > capacity) {
    throw SphereTreeError(std::to_string(centers.size()) + " leaves do not fit in " +
                          std::to_string(levels) + " levels of " + std::to_string(branching));
  }
  Aabb bounds;
  for (const Vector3& c : centers) bounds.Extend(c);
  const double extent = std::max(bounds.LargestExtent(), *std::max_element(radii.begin(), radii.end()));
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
    const int parts = static_cast<int>(std::min<std::size_t>(branching, below[node].size()));
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


std::string SphereTreeParams::ToString() const {
  std::ostringstream s;
  s.precision(17);
  s << "levels=" << levels << " branch=" << branching << " leaves=" << leaves
    << " target_error_mm=" << target_error_mm << " samples=" << samples << " seed=" << seed;
  return s.str();
}

SphereTree BuildSphereTree(const TriangleMesh& mesh, const SphereTreeParams& params,
                           const BuildProgress& progress, SphereTreeBuildStats* stats) {
  const auto t0 = Clock::now();
  const Reporter report(progress);
  if (params.levels < 1 || params.levels > 8) {
    throw SphereTreeError("levels " + std::to_string(params.levels) + " is out of range (expected 1 to 8)");
  }
  if (params.branching < 2 || params.branching > 32) {
    throw SphereTreeError("branching " + std::to_string(params.branching) + " is out of range (expected 2 to 32)");
  }
  std::size_t capacity = 1;
  for (int l = 1; l < params.levels; ++l) capacity *= params.branching;
  if (params.target_error_mm < 0 || !std::isfinite(params.target_error_mm)) {
    throw SphereTreeError("target error must be a positive number of mm");
  }
  if (params.target_error_mm == 0 &&
      (params.leaves < 1 || static_cast<std::size_t>(params.leaves) > capacity)) {
    throw SphereTreeError("leaf budget " + std::to_string(params.leaves) + " does not fit in " +
                          std::to_string(params.levels) + " levels of " +
                          std::to_string(params.branching) + " (at most " +
                          std::to_string(capacity) + " leaves)");
  }
  const MeshReport check = mesh.Check();
  if (!check.closed() || !check.manifold()) {
    throw SphereTreeError("the mesh must be a closed, manifold surface (" +
                          std::to_string(check.boundary_edges) + " boundary and " +
                          std::to_string(check.nonmanifold_edges) + " non-manifold edges)");
  }
  const double extent = check.bounds.LargestExtent();
  const double diag = check.bounds.extent().norm();
  if (!(extent > 0) || std::abs(check.volume) <= 1e-9 * extent * extent * extent) {
    throw SphereTreeError("the mesh encloses no volume (it is flat or degenerate)");
  }
  const double orientation = check.volume > 0 ? 1.0 : -1.0;  // inward meshes still work

  // 1. Pieces and samples.
  const std::size_t budget = params.target_error_mm > 0 ? capacity : params.leaves;
  const int wanted = params.samples > 0 ? params.samples
                                        : std::min(60000, std::max(3000, 8 * static_cast<int>(budget)));
  double h = std::sqrt(check.area / (0.433 * wanted));
  std::vector<Vector3> normals;
  std::vector<Piece> pieces = Subdivide(mesh, h, &normals, orientation);
  while (pieces.size() > 4u * static_cast<std::size_t>(wanted)) {  // long thin faces
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
  const std::vector<Candidate> cands = MedialCandidates(samples, normals, diag, oracle, medial_report);
  if (cands.empty()) throw SphereTreeError("no point of the medial axis was found inside the mesh");
  const double seconds_medial = Seconds(t0);

  // 3. Cover: the smallest protrusion bound whose greedy cover fits the budget,
  // refining the surface pieces that bind it (where the fit is worst).
  const auto t_cover = Clock::now();
  int runs = 0;
  auto tick = [&] { report("cover", 0.4 + 0.4 * std::min(1.0, runs++ / 60.0)); };
  MinMaxCover cover;
  const std::size_t max_pieces = 6 * static_cast<std::size_t>(wanted);
  // Pieces whose best possible bound is above `limit` are split, a few rounds.
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
      throw SphereTreeError("a protrusion of at most " + std::to_string(eps) +
                            " mm needs more leaves than " + std::to_string(params.levels) +
                            " levels of " + std::to_string(params.branching) + " hold (" +
                            std::to_string(capacity) + "); allow more levels or a larger error");
    }
  } else {
    for (int round = 0;; ++round) {
      cover = CoverWithBudget(cands, pieces, budget, 0.02 * h, round > 0 ? cover.eps : 0.0, diag, tick);
      if (round == 3 || !refine_binding(cover.lists, 0.6 * cover.eps)) break;
    }
  }

  std::vector<Leaf> leaves;
  leaves.reserve(budget);
  for (std::int32_t i : cover.chosen) leaves.push_back({cands[i].c, cands[i].depth, {}});
  AssignPieces(&leaves, pieces);
  report("refine", 0.82);
  RefineLeaves(&leaves, pieces, cands, oracle);
  AssignPieces(&leaves, pieces);
  if (params.target_error_mm == 0) {
    SplitWorstLeaves(&leaves, budget, pieces, cands, cover.lists);
    RefineLeaves(&leaves, pieces, cands, oracle);
    AssignPieces(&leaves, pieces);
  }
  std::vector<Vector3> centers;
  std::vector<double> radii;
  double bound = 0;
  for (const Leaf& l : leaves) {
    double r2 = 0;
    for (std::int32_t p : l.pieces) {
      for (const Vector3& v : pieces[p].v) r2 = std::max(r2, (v - l.c).squaredNorm());
    }
    const double r = std::sqrt(r2) * (1 + 1e-12) + 1e-12 * extent;
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
