// The cover: medial spheres chosen by a greedy set cover of the surface pieces,
// each piece enclosed within a protrusion bound (the builder's second stage).
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <queue>

#include "core/spheretree/builder_stages.h"

namespace sulcus::tree_build {

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
