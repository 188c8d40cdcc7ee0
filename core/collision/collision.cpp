#include "core/collision/collision.h"

#include <algorithm>
#include <cmath>
#include <functional>

namespace sulcus {

CollisionWorld::CollisionWorld(const SphereTree& tool, const std::vector<Object>& objects)
    : tool_(&tool), objects_(objects) {
  std::size_t total = 0;
  for (const Object& o : objects_) {
    offset_.push_back(total);
    total += o.tree->size();
  }
  ox_.reserve(total);
  oy_.reserve(total);
  oz_.reserve(total);
  orad_.reserve(total);
  ofirst_.reserve(total);
  ocount_.reserve(total);
  planes_.reserve(total * kPlaneStride);
  concave_.reserve(total);
  for (const Object& o : objects_) {
    const SphereTree& t = *o.tree;
    for (std::size_t n = 0; n < t.size(); ++n) {
      const Vector3 c = o.X_WO * t.center(n);
      ox_.push_back(c.x());
      oy_.push_back(c.y());
      oz_.push_back(c.z());
      orad_.push_back(t.r[n]);
      ofirst_.push_back(t.first_child[n]);
      ocount_.push_back(t.child_count[n]);
      concave_.push_back(
          o.planes != nullptr && n < o.planes->concave.size() ? o.planes->concave[n] : 0);
      for (int j = 0; j < LeafPlanes::kMaxPlanes; ++j) {
        const bool used = o.planes != nullptr && n < o.planes->d.size() &&
                          o.planes->d[n][j] < LeafPlanes::kNone;
        const Vector3 pn =
            used ? Vector3(o.X_WO.rotation() * o.planes->n[n][j]) : Vector3::Zero();
        planes_.insert(planes_.end(),
                       {pn.x(), pn.y(), pn.z(),
                        used ? o.planes->d[n][j] + pn.dot(o.X_WO.translation())
                             : LeafPlanes::kNone});
      }
    }
  }
  for (std::size_t n = 0; n < tool.size(); ++n) {
    if (tool.IsLeaf(n))
      tool_reach_ = std::max(tool_reach_, tool.center(n).norm() + tool.r[n]);
  }
}

double CollisionWorld::ClippedGap(std::size_t k, const Vector3& c_W, double r,
                                  Vector3* normal, int piece) const {
  const Vector3 c(ox_[k], oy_[k], oz_[k]);
  const double* pl = &planes_[k * kPlaneStride];
  Vector3 dir;
  double gap = 0;
  const unsigned united = concave_[k];
  if (united == 0) {
    gap = CutBallDistance(c, orad_[k], pl, c_W, &dir);
  } else {
    // The ball cut by the other planes and by the union of the crease's: the
    // part `piece`, or the nearest part (the ball cut by the others and by
    // each of the crease's).
    int used = 0;
    while (used < LeafPlanes::kMaxPlanes && pl[4 * used + 3] < LeafPlanes::kNone) ++used;
    gap = LeafPlanes::kNone;
    for (int u = 0; u < used; ++u) {
      if (!(united & (1u << u)) || (piece > 0 && u != piece - 1)) continue;
      // Plane u and the planes outside the crease, ended by an unused one.
      double some[kPlaneStride];
      int taken = 0;
      for (int j = 0; j < used; ++j)
        if (j == u || !(united & (1u << j)))
          std::copy_n(pl + 4 * j, 4, some + 4 * taken++);
      if (taken < LeafPlanes::kMaxPlanes) some[4 * taken + 3] = LeafPlanes::kNone;
      Vector3 d;
      const double g = CutBallDistance(c, orad_[k], some, c_W, &d);
      if (g < gap) gap = g, dir = d;
    }
  }
  if (normal) *normal = dir;
  return gap - r;
}

double CollisionWorld::CutBallDistance(const Vector3& c, double R, const double* pl,
                                       const Vector3& c_W, Vector3* dir) {
  Vector3 nearest;
  double gap = PolyhedronDistance(pl, c_W, dir, &nearest);
  // Outside, with the polyhedron's nearest point in the sphere: that is the
  // cut sphere's nearest point too (the common case, a tool over a face).
  if (!(gap > 0 && (nearest - c).squaredNorm() <= R * R)) {
    for (int j = 0; j < LeafPlanes::kMaxPlanes && pl[4 * j + 3] < LeafPlanes::kNone;
         ++j) {
      Vector3 d;
      const double g = BallHalfSpaceDistance(c, R, &pl[4 * j], c_W, &d);
      if (g > gap) gap = g, *dir = d;
    }
  }
  return gap;
}

double CollisionWorld::PolyhedronDistance(const double* pl, const Vector3& q,
                                          Vector3* dir, Vector3* nearest) {
  constexpr int K = LeafPlanes::kMaxPlanes;
  Vector3 n[K];
  double d[K], s[K];
  int m = 0;
  for (; m < K && pl[4 * m + 3] < LeafPlanes::kNone; ++m) {
    n[m] = Vector3(pl[4 * m], pl[4 * m + 1], pl[4 * m + 2]);
    d[m] = pl[4 * m + 3];
    s[m] = n[m].dot(q) - d[m];
  }
  int top = 0;
  for (int j = 1; j < m; ++j)
    if (s[j] > s[top]) top = j;
  // Inside every half space: the depth below the nearest face.
  *nearest = q;
  if (s[top] <= 0) {
    *dir = n[top];
    return s[top];
  }
  constexpr double kSlack = 1e-9;
  auto feasible = [&](const Vector3& p) {
    for (int j = 0; j < m; ++j)
      if (n[j].dot(p) - d[j] > kSlack) return false;
    return true;
  };
  // The face furthest out: its foot, when inside the others, is the nearest
  // point (no point of the polyhedron is nearer than that face's distance).
  *nearest = q - s[top] * n[top];
  if (feasible(*nearest)) {
    *dir = n[top];
    return s[top];
  }
  // Else an edge where two faces meet, or the corner of three: the nearest
  // feasible foot.
  double best = -1;
  Vector3 best_foot = q;
  for (int a = 0; a < m; ++a) {
    for (int b = a + 1; b < m; ++b) {
      // q - x n_a - y n_b on both planes: [1 c; c 1] [x; y] = [s_a; s_b].
      const double c = n[a].dot(n[b]), det = 1 - c * c;
      if (det < 1e-9) continue;
      const double x = (s[a] - c * s[b]) / det, y = (s[b] - c * s[a]) / det;
      const Vector3 foot = q - x * n[a] - y * n[b];
      const double dist = (q - foot).norm();
      if ((best < 0 || dist < best) && feasible(foot)) best = dist, best_foot = foot;
    }
  }
  if (m == 3) {
    Matrix3 N;
    N.row(0) = n[0].transpose();
    N.row(1) = n[1].transpose();
    N.row(2) = n[2].transpose();
    if (std::abs(N.determinant()) > 1e-9) {
      const Vector3 corner = N.inverse() * Vector3(d[0], d[1], d[2]);
      const double dist = (q - corner).norm();
      if (best < 0 || dist < best) best = dist, best_foot = corner;
    }
  }
  if (best <= 1e-12) {
    // Numerically on an edge (or no foot found): the face furthest out, a lower bound.
    *dir = n[top];
    return s[top];
  }
  *nearest = best_foot;
  *dir = (q - best_foot) / best;
  return best;
}

double CollisionWorld::BallHalfSpaceDistance(const Vector3& c, double R, const double* pl,
                                             const Vector3& q, Vector3* dir) {
  const Vector3 n(pl[0], pl[1], pl[2]);
  const double s = n.dot(q) - pl[3];
  const Vector3 away = q - c;
  const double dist = away.norm();
  const Vector3 radial = dist > 1e-12 ? Vector3(away / dist) : Vector3::Zero();
  if (dist <= R && s <= 0) {
    // Inside both: the shallower way out.
    if (dist - R > s) {
      *dir = radial;
      return dist - R;
    }
    *dir = n;
    return s;
  }
  // Outside the ball with its nearest point below the plane: that point.
  if (dist > R && n.dot(c + R * radial) - pl[3] <= 0) {
    *dir = radial;
    return dist - R;
  }
  // Else the nearest point of the disc the plane cuts from the ball.
  const double h = n.dot(c) - pl[3];
  const double a = std::sqrt(std::max(0.0, R * R - h * h));
  const Vector3 centre = c - h * n;
  const Vector3 foot = q - s * n;
  const Vector3 out = foot - centre;
  const double o = out.norm();
  const Vector3 nearest = o <= a || o < 1e-12 ? foot : Vector3(centre + (a / o) * out);
  const Vector3 to_q = q - nearest;
  const double len = to_q.norm();
  *dir = len > 1e-12 ? Vector3(to_q / len) : n;
  return len;
}

CollisionStats FindContacts(const CollisionWorld& world, const RigidTransform& X_WT,
                            double margin, CollisionScratch* s, ContactPair* out,
                            int capacity, const QueryLimits& limits) noexcept {
  CollisionStats stats;
  const SphereTree& tool = world.tool();
  const Matrix3& R = X_WT.rotation();
  const Matrix3 Rt = R.transpose();
  const Vector3& p = X_WT.translation();
  const double* tx = tool.x.data();
  const double* ty = tool.y.data();
  const double* tz = tool.z.data();
  const double* tr = tool.r.data();
  const double* ox = world.ox_.data();
  const double* oy = world.oy_.data();
  const double* oz = world.oz_.data();
  const double* orad = world.orad_.data();
  double d2[256];  // a node has at most 255 children

  // Tests `count` spheres (contiguous in x, y, z, r from `first`) against the
  // point q with radius rq, in one loop the compiler can vectorise; then emits
  // leaf pairs and pushes overlapping pairs that can still be split.
  auto test_children = [&](const double* x, const double* y, const double* z,
                           const double* r, std::int32_t first, int count,
                           const Vector3& q, double rq, auto&& on_hit) {
    for (int c = 0; c < count; ++c) {
      const double dx = x[first + c] - q.x(), dy = y[first + c] - q.y(),
                   dz = z[first + c] - q.z();
      d2[c] = dx * dx + dy * dy + dz * dz;
    }
    stats.node_tests += count;
    for (int c = count - 1; c >= 0; --c) {
      const double reach = rq + r[first + c] + margin;
      if (d2[c] < reach * reach) on_hit(first + c, d2[c]);
    }
  };

  for (int obj = 0; obj < world.num_objects(); ++obj) {
    if (stats.cut_short) break;
    const std::size_t base = world.offset_[obj];
    const double* bx = ox + base;
    const double* by = oy + base;
    const double* bz = oz + base;
    const double* br = orad + base;
    const std::int32_t* ofirst = world.ofirst_.data() + base;
    const std::uint8_t* ocount = world.ocount_.data() + base;
    int top = 0;
    // A pair that overlaps: emitted when both are leaves, else pushed to be split.
    auto hit = [&](std::int32_t a, std::int32_t b, double dist2) {
      if (tool.child_count[a] == 0 && ocount[b] == 0) {
        auto emit = [&](int piece, double gap) {
          if (stats.pairs < capacity) {
            out[stats.pairs++] = {obj, b, a, piece, gap};
          } else {
            stats.overflow = true;
            if (limits.stop_when_full) stats.cut_short = true;
          }
        };
        double gap = std::sqrt(dist2) - tr[a] - br[b];
        if (gap < CollisionWorld::kPlanesWithinMm && world.Clipped(base + b)) {
          // A clipped leaf: its gap as LeafGap gives it; a pair only within the
          // margin; on a concave crease, a pair for each part within it.
          const Vector3 a_W = R * Vector3(tx[a], ty[a], tz[a]) + p;
          const unsigned united = world.concave_[base + b];
          if (united != 0) {
            for (int j = 0; j < LeafPlanes::kMaxPlanes; ++j) {
              if (!(united & (1u << j))) continue;
              gap = world.ClippedGap(base + b, a_W, tr[a], nullptr, j + 1);
              if (gap < margin) emit(j + 1, gap);
            }
            return;
          }
          gap = world.ClippedGap(base + b, a_W, tr[a], nullptr, 0);
          if (!(gap < margin)) return;
        }
        emit(0, gap);
      } else if (top == CollisionScratch::kStackCapacity) {
        stats.stack_overflow = true;
      } else {
        s->stack_tool[top] = a;
        s->stack_obj[top] = b;
        ++top;
      }
    };
    // The roots: the broad phase.
    const Vector3 root_T = Rt * (Vector3(bx[0], by[0], bz[0]) - p);
    test_children(tx, ty, tz, tr, 0, 1, root_T, br[0],
                  [&](std::int32_t a, double dd) { hit(a, 0, dd); });
    if (stats.cut_short) return stats;
    while (top > 0) {
      if (stats.cut_short ||
          (limits.max_node_tests > 0 && stats.node_tests >= limits.max_node_tests)) {
        stats.cut_short = true;
        return stats;
      }
      --top;
      const std::int32_t a = s->stack_tool[top], b = s->stack_obj[top];
      const bool a_leaf = tool.child_count[a] == 0, b_leaf = ocount[b] == 0;
      if (b_leaf || (!a_leaf && tr[a] >= br[b])) {
        // Split the tool node: the object sphere moves into the tool frame once.
        const Vector3 b_T = Rt * (Vector3(bx[b], by[b], bz[b]) - p);
        test_children(tx, ty, tz, tr, tool.first_child[a], tool.child_count[a], b_T,
                      br[b], [&](std::int32_t child, double dd) { hit(child, b, dd); });
      } else {
        // Split the object node: the tool sphere moves into the world once.
        const Vector3 a_W = R * Vector3(tx[a], ty[a], tz[a]) + p;
        test_children(bx, by, bz, br, ofirst[b], ocount[b], a_W, tr[a],
                      [&](std::int32_t child, double dd) { hit(a, child, dd); });
      }
    }
  }
  return stats;
}

std::vector<ContactPair> FindContactsReference(const CollisionWorld& world,
                                               const RigidTransform& X_WT,
                                               double margin) {
  std::vector<ContactPair> out;
  const SphereTree& tool = world.tool();
  for (int obj = 0; obj < world.num_objects(); ++obj) {
    const SphereTree& ot = world.object_tree(obj);
    // Algorithm 1: if the two spheres are within the margin, either report the
    // leaf pair or recurse into every child pair.
    std::function<void(std::int32_t, std::int32_t)> visit = [&](std::int32_t a,
                                                                std::int32_t b) {
      const Vector3 ca = X_WT * tool.center(a);
      const Vector3 cb = world.ObjectCenter(obj, b);
      const double gap = (ca - cb).norm() - tool.r[a] - ot.r[b];
      if (!(gap < margin)) return;
      if (tool.IsLeaf(a) && ot.IsLeaf(b)) {
        const unsigned united = world.UnitedPlanes(obj, b);
        if (united != 0 && gap < CollisionWorld::kPlanesWithinMm) {
          for (int j = 0; j < LeafPlanes::kMaxPlanes; ++j) {
            if (!(united & (1u << j))) continue;
            const double part = world.LeafGap(obj, b, ca, tool.r[a], nullptr, j + 1);
            if (part < margin) out.push_back({obj, b, a, j + 1, part});
          }
          return;
        }
        const double leaf_gap = world.LeafGap(obj, b, ca, tool.r[a]);
        if (leaf_gap < margin) out.push_back({obj, b, a, 0, leaf_gap});
        return;
      }
      if (tool.IsLeaf(a)) {
        for (int j = 0; j < ot.child_count[b]; ++j) visit(a, ot.first_child[b] + j);
      } else if (ot.IsLeaf(b)) {
        for (int i = 0; i < tool.child_count[a]; ++i) visit(tool.first_child[a] + i, b);
      } else {
        for (int i = 0; i < tool.child_count[a]; ++i) {
          for (int j = 0; j < ot.child_count[b]; ++j)
            visit(tool.first_child[a] + i, ot.first_child[b] + j);
        }
      }
    };
    visit(0, 0);
  }
  return out;
}

}  // namespace sulcus
