#include "core/anatomy/gingiva.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace sulcus {
namespace {

constexpr double kPi = std::numbers::pi;

// Periodic smooth interpolation of the six site values around the tooth, with
// the mesial (0) and distal (pi) points the mean of their neighbours.
double AroundTooth(const std::array<double, 6>& site, double th) {
  // Knots by angle: M, MB, B, DB, D, DL, L, ML.
  const double knots[8] = {0.5 * (site[0] + site[3]), site[0], site[1], site[2],
                           0.5 * (site[2] + site[5]), site[5], site[4], site[3]};
  double a = std::fmod(th, 2 * kPi);
  if (a < 0) a += 2 * kPi;
  const double x = a / (kPi / 4);
  const int i = static_cast<int>(std::floor(x)) % 8;
  const double t = x - std::floor(x);
  const double s = 0.5 - 0.5 * std::cos(kPi * t);
  return knots[i] + s * (knots[(i + 1) % 8] - knots[i]);
}

}  // namespace

// The farthest crossing of the horizontal ray from (0, 0, z) along angle th with
// the mesh (the tooth's outer surface in that direction), or 0 when it misses.
double OuterRadius(const TriangleMesh& mesh, double th, double z) {
  const Vector3 o(0, 0, z), d(std::cos(th), std::sin(th), 0);
  double best = 0;
  const auto& v = mesh.vertices();
  for (const auto& f : mesh.faces()) {
    const Vector3& a = v[f[0]];
    const Vector3 e1 = v[f[1]] - a, e2 = v[f[2]] - a;
    const Vector3 p = d.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-14) continue;
    const Vector3 s = o - a;
    const double u = s.dot(p) / det;
    if (u < 0 || u > 1) continue;
    const Vector3 q = s.cross(e1);
    const double w = d.dot(q) / det;
    if (w < 0 || u + w > 1) continue;
    best = std::max(best, e2.dot(q) / det);
  }
  return best;
}

double GingivaModel::FloorAt(double th) const {
  const int n = static_cast<int>(floor_z.size());
  if (n == 0) return 0;
  double a = std::fmod(th, 2 * kPi);
  if (a < 0) a += 2 * kPi;
  return floor_z[static_cast<int>(std::lround(a / (2 * kPi) * n)) % n];
}

const std::array<double, 6>& SiteAngles() {
  static const std::array<double, 6> a = {kPi / 4, kPi / 2, 3 * kPi / 4, 7 * kPi / 4, 3 * kPi / 2, 5 * kPi / 4};
  return a;
}

GingivaModel GenerateGingiva(const ToothModel& tooth, const GingivaParams& p) {
  if (p.segments < 8 || p.segments % 8 != 0)
    throw std::invalid_argument("gingiva segments must be a multiple of 8, at least 8");
  if (!(p.gap_mm >= 0.55)) throw std::invalid_argument("the sulcus must be at least 0.55 mm wide for a 0.5 mm probe tip");
  for (int i = 0; i < 6; ++i) {
    if (p.pocket_mm[i] < 0 || p.pocket_mm[i] + p.recession_mm[i] > MaxAttachmentLoss(tooth.dimensions))
      throw std::invalid_argument("pocket of " + std::to_string(p.pocket_mm[i]) + " mm at site " +
                                  std::to_string(i) + " does not fit the root of tooth " +
                                  std::to_string(tooth.tooth.fdi));
  }
  const int n = p.segments;
  const int wall_levels = 8;
  // Cross-section by angle: A margin, wall down to B, floor to C, D, E, F, G (top).
  std::vector<std::array<Vector3, 7 + wall_levels>> rings(n);  // (r, z) points as Vector3(r, z, 0)
  GingivaModel out;
  out.site_angle = SiteAngles();
  std::vector<double> r_in_at(n), z_m_at(n), z_f_at(n);
  for (int k = 0; k < n; ++k) {
    const double th = 2 * kPi * k / n;
    // The CEJ height at this angle (the tooth's CEJ curve has 72 points, evenly spaced).
    const double cej_z = tooth.cej[static_cast<std::size_t>(std::lround(72.0 * k / n)) % tooth.cej.size()].z();
    const double c2 = std::cos(th) * std::cos(th);
    const double papilla = p.papilla_mm * c2 * c2;
    const double z_m = cej_z + p.margin_above_cej_mm - AroundTooth(p.recession_mm, th) + papilla;
    const double z_f = z_m - AroundTooth(p.pocket_mm, th);
    double widest = 0;
    for (int j = 0; j <= 12; ++j) widest = std::max(widest, OuterRadius(tooth.mesh, th, z_f + (z_m - z_f) * j / 12.0));
    const double r_in = widest + p.gap_mm;
    const double thickness = p.thickness_mm * (0.35 + 0.65 * std::sin(th) * std::sin(th));
    const double r_out = r_in + thickness;
    const double r_floor = std::max(0.3, OuterRadius(tooth.mesh, th, z_f) - 0.3);
    auto& ring = rings[k];
    int i = 0;
    for (int j = 0; j < wall_levels; ++j) ring[i++] = Vector3(r_in, z_m + (z_f - z_m) * j / wall_levels, 0);  // A ..
    ring[i++] = Vector3(r_in, z_f, 0);                        // B
    ring[i++] = Vector3(r_floor, z_f, 0);                     // C
    ring[i++] = Vector3(r_floor, z_f - 1.0, 0);               // D
    ring[i++] = Vector3(r_out, z_f - 1.0, 0);                 // E
    ring[i++] = Vector3(r_out, z_m - 0.8, 0);                 // F
    ring[i++] = Vector3(r_in + 0.75 * thickness, z_m - 0.25, 0);  // G
    ring[i++] = Vector3(r_in + 0.35 * thickness, z_m - 0.03, 0);  // rounded top
    r_in_at[k] = r_in;
    z_m_at[k] = z_m;
    z_f_at[k] = z_f;
  }
  const int m = 7 + wall_levels;
  std::vector<Vector3> vertices;
  vertices.reserve(static_cast<std::size_t>(n) * m);
  for (int k = 0; k < n; ++k) {
    const double th = 2 * kPi * k / n;
    for (const Vector3& rz : rings[k]) vertices.emplace_back(rz.x() * std::cos(th), rz.x() * std::sin(th), rz.y());
  }
  std::vector<TriangleMesh::Face> faces;
  for (int k = 0; k < n; ++k) {
    const int k2 = (k + 1) % n;
    for (int i = 0; i < m; ++i) {
      const int i2 = (i + 1) % m;
      const int a = k * m + i, b = k * m + i2, c = k2 * m + i2, d = k2 * m + i;
      faces.push_back({a, b, c});
      faces.push_back({a, c, d});
    }
  }
  out.mesh = TriangleMesh(std::move(vertices), std::move(faces));
  out.floor_z = z_f_at;
  out.margin_z = z_m_at;
  out.sulcus_r.resize(n);
  for (int k = 0; k < n; ++k) out.sulcus_r[k] = r_in_at[k] - 0.5 * p.gap_mm;
  if (out.mesh.Volume() < 0) out.mesh.FlipOrientation();
  for (int s = 0; s < 6; ++s) {
    const int k = static_cast<int>(std::lround(out.site_angle[s] / (2 * kPi) * n)) % n;
    const double th = out.site_angle[s];
    const double r = r_in_at[k] - 0.5 * p.gap_mm;
    out.margin[s] = Vector3(r * std::cos(th), r * std::sin(th), z_m_at[k]);
    out.floor[s] = Vector3(r * std::cos(th), r * std::sin(th), z_f_at[k]);
  }
  return out;
}

}  // namespace sulcus
