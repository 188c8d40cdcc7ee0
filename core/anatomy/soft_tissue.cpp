#include "core/anatomy/soft_tissue.h"

#include <stdexcept>

#include "core/geometry/primitives.h"

namespace sulcus {
namespace {

TriangleMesh Ellipsoid(const Vector3& centre, const Vector3& radii) {
  TriangleMesh m = MakeIcosphere(1.0, 4);
  m.Transform(radii.asDiagonal(), centre);
  return m;
}

// A tube along the arch y = -k x^2 (|x| <= half_width) at height z.
TriangleMesh ArchTube(double k, double half_width, double z, double radius) {
  std::vector<Vector3> path;
  std::vector<double> radii;
  const int n = 48;
  for (int i = 0; i <= n; ++i) {
    const double x = -half_width + 2 * half_width * i / n;
    path.emplace_back(x, -k * x * x, z);
    const double end = std::min(i, n - i);
    radii.push_back(end == 0 ? 0.0 : radius * std::min(1.0, std::sqrt(end / 2.0)));
  }
  return MakeSweep(path, radii, 24);
}

}  // namespace

const std::vector<std::string>& SoftTissueNames() {
  static const std::vector<std::string> names = {"tongue", "palate", "cheek_left", "cheek_right", "jaw_lower",
                                                 "jaw_upper"};
  return names;
}

TriangleMesh MakeSoftTissue(const std::string& name, const ArchParams& arch) {
  const double lift = arch.upper_lift_mm;
  if (name == "tongue") return Ellipsoid({0, -21, -4}, {14.5, 21, 9});
  if (name == "palate") return Ellipsoid({0, -19, 21 + lift}, {16, 22, 6});
  if (name == "cheek_left") return Ellipsoid({34, -19, lift / 2}, {3, 19, 15 + lift / 2});
  if (name == "cheek_right") return Ellipsoid({-34, -19, lift / 2}, {3, 19, 15 + lift / 2});
  if (name == "jaw_lower") return ArchTube(arch.k_lower, 25, -13, 6.5);
  if (name == "jaw_upper") return ArchTube(arch.k_upper, 27, 13 + lift, 6.5);
  std::string known;
  for (const std::string& n : SoftTissueNames()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown anatomy '" + name + "'; known: " + known);
}

}  // namespace sulcus
