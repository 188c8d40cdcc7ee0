#include "core/anatomy/findings.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/anatomy/gingiva.h"
#include "core/geometry/primitives.h"

namespace sulcus {

Vector3 CariesCentre(const ToothModel& tooth, ToothSurface surface) {
  const ToothDimensions& d = tooth.dimensions;
  const bool anterior = tooth.tooth.position <= 3;
  // The vertex that maximises a score: outward along the surface's direction at
  // the wanted height.
  auto best = [&](auto score) {
    const Vector3* arg = &tooth.mesh.vertices().front();
    double top = -1e300;
    for (const Vector3& v : tooth.mesh.vertices()) {
      const double s = score(v);
      if (s > top) {
        top = s;
        arg = &v;
      }
    }
    return *arg;
  };
  const double contact = (anterior ? 0.75 : 0.6) * d.crown_height;
  switch (surface) {
    case ToothSurface::kMesial:
    case ToothSurface::kDistal: {
      const double sx = surface == ToothSurface::kMesial ? 1 : -1;
      const double z = contact - 1.5;  // just cervical of the contact
      return best([&](const Vector3& v) {
        return sx * v.x() - 3 * std::abs(v.z() - z) - std::abs(v.y());
      });
    }
    case ToothSurface::kBuccal:
    case ToothSurface::kLingual: {
      const double sy = surface == ToothSurface::kBuccal ? 1 : -1;
      const double z =
          0.2 * d.crown_height + 0.8;  // the cervical third, above the CEJ's scallop
      return best([&](const Vector3& v) {
        return sy * v.y() - 3 * std::abs(v.z() - z) - std::abs(v.x());
      });
    }
    case ToothSurface::kOcclusal:
      if (anterior) {
        // The lingual fossa below the incisal edge.
        const double z = 0.7 * d.crown_height;
        return best([&](const Vector3& v) {
          return -v.y() - 3 * std::abs(v.z() - z) - std::abs(v.x());
        });
      }
      // The central fossa: the crown's top surface nearest the long axis.
      return best([&](const Vector3& v) {
        return v.z() > 0.5 * d.crown_height ? v.z() - 4 * std::hypot(v.x(), v.y())
                                            : -1e300;
      });
  }
  return Vector3::Zero();
}

SurfacePoint CariesSpot(const ToothModel& tooth, ToothSurface surface) {
  SurfacePoint out;
  out.point = CariesCentre(tooth, surface);
  Vector3 n = Vector3::Zero();
  const auto& v = tooth.mesh.vertices();
  for (const auto& f : tooth.mesh.faces()) {
    if (v[f[0]] != out.point && v[f[1]] != out.point && v[f[2]] != out.point) continue;
    n += (v[f[1]] - v[f[0]]).cross(v[f[2]] - v[f[0]]);
  }
  if (n.norm() > 0) out.normal = n.normalized();
  return out;
}

void CarveCavities(ToothModel* tooth, const std::array<double, 5>& caries_mm,
                   const std::array<double, 5>& cavity_mm) {
  // Where each cavity is and which way, from the intact surface, before any moves.
  struct Cavity {
    SurfacePoint at;
    double radius, depth;
  };
  std::vector<Cavity> cavities;
  for (int s = 0; s < 5; ++s)
    if (cavity_mm[s] > 0 && caries_mm[s] > 0)
      cavities.push_back({CariesSpot(*tooth, static_cast<ToothSurface>(s)), caries_mm[s],
                          std::min(cavity_mm[s], kMaxCavityMm)});
  if (cavities.empty()) return;
  const double facing =
      std::cos(70 * std::numbers::pi /
               180);  // a vertex moves when its normal is within 70 degrees
  const std::vector<Vector3> normals = tooth->mesh.VertexNormalSums();
  std::vector<Vector3> moved = tooth->mesh.vertices();
  for (std::size_t i = 0; i < moved.size(); ++i) {
    if (normals[i].norm() == 0) continue;
    const Vector3 v = moved[i], n = normals[i].normalized();
    double sink = 0;
    Vector3 along = Vector3::Zero();
    for (const Cavity& c : cavities) {
      const double d = (v - c.at.point).norm();
      if (d >= c.radius || n.dot(c.at.normal) < facing) continue;
      // A flat floor over the inner half, walls rising smoothly to the rim.
      const double t = std::clamp((d / c.radius - 0.5) / 0.5, 0.0, 1.0),
                   u = 1 - t * t * (3 - 2 * t);
      if (c.depth * u > sink) {
        sink = c.depth * u;
        along = c.at.normal;
      }
    }
    moved[i] = v - sink * along;
  }
  tooth->mesh = TriangleMesh(std::move(moved), tooth->mesh.faces());
}

std::vector<double> CariesCoverage(const ToothModel& tooth,
                                   const std::array<double, 5>& caries_mm) {
  std::vector<double> out(tooth.mesh.num_vertices(), 0.0);
  for (int s = 0; s < 5; ++s) {
    const double r = caries_mm[s];
    if (r <= 0) continue;
    const Vector3 c = CariesCentre(tooth, static_cast<ToothSurface>(s));
    for (std::size_t i = 0; i < out.size(); ++i) {
      const double d = (tooth.mesh.vertices()[i] - c).norm();
      if (d < r) out[i] = std::max(out[i], 1 - d / r);
    }
  }
  return out;
}

std::vector<double> LesionCoverage(const TriangleMesh& mesh, const Vector3& centre,
                                   double radius_mm) {
  std::vector<double> out(mesh.num_vertices(), 0.0);
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double d = (mesh.vertices()[i] - centre).norm();
    if (d < radius_mm) out[i] = 1 - d / radius_mm;
  }
  return out;
}

std::vector<double> InflammationCoverage(const std::vector<Vector3>& vertices,
                                         const std::array<bool, 6>& inflamed) {
  constexpr double kPi = std::numbers::pi;
  std::vector<double> out(vertices.size(), 0.0);
  const auto& angles = SiteAngles();
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const double th = std::atan2(vertices[i].y(), vertices[i].x());
    for (int s = 0; s < 6; ++s) {
      if (!inflamed[s]) continue;
      double d = std::abs(std::remainder(th - angles[s], 2 * kPi));
      // Sites are pi/4 apart (pi/2 across the proximal surfaces): full within
      // pi/10 of the site, none beyond pi/4.
      const double w = std::clamp((kPi / 4 - d) / (kPi / 4 - kPi / 10), 0.0, 1.0);
      out[i] = std::max(out[i], w);
    }
  }
  return out;
}

// How far a calculus deposit's lumps stand in or out, as a fraction of its size.
constexpr double kCalculusLumps = 1.0 / 6;

TriangleMesh MakeCalculus(const ToothModel& tooth, const GingivaModel* gingiva, int site,
                          bool subgingival) {
  const double th = SiteAngles()[site];
  double margin = 1.5, floor = -0.5;
  if (gingiva) {
    margin = gingiva->margin[site].z();
    floor = gingiva->floor[site].z();
  } else {
    const int k =
        static_cast<int>(std::lround(th / (2 * std::numbers::pi) * tooth.cej.size())) %
        tooth.cej.size();
    margin = tooth.cej[k].z() + 1.5;
    floor = margin - 2.0;
  }
  const double z = subgingival ? floor + (margin - floor) / 3 : margin + 0.8;
  const double r = OuterRadius(tooth.mesh, th, z);
  // Semi-axes: 1.0 along the surface (tangent), 0.6 up the tooth, 0.45 out of
  // it; the centre 0.15 mm inside the surface, so 0.3 mm stands proud.
  // Calculus is not smooth: the deposit's surface is lumpy, each vertex of the
  // unit sphere moved in or out by up to a sixth along its own direction (so
  // the solid stays star-shaped about its centre, and closed). The lumps differ
  // from site to site.
  TriangleMesh unit = MakeIcosphere(1.0, 3);
  std::vector<Vector3> lumpy;
  lumpy.reserve(unit.num_vertices());
  const double phase = 1.3 * site + (subgingival ? 0.7 : 0.0);
  for (const Vector3& u : unit.vertices()) {
    const double lumps = 0.5 * std::sin(3.1 * u.x() + 2.3 * u.y() + 1.7 + phase) *
                             std::cos(2.7 * u.z() - 1.1 * u.y()) +
                         0.5 * std::sin(4.3 * u.y() - 3.7 * u.z() + 0.4 + 2 * phase);
    lumpy.push_back(u * (1 + kCalculusLumps * lumps));
  }
  TriangleMesh m(std::move(lumpy), unit.faces());
  const Vector3 radial(std::cos(th), std::sin(th), 0),
      tangent(-std::sin(th), std::cos(th), 0);
  Matrix3 A;
  A.col(0) = 0.45 * radial;
  A.col(1) = 1.0 * tangent;
  A.col(2) = 0.6 * Vector3::UnitZ();
  m.Transform(A, (r - 0.15) * radial + Vector3(0, 0, z));
  if (m.Volume() < 0) m.FlipOrientation();
  return m;
}

}  // namespace sulcus
