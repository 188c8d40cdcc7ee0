// Leaf refinement: the cover's leaves tightened, traded and cut under the leaf
// budget, every surface piece kept inside the leaf that holds it (the builder's
// third stage).
#include <CGAL/Min_sphere_of_spheres_d.h>
#include <CGAL/Min_sphere_of_spheres_d_traits_3.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>
#include <unordered_map>
#include <utility>

#include "core/geometry/cgal_internal.h"
#include "core/spheretree/builder_stages.h"
#include "core/spheretree/mesh_oracle.h"

namespace sulcus::tree_build {
namespace {

using K = CgalKernel;

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

// Each leaf's radius (its bound at depth 0), with a hair for round-off.
std::vector<double> LeafRadii(const std::vector<Leaf>& leaves,
                              const std::vector<Piece>& pieces) {
  std::vector<double> radius(leaves.size());
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    radius[i] = CoverError(leaves[i].c, 0.0, pieces, leaves[i].pieces) * (1 + 1e-12);
  }
  return radius;
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

}  // namespace

void AssignPieces(std::vector<Leaf>* leaves, const std::vector<Piece>& pieces) {
  for (Leaf& l : *leaves) l.pieces.clear();
  const CentreKdTree<Leaf> tree(*leaves);
  for (std::size_t p = 0; p < pieces.size(); ++p)
    (*leaves)[tree.Best(pieces[p])].pieces.push_back(static_cast<std::int32_t>(p));
  std::erase_if(*leaves, [](const Leaf& l) { return l.pieces.empty(); });
}

void RefineLeaves(std::vector<Leaf>* leaves, const std::vector<Piece>& pieces,
                  const CandidateIndex& index, const MeshOracle& oracle,
                  bool toward_ball) {
  for (Leaf& l : *leaves) RefineLeaf(&l, pieces, index, oracle, toward_ball);
}

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
      bvh.ForEachEnclosed(c, radius[i], [&](std::int32_t p, double r2) {
        const double margin = radius[i] - std::sqrt(r2);
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

}  // namespace sulcus::tree_build
