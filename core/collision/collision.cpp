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
    }
  }
  for (std::size_t n = 0; n < tool.size(); ++n) {
    if (tool.IsLeaf(n)) tool_reach_ = std::max(tool_reach_, tool.center(n).norm() + tool.r[n]);
  }
}

CollisionScratch::CollisionScratch(const CollisionWorld& world)
    : tool_center_W(world.tool().size()), stamp(world.tool().size(), 0) {}

CollisionStats FindContacts(const CollisionWorld& world, const RigidTransform& X_WT, double margin,
                            CollisionScratch* s, ContactPair* out, int capacity) noexcept {
  CollisionStats stats;
  const SphereTree& tool = world.tool();
  const Matrix3& R = X_WT.rotation();
  const Vector3& p = X_WT.translation();
  if (++s->query == 0) {  // wrapped: clear stamps once every 4 billion queries
    std::fill(s->stamp.begin(), s->stamp.end(), 0u);
    s->query = 1;
  }
  const std::uint32_t q = s->query;
  auto tool_center = [&](std::int32_t n) -> const Vector3& {
    if (s->stamp[n] != q) {
      s->stamp[n] = q;
      s->tool_center_W[n] = R * Vector3(tool.x[n], tool.y[n], tool.z[n]) + p;
    }
    return s->tool_center_W[n];
  };
  const double* ox = world.ox_.data();
  const double* oy = world.oy_.data();
  const double* oz = world.oz_.data();
  const double* orad = world.orad_.data();

  for (int obj = 0; obj < world.num_objects(); ++obj) {
    const std::size_t base = world.offset_[obj];
    const std::int32_t* ofirst = world.ofirst_.data() + base;
    const std::uint8_t* ocount = world.ocount_.data() + base;
    int top = 0;
    s->stack_tool[top] = 0;
    s->stack_obj[top] = 0;
    ++top;
    while (top > 0) {
      --top;
      const std::int32_t a = s->stack_tool[top], b = s->stack_obj[top];
      const Vector3& ca = tool_center(a);
      const std::size_t k = base + b;
      const double dx = ca.x() - ox[k], dy = ca.y() - oy[k], dz = ca.z() - oz[k];
      const double reach = tool.r[a] + orad[k] + margin;
      const double d2 = dx * dx + dy * dy + dz * dz;
      ++stats.node_tests;
      if (d2 >= reach * reach) continue;  // the first test is the broad phase
      const bool a_leaf = tool.child_count[a] == 0, b_leaf = ocount[b] == 0;
      if (a_leaf && b_leaf) {
        if (stats.pairs < capacity) {
          out[stats.pairs++] = {obj, b, a, std::sqrt(d2) - tool.r[a] - orad[k]};
        } else {
          stats.overflow = true;
        }
        continue;
      }
      // Descend the larger sphere (or the only non-leaf).
      const bool split_tool = b_leaf || (!a_leaf && tool.r[a] >= orad[k]);
      const int children = split_tool ? tool.child_count[a] : ocount[b];
      if (top + children > CollisionScratch::kStackCapacity) {
        stats.stack_overflow = true;
        continue;
      }
      for (int c = children - 1; c >= 0; --c) {
        s->stack_tool[top] = split_tool ? tool.first_child[a] + c : a;
        s->stack_obj[top] = split_tool ? b : ofirst[b] + c;
        ++top;
      }
    }
  }
  std::sort(out, out + stats.pairs,
            [](const ContactPair& x, const ContactPair& y) { return x.key() < y.key(); });
  return stats;
}

std::vector<ContactPair> FindContactsReference(const CollisionWorld& world, const RigidTransform& X_WT,
                                               double margin) {
  std::vector<ContactPair> out;
  const SphereTree& tool = world.tool();
  for (int obj = 0; obj < world.num_objects(); ++obj) {
    const SphereTree& ot = world.object_tree(obj);
    // Algorithm 1: if the two spheres are within the margin, either report the
    // leaf pair or recurse into every child pair.
    std::function<void(std::int32_t, std::int32_t)> visit = [&](std::int32_t a, std::int32_t b) {
      const Vector3 ca = X_WT * tool.center(a);
      const Vector3 cb = world.ObjectCenter(obj, b);
      const double gap = (ca - cb).norm() - tool.r[a] - ot.r[b];
      if (!(gap < margin)) return;
      if (tool.IsLeaf(a) && ot.IsLeaf(b)) {
        out.push_back({obj, b, a, gap});
        return;
      }
      if (tool.IsLeaf(a)) {
        for (int j = 0; j < ot.child_count[b]; ++j) visit(a, ot.first_child[b] + j);
      } else if (ot.IsLeaf(b)) {
        for (int i = 0; i < tool.child_count[a]; ++i) visit(tool.first_child[a] + i, b);
      } else {
        for (int i = 0; i < tool.child_count[a]; ++i) {
          for (int j = 0; j < ot.child_count[b]; ++j) visit(tool.first_child[a] + i, ot.first_child[b] + j);
        }
      }
    };
    visit(0, 0);
  }
  std::sort(out.begin(), out.end(), [](const ContactPair& x, const ContactPair& y) { return x.key() < y.key(); });
  return out;
}

}  // namespace sulcus
