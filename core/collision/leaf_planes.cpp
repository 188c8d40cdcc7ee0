#include "core/collision/leaf_planes.h"

#include <algorithm>
#include <cmath>

namespace sulcus {
namespace {

// Largest n.p over the part of triangle (a, b, c) inside the ball (o, R); false
// when the triangle misses the ball.
bool MaxOverTriangleInBall(const Vector3& a, const Vector3& b, const Vector3& c,
                           const Vector3& o, double R, const Vector3& n, double* best) {
  bool any = false;
  auto take = [&](const Vector3& p) {
    const double f = n.dot(p);
    if (!any || f > *best) *best = f;
    any = true;
  };
  const double R2 = R * R;
  const Vector3 v[3] = {a, b, c};
  for (const Vector3& p : v)
    if ((p - o).squaredNorm() <= R2) take(p);
  // Where each edge crosses the sphere.
  for (int i = 0; i < 3; ++i) {
    const Vector3& p = v[i];
    const Vector3 e = v[(i + 1) % 3] - p;
    const double ee = e.squaredNorm();
    if (ee <= 0) continue;
    const Vector3 w = p - o;
    const double half_b = w.dot(e), cc = w.squaredNorm() - R2;
    const double disc = half_b * half_b - ee * cc;
    if (disc < 0) continue;
    const double s = std::sqrt(disc);
    for (const double t : {(-half_b - s) / ee, (-half_b + s) / ee})
      if (t >= 0 && t <= 1) take(p + t * e);
  }
  // The extreme of the disc where the triangle's plane cuts the ball, when it
  // lies inside the triangle.
  const Vector3 m_raw = (b - a).cross(c - a);
  const double twice_area = m_raw.norm();
  if (twice_area > 0) {
    const Vector3 m = m_raw / twice_area;
    const double h = (o - a).dot(m);
    const double rho2 = R2 - h * h;
    if (rho2 >= 0) {
      const Vector3 centre = o - h * m;
      const Vector3 u = n - n.dot(m) * m;
      const double un = u.norm();
      const Vector3 p =
          un > 1e-12 ? Vector3(centre + std::sqrt(rho2) * (u / un)) : centre;
      // Inside the triangle: on the inner side of each edge.
      bool inside = true;
      for (int i = 0; i < 3 && inside; ++i)
        inside = (v[(i + 1) % 3] - v[i]).cross(p - v[i]).dot(m) >= -1e-12 * twice_area;
      if (inside) take(p);
    }
  }
  return any;
}

}  // namespace

int LeafPlanes::count() const {
  return static_cast<int>(
      std::count_if(d.begin(), d.end(), [](const auto& x) { return x[0] < kNone; }));
}

bool LeafPlanes::Below(std::size_t node, const Vector3& p, double tolerance) const {
  const std::uint8_t united = node < concave.size() ? concave[node] : 0;
  bool cut = true, any_united = united == 0;
  for (int j = 0; j < kMaxPlanes && d[node][j] < kNone; ++j) {
    const bool below = n[node][j].dot(p) <= d[node][j] + tolerance;
    if (united & (1u << j))
      any_united = any_united || below;
    else
      cut = cut && below;
  }
  return cut && any_united;
}

LeafPlanes FitLeafPlanes(const TriangleMesh& mesh, const SphereTree& tree,
                         const LeafPlaneParams& params) {
  constexpr int K = LeafPlanes::kMaxPlanes;
  LeafPlanes out;
  std::array<Vector3, K> no_n;
  no_n.fill(Vector3::Zero());
  std::array<double, K> no_d;
  no_d.fill(LeafPlanes::kNone);
  out.n.assign(tree.size(), no_n);
  out.d.assign(tree.size(), no_d);
  out.concave.assign(tree.size(), 0);
  if (tree.empty()) return out;
  const auto& V = mesh.vertices();
  const auto& F = mesh.faces();
  // The faces near each leaf: each face's bounding ball down the tree.
  std::vector<std::vector<std::int32_t>> near(tree.size());
  std::vector<std::int32_t> stack;
  for (std::size_t f = 0; f < F.size(); ++f) {
    const Vector3 a = V[F[f][0]], b = V[F[f][1]], c = V[F[f][2]];
    const Vector3 centre = (a + b + c) / 3.0;
    const double r =
        std::sqrt(std::max({(a - centre).squaredNorm(), (b - centre).squaredNorm(),
                            (c - centre).squaredNorm()}));
    stack.assign(1, 0);
    while (!stack.empty()) {
      const std::int32_t node = stack.back();
      stack.pop_back();
      if ((tree.center(node) - centre).norm() > tree.r[node] + r) continue;
      if (tree.IsLeaf(node)) {
        near[node].push_back(static_cast<std::int32_t>(f));
      } else {
        for (int k = 0; k < tree.child_count[node]; ++k)
          stack.push_back(tree.first_child[node] + k);
      }
    }
  }
  const double cos_group = std::cos(params.group_angle_deg * M_PI / 180.0);
  struct Meeting {
    std::int32_t face;
    Vector3 normal;
    double area;
  };
  std::vector<Meeting> meeting;
  for (std::size_t leaf = 0; leaf < tree.size(); ++leaf) {
    if (!tree.IsLeaf(leaf) || near[leaf].empty()) continue;
    const Vector3 o = tree.center(leaf);
    const double R = tree.r[leaf];
    // The faces that meet the sphere, each weighted by its area (at most the
    // sphere's great disc).
    meeting.clear();
    for (const std::int32_t f : near[leaf]) {
      const Vector3 a = V[F[f][0]], b = V[F[f][1]], c = V[F[f][2]];
      double unused = 0;
      const Vector3 m = mesh.FaceNormal(static_cast<std::size_t>(f));
      if (m.squaredNorm() == 0 ||
          !MaxOverTriangleInBall(a, b, c, o, R, Vector3::UnitZ(), &unused))
        continue;
      meeting.push_back(
          {f, m, std::min(0.5 * (b - a).cross(c - a).norm(), M_PI * R * R)});
    }
    if (meeting.empty()) continue;
    // Groups by normal: seeds taken farthest first (the largest face, then the
    // face least like every seed so far, while one is further than the group
    // angle), then each group's mean normal, twice.
    std::array<Vector3, K> seeds;
    int groups = 0;
    seeds[groups++] = std::max_element(meeting.begin(), meeting.end(),
                                       [](const Meeting& x, const Meeting& y) {
                                         return x.area < y.area;
                                       })
                          ->normal;
    while (groups < K) {
      double least = 2;
      Vector3 next = Vector3::Zero();
      for (const Meeting& m : meeting) {
        double like = -2;
        for (int g = 0; g < groups; ++g) like = std::max(like, m.normal.dot(seeds[g]));
        if (like < least) least = like, next = m.normal;
      }
      if (least >= cos_group) break;
      seeds[groups++] = next;
    }
    for (int round = 0; round < 2; ++round) {
      std::array<Vector3, K> sum;
      sum.fill(Vector3::Zero());
      for (const Meeting& m : meeting) {
        int best = 0;
        for (int g = 1; g < groups; ++g)
          if (m.normal.dot(seeds[g]) > m.normal.dot(seeds[best])) best = g;
        sum[best] += m.area * m.normal;
      }
      for (int g = 0; g < groups; ++g)
        if (sum[g].norm() > 1e-12) seeds[g] = sum[g].normalized();
    }
    // by[g][h]: the largest n_g.p over the part inside the sphere of the faces
    // of group h (-kNone: none).
    std::array<std::array<double, K>, K> by;
    for (auto& row : by) row.fill(-LeafPlanes::kNone);
    for (const Meeting& m : meeting) {
      int h = 0;
      for (int g = 1; g < groups; ++g)
        if (m.normal.dot(seeds[g]) > m.normal.dot(seeds[h])) h = g;
      const auto& f = F[m.face];
      for (int g = 0; g < groups; ++g) {
        double top = 0;
        if (MaxOverTriangleInBall(V[f[0]], V[f[1]], V[f[2]], o, R, seeds[g], &top))
          by[g][h] = std::max(by[g][h], top);
      }
    }
    // A concave crease: two or three groups each of whose planes the others'
    // faces rise above, which lowers their planes by more than the lift in
    // all. Their planes are united, each bounding the faces of its own group
    // and of the groups outside the crease; every other plane bounds every
    // face (-kNone: none).
    constexpr double kRaised = 1e-6;  // mm: above round-off
    // Plane g's offset with the groups in `mask` united.
    auto offset = [&](int g, unsigned mask) {
      double d = -LeafPlanes::kNone;
      for (int h = 0; h < groups; ++h)
        if (h == g || !(mask & (1u << g)) || !(mask & (1u << h)))
          d = std::max(d, by[g][h]);
      return d;
    };
    auto cuts = [&](int g, unsigned mask) {
      return offset(g, mask) < seeds[g].dot(o) + R - 1e-9;
    };
    // Whether the groups in `mask` form a crease, and by how much it lowers
    // their planes in all.
    auto crease = [&](unsigned mask, double* lowered) {
      bool ok = params.concave_lift_mm > 0;
      *lowered = 0;
      for (int g = 0; g < groups && ok; ++g) {
        if (!(mask & (1u << g))) continue;
        const double own = offset(g, mask);
        ok = own > -LeafPlanes::kNone && cuts(g, mask);
        for (int h = 0; h < groups && ok; ++h)
          if (h != g && (mask & (1u << h))) ok = by[g][h] > own + kRaised;
        *lowered += offset(g, 0) - own;
      }
      return ok && *lowered > params.concave_lift_mm;
    };
    unsigned united = 0;
    double best_lowered = 0;
    for (const unsigned mask : {7u, 3u, 5u, 6u}) {
      if (mask >= (1u << groups)) continue;
      double lowered = 0;
      if (crease(mask, &lowered) && lowered > best_lowered)
        united = mask, best_lowered = lowered;
      if (united == 7u) break;  // all three: a corner
    }
    // A plane that does not cut the sphere changes nothing and is left out.
    int kept = 0;
    std::uint8_t kept_united = 0;
    for (int g = 0; g < groups; ++g) {
      if (!cuts(g, united)) continue;
      out.n[leaf][kept] = seeds[g];
      out.d[leaf][kept] = offset(g, united);
      if (united & (1u << g)) kept_united |= static_cast<std::uint8_t>(1u << kept);
      ++kept;
    }
    out.concave[leaf] = kept_united;
  }
  return out;
}

}  // namespace sulcus
