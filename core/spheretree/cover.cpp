// The cover: medial spheres chosen by a greedy set cover of the surface pieces,
// each piece enclosed within a protrusion bound (the builder's second stage).
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <optional>
#include <queue>

#include "core/spheretree/builder_stages.h"

namespace sulcus::tree_build {

CoverLists ComputeCovers(const std::vector<Candidate>& cands, const PieceBvh& bvh,
                         double eps_max) {
  CoverLists lists;
  lists.start.reserve(cands.size() + 1);
  lists.start.push_back(0);
  std::vector<std::pair<float, std::int32_t>> found;
  for (const Candidate& c : cands) {
    found.clear();
    bvh.ForEachEnclosed(c.c, c.depth + eps_max, [&](std::int32_t p, double r2) {
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

std::vector<std::int32_t> GreedyCover(const CoverLists& lists, double eps,
                                      std::size_t num_pieces, std::size_t budget,
                                      const std::vector<float>* limit) {
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

std::vector<float> PieceFloors(const CoverLists& lists, std::size_t num_pieces) {
  std::vector<float> floor(num_pieces, std::numeric_limits<float>::infinity());
  for (std::size_t k = 0; k < lists.items.size(); ++k) {
    floor[lists.items[k]] = std::min(floor[lists.items[k]], lists.need[k]);
  }
  return floor;
}

constexpr float kFloorSlack = 1.3f;

namespace {

// Searching every candidate for each of `pieces` costs about a nanosecond a
// pair; it pays against lists of tens of millions of entries up to about 10^8
// pairs (a few tenths of a second).
bool SearchPays(std::size_t pieces, std::size_t cands) {
  return static_cast<double>(pieces) * static_cast<double>(cands) <= 1e8;
}

// A candidate encloses a piece within a protrusion bound eps: the test the
// lists are made with (ComputeCovers' ball query).
bool Encloses(const Candidate& c, const Piece& p, double eps) {
  return FarCorner2(p, c.c) <= (c.depth + eps) * (c.depth + eps);
}

// The bound a candidate needs for a piece, as the lists store it (rounded up).
float Need(const Candidate& c, const Piece& p) {
  return std::nextafter(static_cast<float>(std::sqrt(FarCorner2(p, c.c)) - c.depth),
                        1e30f);
}

// The lists at `cap` as the bisection below eps_g uses them, without computing
// them for the whole surface at `cap`: the lists at eps_g (`general`), and,
// for the few pieces whose best bound times kFloorSlack is above eps_g (hard
// spots: a thin rim, a sharp edge), every candidate that encloses them within
// `cap` but not within eps_g and needs at most kFloorSlack times their best
// (found by search). A greedy cover at any eps <= eps_g then sees exactly the
// entries it would see in the lists at `cap`. At 1.6 mm a gingiva's lists hold
// 20 to 30 million entries, for a cover at 0.3 mm. Returns false, leaving
// `general` as it was, when too many pieces are hard for the search to pay.
bool AddHardPieces(const std::vector<Candidate>& cands,
                   const CentreKdTree<Candidate>& tree, const std::vector<Piece>& pieces,
                   double eps_g, double cap, CoverLists* general) {
  const std::vector<float> floor = PieceFloors(*general, pieces.size());
  const auto feps = static_cast<float>(eps_g);
  const auto inf = std::numeric_limits<float>::infinity();
  std::vector<std::int32_t> hard;
  for (std::size_t p = 0; p < pieces.size(); ++p)
    if (floor[p] == inf || std::nextafter(kFloorSlack * floor[p], inf) > feps)
      hard.push_back(static_cast<std::int32_t>(p));
  if (!SearchPays(hard.size(), cands.size())) return false;
  struct Extra {
    std::int32_t cand;
    std::int32_t piece;
    float need;
  };
  std::vector<Extra> extra, mine;
  // (the candidates that can reach each hard piece within the cap, from the
  // k-d tree over them, in index order: the same entries, in the same order,
  // as a scan)
  std::vector<std::int32_t> near;
  for (const std::int32_t p : hard) {
    mine.clear();
    float best = floor[p];
    tree.Within(pieces[p].centroid, cap, &near);
    for (const std::int32_t i : near) {
      if (!Encloses(cands[i], pieces[p], cap) || Encloses(cands[i], pieces[p], eps_g))
        continue;
      const float need = Need(cands[i], pieces[p]);
      best = std::min(best, need);
      mine.push_back({i, p, need});
    }
    const float limit = std::nextafter(kFloorSlack * best, inf);
    for (const Extra& e : mine)
      if (e.need <= limit) extra.push_back(e);
  }
  std::sort(extra.begin(), extra.end(), [](const Extra& a, const Extra& b) {
    return a.cand != b.cand ? a.cand < b.cand : a.need < b.need;
  });
  CoverLists out;
  out.start.reserve(general->start.size());
  out.items.reserve(general->items.size() + extra.size());
  out.need.reserve(general->items.size() + extra.size());
  out.start.push_back(0);
  std::size_t e = 0;
  const std::size_t n = general->start.size() - 1;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::int64_t k = general->start[i]; k < general->start[i + 1]; ++k) {
      out.items.push_back(general->items[k]);
      out.need.push_back(general->need[k]);
    }
    for (; e < extra.size() && extra[e].cand == static_cast<std::int32_t>(i); ++e) {
      out.items.push_back(extra[e].piece);
      out.need.push_back(extra[e].need);
    }
    out.start.push_back(static_cast<std::int64_t>(out.items.size()));
  }
  *general = std::move(out);
  return true;
}

// ComputeCovers' test, as its query makes it: the candidate encloses the
// piece within the bound eps (every corner within depth + eps of the centre).
bool EnclosesAsQueried(const Candidate& c, const Piece& p, double eps) {
  const double radius = c.depth + eps;
  static_assert(sizeof(p.v) == 9 * sizeof(double), "a piece's corners lie in a row");
  return FarCorner2Of(p.v[0].data(), c.c.x(), c.c.y(), c.c.z()) <= radius * radius;
}

// For each piece, the index of the first of `bounds` (ascending) at which
// some candidate encloses it (ComputeCovers' test), or bounds.size() when
// none does. Found from the candidate with the smallest bound for it (a k-d
// search over `tree`, the k-d tree of `cands`); where that bound lies within
// rounding of one of `bounds`, the test itself decides, over the candidates
// that can reach the piece there.
std::vector<int> FirstReach(const std::vector<Candidate>& cands,
                            const CentreKdTree<Candidate>& tree,
                            const std::vector<Piece>& pieces,
                            const std::vector<double>& bounds) {
  const int n = static_cast<int>(bounds.size());
  std::vector<int> first(pieces.size(), n);
  std::vector<std::int32_t> near;
  for (std::size_t p = 0; p < pieces.size(); ++p) {
    const Piece& piece = pieces[p];
    const Candidate& best = cands[tree.Best(piece)];
    const double g = std::sqrt(FarCorner2(piece, best.c)) - best.depth;
    int k = static_cast<int>(std::lower_bound(bounds.begin(), bounds.end(), g) -
                             bounds.begin());
    const double tie = 1e-9 * (1 + std::abs(g));
    const bool near_bound =
        (k < n && bounds[k] - g < tie) || (k > 0 && g - bounds[k - 1] < tie);
    if (near_bound) {
      k = std::max(0, k - 1);
      auto reached = [&](int at) {
        tree.Within(piece.centroid, bounds[at], &near);
        return std::any_of(near.begin(), near.end(), [&](std::int32_t i) {
          return EnclosesAsQueried(cands[i], piece, bounds[at]);
        });
      };
      while (k < n && !reached(k)) ++k;
    }
    first[p] = k;
  }
  return first;
}

}  // namespace

MinMaxCover CoverWithBudget(const std::vector<Candidate>& cands,
                            const std::vector<Piece>& pieces, std::size_t budget,
                            double start_eps, double reach_eps, double diag,
                            const std::function<void()>& tick) {
  const PieceBvh bvh(pieces);
  // The candidates' k-d tree, made once when a search first needs it.
  std::optional<CentreKdTree<Candidate>> kd;
  auto cand_tree = [&]() -> const CentreKdTree<Candidate>& {
    if (!kd) kd.emplace(cands);
    return *kd;
  };
  MinMaxCover out;
  auto use_lists = [&](CoverLists lists, double eps) {
    out.lists = std::move(lists);
    out.lists_eps = eps;
    out.limits = PieceFloors(out.lists, pieces.size());
    for (float& f : out.limits)
      f = std::nextafter(kFloorSlack * f, std::numeric_limits<float>::infinity());
  };
  auto attempt = [&](double eps) {
    tick();
    if (eps > out.lists_eps) use_lists(ComputeCovers(cands, bvh, eps), eps);
    return GreedyCover(out.lists, eps, pieces.size(), budget, &out.limits);
  };
  // Bracket: grow until every piece is reachable and the cover fits.
  double hi = reach_eps > 0 ? reach_eps : start_eps;
  const double grow = reach_eps > 0 ? 1.25 : 2.0;
  auto next = [&] {
    hi *= grow;
    if (hi > 4 * diag) throw SphereTreeError("no cover found (is the mesh a solid?)");
  };
  // The bracket stops at the first bound that reaches every piece (and fits).
  // While most pieces are out of reach, the lists are cheap and computed as
  // the bracket goes; once only a few are (hard spots), the bound that reaches
  // them is found by search, and the lists at half of it (plus the hard
  // pieces' entries) give the bisection below it the same covers as the
  // lists at it would, for a fraction of their size. A first bound from an
  // earlier round (reach_eps) is checked the same way from half of it.
  // A first bracket (no earlier round) needs, at each bound it passes, only
  // how many pieces no candidate reaches. Each piece's first reaching bound
  // gives those counts for every bound at once: the bracket steps (ticks,
  // growth and its limit as below) to the first bound whose count stops it,
  // and the lists are computed there alone.
  if (!(reach_eps > 0)) {
    std::vector<double> bounds;
    for (double e = hi; e <= 4 * diag; e *= grow) bounds.push_back(e);
    std::vector<std::size_t> reached_first(bounds.size() + 1, 0);
    for (const int k : FirstReach(cands, cand_tree(), pieces, bounds)) ++reached_first[k];
    std::size_t unreached = pieces.size() - reached_first[0];
    for (std::size_t k = 0; unreached > 0 && !SearchPays(unreached, cands.size()); ++k) {
      tick();
      next();
      unreached -= reached_first[k + 1];
    }
  }
  std::optional<std::vector<std::int32_t>> first_half;
  double found = 0;
  for (double e = reach_eps > 0 ? 0.5 * hi : hi;;) {
    CoverLists lists = ComputeCovers(cands, bvh, e);
    const std::vector<float> floor = PieceFloors(lists, pieces.size());
    std::vector<std::int32_t> unreached;
    for (std::size_t p = 0; p < pieces.size(); ++p)
      if (floor[p] == std::numeric_limits<float>::infinity())
        unreached.push_back(static_cast<std::int32_t>(p));
    if (e == hi && unreached.empty()) {
      use_lists(std::move(lists), hi);  // the lists the bracket computes anyway
      break;
    }
    if (!SearchPays(unreached.size(), cands.size())) {
      if (e < hi) break;  // the bracket's own lists at the earlier round's bound
      tick();             // (the bracket's attempt here fails: pieces out of reach)
      next();
      e = hi;
      continue;
    }
    // The first bound of the bracket that reaches every piece.
    std::vector<std::int32_t> near;
    auto reaches = [&](double eps) {
      for (const std::int32_t p : unreached) {
        cand_tree().Within(pieces[p].centroid, eps, &near);
        const bool any = std::any_of(near.begin(), near.end(), [&](std::int32_t i) {
          return Encloses(cands[i], pieces[p], eps);
        });
        if (!any) return false;
      }
      return true;
    };
    if (e == hi) next();
    while (!reaches(hi)) next();
    const double half = 0.5 * hi;
    if (half != e) lists = ComputeCovers(cands, bvh, half);
    if (!AddHardPieces(cands, cand_tree(), pieces, half, hi, &lists)) break;
    use_lists(std::move(lists), hi);
    tick();
    first_half = GreedyCover(out.lists, half, pieces.size(), budget, &out.limits);
    if (first_half->empty()) {
      // The bisection would look above half: the lists at the bound itself.
      first_half.reset();
      out.lists_eps = 0;
    }
    found = hi;
    break;
  }
  if (first_half) {
    out.chosen = *first_half;  // (a cover at half fits; one at the bound does too)
  } else {
    if (found > 0) hi = found;
    while ((out.chosen = attempt(hi)).empty()) next();
  }
  // Bisect below it with the same lists. A failure in the bracket may have been
  // an unreachable piece, which the lists now reach, so the search starts at 0.
  double lo = 0;
  for (int i = 0; i < 14 && hi - lo > 2e-2 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    auto c = i == 0 && first_half ? *first_half : attempt(mid);
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

double CoverError(const Vector3& c, double depth, const std::vector<Piece>& pieces,
                  const std::vector<std::int32_t>& members) {
  double r2 = 0;
  for (std::int32_t p : members) r2 = std::max(r2, FarCorner2(pieces[p], c));
  return std::sqrt(r2) - depth;
}

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

}  // namespace sulcus::tree_build
