#include "tests/bench/mouth_proxy.h"

#include <cmath>
#include <random>

#include "core/geometry/primitives.h"
#include "core/spheretree/cache.h"

namespace sulcus::bench {
namespace {

TriangleMesh Ellipsoid(const Vector3& semi_axes, int subdivisions) {
  TriangleMesh m = MakeIcosphere(1.0, subdivisions);
  m.Transform(semi_axes.asDiagonal(), Vector3::Zero());
  return m;
}

SphereTree Tree(const TriangleMesh& mesh) {
  return LoadOrBuildSphereTree(mesh, SphereTreeParams{},
                               std::filesystem::path(SULCUS_BENCH_CACHE));
}

}  // namespace

const MouthProxy& Mouth() {
  static const std::unique_ptr<MouthProxy> mouth = [] {
    auto m = std::make_unique<MouthProxy>();
    m->tooth_mesh = Ellipsoid(Vector3(4, 3.5, 10), 4);
    m->jaw_mesh = Ellipsoid(Vector3(30, 30, 6), 4);
    m->probe_mesh = MakeCylinder(0.4, 16, 24, 24);  // tip at the origin, shaft along +z
    m->tooth = Tree(m->tooth_mesh);
    m->jaw = Tree(m->jaw_mesh);
    m->probe = Tree(m->probe_mesh);
    // Arches y = -x^2 / 40 (mm), 16 teeth each every 8.2 mm of arc (8 mm wide
    // teeth with 0.2 mm gaps), upper at z = +12, lower at z = -12.
    std::vector<double> xs;
    for (double x = 0, arc = 4.1; xs.size() < 8; x += 0.001) {
      arc -= 0.001 * std::sqrt(1 + std::pow(2 * x / 40, 2));
      if (arc <= 0) {
        xs.push_back(x);
        arc += 8.2;
      }
    }
    for (int arch = 0; arch < 2; ++arch) {
      for (int i = 0; i < 16; ++i) {
        const double x = i < 8 ? -xs[7 - i] : xs[i - 8];
        const Matrix3 R = Eigen::AngleAxisd(std::atan(-2 * x / 40), Vector3::UnitZ())
                              .toRotationMatrix();
        const RigidTransform X(R, Vector3(x, -x * x / 40, arch ? 12 : -12));
        m->tooth_poses.push_back(X);
        m->objects.push_back({&m->tooth, X});
      }
    }
    m->objects.push_back(
        {&m->jaw, RigidTransform(Matrix3::Identity(), Vector3(0, -10, -28.5))});
    return m;
  }();
  return *mouth;
}

std::vector<RigidTransform> MouthProxy::ContactPoses(int n, unsigned seed,
                                                     int only_tooth) const {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> tooth(0, static_cast<int>(tooth_poses.size()) - 1);
  std::uniform_int_distribution<int> face(0,
                                          static_cast<int>(tooth_mesh.num_faces()) - 1);
  std::vector<RigidTransform> out;
  for (int i = 0; i < n; ++i) {
    int f = face(rng);
    // Buccal and lingual faces only: mesial and distal ones face the neighbours.
    while (std::abs(tooth_mesh.FaceNormal(f).y()) < 0.7) f = face(rng);
    const auto& t = tooth_mesh.faces()[f];
    const Vector3 p = (tooth_mesh.vertices()[t[0]] + tooth_mesh.vertices()[t[1]] +
                       tooth_mesh.vertices()[t[2]]) /
                      3;
    const Vector3 nrm = tooth_mesh.FaceNormal(f);
    const int which = tooth(rng);
    const RigidTransform& X_WO = tooth_poses[only_tooth >= 0 ? only_tooth : which];
    const Vector3 n_W = X_WO.rotation() * nrm;
    const Vector3 tip = X_WO * p - 0.02 * n_W;
    // Shaft (tool +z) along the outward normal.
    const Matrix3 R =
        Quaternion::FromTwoVectors(Vector3::UnitZ(), n_W).toRotationMatrix();
    out.emplace_back(R, tip);  // the probe's end face is its origin
  }
  return out;
}

}  // namespace sulcus::bench
