#include "core/spheretree/metrics.h"

#include <cmath>
#include <numbers>

#include "core/spheretree/mesh_oracle.h"
#include "core/spheretree/random.h"

namespace sulcus {
namespace {

using detail::Uniform;

// Evenly spread unit vectors (Fibonacci lattice).
std::vector<Vector3> SphereDirections(int n) {
  std::vector<Vector3> out;
  out.reserve(n);
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n;
    const double rho = std::sqrt(1 - z * z);
    out.emplace_back(rho * std::cos(golden * i), rho * std::sin(golden * i), z);
  }
  return out;
}

std::vector<Vector3> SurfaceSamples(const TriangleMesh& mesh, int n, std::uint64_t seed) {
  std::vector<double> cumulative;
  cumulative.reserve(mesh.num_faces());
  double total = 0;
  for (const auto& f : mesh.faces()) {
    const auto& v = mesh.vertices();
    total += 0.5 * (v[f[1]] - v[f[0]]).cross(v[f[2]] - v[f[0]]).norm();
    cumulative.push_back(total);
  }
  std::vector<Vector3> out(mesh.vertices());
  std::uint64_t rng = seed;
  for (int i = 0; i < n; ++i) {
    const double pick = Uniform(rng) * total;
    const std::size_t f = std::min<std::size_t>(
        std::lower_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin(),
        mesh.num_faces() - 1);
    double u = Uniform(rng), v = Uniform(rng);
    if (u + v > 1) {
      u = 1 - u;
      v = 1 - v;
    }
    const auto& face = mesh.faces()[f];
    const auto& vs = mesh.vertices();
    out.push_back(vs[face[0]] + u * (vs[face[1]] - vs[face[0]]) +
                  v * (vs[face[2]] - vs[face[0]]));
  }
  return out;
}

}  // namespace

TreeMetrics EvaluateSphereTree(const TriangleMesh& mesh, const SphereTree& tree,
                               const EvalParams& params) {
  tree.Validate();
  const MeshOracle oracle(mesh);
  TreeMetrics out;
  const MeshReport report = mesh.Check();
  out.largest_extent_mm = report.bounds.LargestExtent();
  out.volume_mm3 = std::abs(report.volume);
  const std::vector<Vector3> surface =
      SurfaceSamples(mesh, params.surface_samples, params.seed);
  out.surface_samples = surface.size();
  const std::vector<Vector3> dirs = SphereDirections(params.points_per_sphere);
  const double tolerance = 1e-9 * out.largest_extent_mm;  // containment round-off

  // Per node: protrusion and the depth of its centre (negative when outside).
  const std::size_t n = tree.size();
  std::vector<double> protrusion(n, 0.0), depth(n, -1.0);
  std::vector<std::int32_t> parent(n, -1);
  for (std::size_t i = 0; i < n; ++i) {
    for (int c = 0; c < tree.child_count[i]; ++c)
      parent[tree.first_child[i] + c] = static_cast<std::int32_t>(i);
    const Vector3 c = tree.center(i);
    if (oracle.Inside(c)) depth[i] = oracle.Distance(c);
    if (depth[i] >= tree.r[i]) continue;  // entirely inside the solid
    double worst = 0;
    for (const Vector3& d : dirs) {
      const Vector3 p = c + tree.r[i] * d;
      if (!oracle.Inside(p)) worst = std::max(worst, oracle.Distance(p));
    }
    protrusion[i] = worst;
  }

  std::uint64_t rng = params.seed ^ 0xA5A5A5A5ull;
  for (int l = 0; l < tree.levels; ++l) {
    const std::vector<std::int32_t> cut = tree.CutAtLevel(l);
    if (cut.empty()) continue;
    LevelMetrics m;
    m.level = l;
    m.spheres = cut.size();
    for (std::int32_t i : cut) {
      m.protrusion_max_mm = std::max(m.protrusion_max_mm, protrusion[i]);
      m.protrusion_mean_mm += protrusion[i];
    }
    m.protrusion_mean_mm /= static_cast<double>(cut.size());

    // How many spheres of the cut hold p.
    auto holding = [&](const Vector3& p) {
      int count = 0;
      for (std::int32_t i : cut)
        count += (p - tree.center(i)).norm() <= tree.r[i] + tolerance;
      return count;
    };
    std::size_t holders = 0;
    for (const Vector3& p : surface) {
      const int count = holding(p);
      m.uncovered_samples += count == 0;
      holders += count;
    }
    m.overlap = static_cast<double>(holders) / static_cast<double>(surface.size());
    m.coverage = 1.0 - static_cast<double>(m.uncovered_samples) /
                           static_cast<double>(surface.size());

    // Union volume outside the solid: sample each ball uniformly and weight a point
    // by 1 / (number of balls holding it), so overlaps count once.
    double excess = 0;
    for (std::int32_t i : cut) {
      if (depth[i] >= tree.r[i]) continue;
      double sum = 0;
      for (int s = 0; s < params.volume_samples_per_sphere; ++s) {
        Vector3 d;
        do {
          d = Vector3(2 * Uniform(rng) - 1, 2 * Uniform(rng) - 1, 2 * Uniform(rng) - 1);
        } while (d.squaredNorm() > 1);
        const Vector3 p = tree.center(i) + tree.r[i] * d;
        if (depth[i] > 0 && (p - tree.center(i)).norm() <= depth[i])
          continue;  // inner ball
        if (oracle.Inside(p)) continue;
        sum += 1.0 / std::max(1, holding(p));
      }
      excess += 4.0 / 3.0 * std::numbers::pi * std::pow(tree.r[i], 3) * sum /
                params.volume_samples_per_sphere;
    }
    m.excess_volume = excess / out.volume_mm3;

    std::size_t with_parent = 0, inside = 0;
    for (std::int32_t i : tree.NodesOnLevel(l)) {
      if (parent[i] < 0) continue;
      ++with_parent;
      inside += (tree.center(i) - tree.center(parent[i])).norm() + tree.r[i] <=
                tree.r[parent[i]] + tolerance;
    }
    m.children_inside = with_parent ? static_cast<double>(inside) / with_parent : 1.0;
    out.levels.push_back(m);
  }
  return out;
}

}  // namespace sulcus
