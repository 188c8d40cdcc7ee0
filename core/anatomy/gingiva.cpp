#include "core/anatomy/gingiva.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/geometry/isosurface.h"
#include "core/geometry/simplify.h"

namespace sulcus {
namespace {

constexpr double kPi = std::numbers::pi;

// The eight knots around the tooth by angle: the mesial interproximal point
// (0), MB, B, DB, the distal one (pi), DL, L, ML, with 2 pi closing the ring.
struct Knots {
  std::array<double, 9> angle;
  int i = 0;       // the knot before th
  double t = 0;    // how far th is from it toward the next, 0 to 1
  double gap = 0;  // the angle between the two
  Knots(const std::array<double, 6>& line, double th)
      : angle{0, line[0], line[1], line[2], kPi, line[5], line[4], line[3], 2 * kPi} {
    double a = std::fmod(th, 2 * kPi);
    if (a < 0) a += 2 * kPi;
    while (i < 7 && a >= angle[static_cast<std::size_t>(i + 1)]) ++i;
    gap = angle[static_cast<std::size_t>(i + 1)] - angle[static_cast<std::size_t>(i)];
    t = gap > 0 ? std::clamp((a - angle[static_cast<std::size_t>(i)]) / gap, 0.0, 1.0)
                : 0.0;
  }
};

// Periodic smooth interpolation of the six site values around the tooth, with
// the mesial (0) and distal (pi) points the mean of their neighbours.
double AroundTooth(const std::array<double, 6>& site, const std::array<double, 6>& line,
                   double th) {
  const double knots[8] = {0.5 * (site[0] + site[3]), site[0], site[1], site[2],
                           0.5 * (site[2] + site[5]), site[5], site[4], site[3]};
  const Knots k(line, th);
  const double s = 0.5 - 0.5 * std::cos(kPi * k.t);
  return knots[k.i] + s * (knots[(k.i + 1) % 8] - knots[k.i]);
}

// The pocket's depth around the tooth, so that each site's value is the
// deepest of its zone (core/haptics/tip_locator.h: thirds of the facial and
// oral halves of the outline, a mid site's zone reaching about 30 degrees
// either side of its line, an interdental site's about 15 toward the mid site
// and all the way to the interproximal point): between two neighbouring knots
// (the six sites at their lines, and the mesial and distal points, each the
// shallower of its two sites) the depth stays at the shallower knot's value
// and rises to the deeper one within the deeper one's zone: with a flat top by
// the deeper site's line (which the meshes resolve), over 20 degrees to a mid
// site, over 9 to an interdental site from its mid site, and smoothly over the
// whole arc between an interdental site and the interproximal point.
double PocketAroundTooth(const std::array<double, 6>& site,
                         const std::array<double, 6>& line, double th) {
  const double knots[8] = {std::min(site[0], site[3]), site[0], site[1], site[2],
                           std::min(site[2], site[5]), site[5], site[4], site[3]};
  const Knots k(line, th);
  const int i = k.i, j = (k.i + 1) % 8;
  const double lo = knots[i], hi = knots[j];
  // Knots 0 and 4 are the interproximal points, 2 and 6 the mid sites.
  if (i % 4 == 0 || j % 4 == 0) {
    const double s = 0.5 - 0.5 * std::cos(kPi * k.t);
    return lo + s * (hi - lo);
  }
  const bool deep_is_mid = (hi >= lo ? j : i) % 4 == 2;
  double top = (deep_is_mid ? 8.0 : 5.0) * kPi / 180;
  double rise = (deep_is_mid ? 20.0 : 9.0) * kPi / 180;
  // Where the interdental line was moved toward its mid site (by `moved`),
  // the zones' bound between the two moves too (the tip locator's rule: 30
  // degrees from the mid site, or halfway between the lines once the line
  // comes within 3 degrees of that): the rise stays a degree inside the
  // deeper site's zone.
  const int inter = i % 4 == 2 ? j : i;
  const double moved = std::abs(
      k.angle[static_cast<std::size_t>(inter)] -
      kSiteAngles[static_cast<std::size_t>(inter <= 3 ? inter - 1 : 8 - inter + 2)]);
  if (moved > 1e-9) {
    const double deg = kPi / 180, halfway = 0.5 * k.gap;
    const double reach = deep_is_mid ? (moved > 12 * deg ? halfway : 30 * deg)
                                     : (moved > 12 * deg ? halfway : 15 * deg - moved);
    const double shrink = std::clamp((reach - deg) / (top + rise), 0.1, 1.0);
    top *= shrink;
    rise *= shrink;
  }
  const double from = k.t * k.gap, to = k.gap - from;
  const double left = hi >= lo ? to : from;  // from the deeper knot
  const double u = std::clamp(1.0 - (left - top) / rise, 0.0, 1.0);
  const double s = 0.5 - 0.5 * std::cos(kPi * u);
  return std::min(lo, hi) + s * std::abs(hi - lo);
}

}  // namespace

namespace {

// Where the horizontal ray o + t d crosses the triangle (a, b, c): t, or -1
// when it misses (the test OuterRadius and OuterRadii share).
double RayCrossing(const Vector3& o, const Vector3& d, const Vector3& a, const Vector3& b,
                   const Vector3& c) {
  const Vector3 e1 = b - a, e2 = c - a;
  const Vector3 p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-14) return -1;
  const Vector3 s = o - a;
  const double u = s.dot(p) / det;
  if (u < 0 || u > 1) return -1;
  const Vector3 q = s.cross(e1);
  const double w = d.dot(q) / det;
  if (w < 0 || u + w > 1) return -1;
  return e2.dot(q) / det;
}

}  // namespace

// The farthest crossing of the horizontal ray from (0, 0, z) along angle th with
// the mesh (the tooth's outer surface in that direction), or 0 when it misses.
double OuterRadius(const TriangleMesh& mesh, double th, double z) {
  const Vector3 o(0, 0, z), d(std::cos(th), std::sin(th), 0);
  double best = 0;
  const auto& v = mesh.vertices();
  for (const auto& f : mesh.faces())
    best = std::max(best, RayCrossing(o, d, v[f[0]], v[f[1]], v[f[2]]));
  return best;
}

OuterRadii::OuterRadii(const TriangleMesh& mesh) : mesh_(mesh) {
  const Aabb box = mesh.Bounds();
  if (box.empty()) return;
  // A face is listed in every band its heights reach, widened by far more than
  // rounding: a ray at a height a face does not reach cannot cross it.
  constexpr double kSlack = 1e-6;
  z0_ = box.min.z() - kSlack;
  bands_ = static_cast<int>((box.max.z() + kSlack - z0_) / kBandMm) + 1;
  const auto& v = mesh.vertices();
  auto range = [&](const TriangleMesh::Face& f) {
    const double lo = std::min({v[f[0]].z(), v[f[1]].z(), v[f[2]].z()}) - kSlack,
                 hi = std::max({v[f[0]].z(), v[f[1]].z(), v[f[2]].z()}) + kSlack;
    return std::pair(std::clamp(static_cast<int>((lo - z0_) / kBandMm), 0, bands_ - 1),
                     std::clamp(static_cast<int>((hi - z0_) / kBandMm), 0, bands_ - 1));
  };
  start_.assign(bands_ + 1, 0);
  for (const auto& f : mesh.faces()) {
    const auto [b0, b1] = range(f);
    for (int b = b0; b <= b1; ++b) ++start_[b + 1];
  }
  for (int b = 0; b < bands_; ++b) start_[b + 1] += start_[b];
  faces_.resize(start_[bands_]);
  std::vector<std::int32_t> fill(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < mesh.faces().size(); ++i) {
    const auto [b0, b1] = range(mesh.faces()[i]);
    for (int b = b0; b <= b1; ++b) faces_[fill[b]++] = static_cast<std::int32_t>(i);
  }
}

double OuterRadii::At(double th, double z) const {
  const double x = (z - z0_) / kBandMm;
  if (bands_ == 0 || !(x >= 0) || x >= bands_) return 0;
  const int b = static_cast<int>(x);
  const Vector3 o(0, 0, z), d(std::cos(th), std::sin(th), 0);
  const auto& v = mesh_.vertices();
  double best = 0;
  for (std::int32_t k = start_[b]; k < start_[b + 1]; ++k) {
    const TriangleMesh::Face& f = mesh_.faces()[faces_[k]];
    best = std::max(best, RayCrossing(o, d, v[f[0]], v[f[1]], v[f[2]]));
  }
  return best;
}

ToothRadii::ToothRadii(const TriangleMesh& mesh, double z_lo, double z_hi)
    : z0_(z_lo),
      levels_(std::max(2, static_cast<int>(std::ceil((z_hi - z_lo) / kDz)) + 1)) {
  r_.assign(static_cast<std::size_t>(levels_) * kAngles, 0.0f);
  const double step = 2 * kPi / kAngles;
  const auto& v = mesh.vertices();
  for (const auto& f : mesh.faces()) {
    const Vector3 *a = &v[f[0]], *b = &v[f[1]], *c = &v[f[2]];
    const double lo = std::min({a->z(), b->z(), c->z()}),
                 hi = std::max({a->z(), b->z(), c->z()});
    const int j0 = std::max(0, static_cast<int>(std::ceil((lo - z0_) / kDz)));
    const int j1 = std::min(levels_ - 1, static_cast<int>(std::floor((hi - z0_) / kDz)));
    for (int j = j0; j <= j1; ++j) {
      // The face's section at this height: a segment P Q.
      const double z = z0_ + j * kDz;
      Eigen::Vector2d ends[2];
      int found = 0;
      for (const auto& [p, q] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
        if ((p->z() - z) * (q->z() - z) > 0 || p->z() == q->z() || found == 2) continue;
        const double t = (z - p->z()) / (q->z() - p->z());
        ends[found++] = (*p + t * (*q - *p)).head<2>();
      }
      if (found < 2) continue;
      const Eigen::Vector2d P = ends[0], E = ends[1] - ends[0];
      const double t0 = std::atan2(P.y(), P.x());
      double sweep = std::atan2(ends[1].y(), ends[1].x()) - t0;
      if (sweep > kPi) sweep -= 2 * kPi;
      if (sweep < -kPi) sweep += 2 * kPi;
      const int k0 = static_cast<int>(std::ceil(std::min(t0, t0 + sweep) / step));
      const int k1 = static_cast<int>(std::floor(std::max(t0, t0 + sweep) / step));
      for (int k = k0; k <= k1; ++k) {
        // The ray t u from the axis meets P + s E where t (u x E) = P x E.
        const Eigen::Vector2d u(std::cos(k * step), std::sin(k * step));
        const double den = u.x() * E.y() - u.y() * E.x();
        if (std::abs(den) < 1e-12) continue;
        const double t = (P.x() * E.y() - P.y() * E.x()) / den;
        if (t <= 0) continue;
        float& r = r_[static_cast<std::size_t>(j) * kAngles +
                      ((k % kAngles) + kAngles) % kAngles];
        r = std::max(r, static_cast<float>(t));
      }
    }
  }
  // Where a ray misses (between a molar's roots, below the furcation's roof),
  // the radius runs straight from the last root it met to the next one
  // around, as tissue spans the furcation's entrance.
  for (int j = 0; j < levels_; ++j) {
    float* level = &r_[static_cast<std::size_t>(j) * kAngles];
    int first = -1;
    for (int k = 0; k < kAngles && first < 0; ++k)
      if (level[k] > 0) first = k;
    if (first < 0) continue;  // (above the crown or below the apices)
    for (int k = first, steps = 0; steps < kAngles; ++steps) {
      int next = (k + 1) % kAngles, gap = 1;
      while (level[next] <= 0) next = (next + 1) % kAngles, ++gap;
      for (int m = 1; m < gap; ++m)
        level[(k + m) % kAngles] = level[k] + (level[next] - level[k]) *
                                                  static_cast<float>(m) /
                                                  static_cast<float>(gap);
      steps += gap - 1;
      k = next;
    }
  }
}

double ToothRadii::At(double th, double z) const {
  const double y = (z - z0_) / kDz;
  if (!(y >= 0) || y > levels_ - 1) return 0;
  double x = th / (2 * kPi / kAngles);
  x -= kAngles * std::floor(x / kAngles);
  const int i = std::min(static_cast<int>(x), kAngles - 1),
            j = std::min(static_cast<int>(y), levels_ - 2);
  const double s = x - i, t = y - j;
  const int i2 = (i + 1) % kAngles;
  const auto at = [this](int level, int angle) {
    return static_cast<double>(r_[static_cast<std::size_t>(level) * kAngles + angle]);
  };
  const double r00 = at(j, i), r10 = at(j, i2), r01 = at(j + 1, i), r11 = at(j + 1, i2);
  if (r00 <= 0 || r10 <= 0 || r01 <= 0 || r11 <= 0) return 0;
  return (1 - t) * ((1 - s) * r00 + s * r10) + t * ((1 - s) * r01 + s * r11);
}

int GingivaModel::SegmentAt(double th) const {
  const int n = static_cast<int>(floor_z.size());
  if (n == 0) return 0;
  double a = std::fmod(th, 2 * kPi);
  if (a < 0) a += 2 * kPi;
  return static_cast<int>(std::lround(a / (2 * kPi) * n)) % n;
}

double GingivaModel::FloorAt(double th) const {
  return floor_z.empty() ? 0 : floor_z[SegmentAt(th)];
}

double GingivaThicknessMm(const FdiTooth& tooth) {
  return tooth.position <= 2 ? 1.0 : tooth.position == 3 ? 1.2 : 1.5;
}

const std::array<double, 6>& SiteAngles() { return kSiteAngles; }

GingivaModel GenerateGingiva(const ToothModel& tooth, const GingivaParams& p) {
  if (p.segments < 8 || p.segments % 8 != 0)
    throw std::invalid_argument("gingiva segments must be a multiple of 8, at least 8");
  if (!(p.crest_drop_mm >= 0) || !(p.crest_up.z() > 0.5) ||
      std::abs(p.crest_up.norm() - 1) > 1e-6)
    throw std::invalid_argument(
        "the gingiva's bone crest needs a drop of at least 0 and a unit 'up' within 60 "
        "degrees of the tooth's axis");
  if (!(p.gap_mm >= 0.55))
    throw std::invalid_argument(
        "the sulcus must be at least 0.55 mm wide for a 0.5 mm probe tip");
  {
    const auto& a = p.site_angle;
    if (!(0 < a[0] && a[0] < a[1] && a[1] < a[2] && a[2] < kPi && kPi < a[5] &&
          a[5] < a[4] && a[4] < a[3] && a[3] < 2 * kPi))
      throw std::invalid_argument(
          "the gingiva's site lines must go round the tooth in order (MB, B, DB from the "
          "mesial point to the distal one, DL, L, ML back), each within its half");
  }
  if (!(p.thickness_mm >= 0))
    throw std::invalid_argument(
        "the gingiva's thickness must be positive (0: the tooth's own)");
  for (int i = 0; i < 6; ++i) {
    if (p.pocket_mm[i] < 0 ||
        p.pocket_mm[i] + p.recession_mm[i] > MaxAttachmentLoss(tooth.dimensions))
      throw std::invalid_argument("pocket of " + std::to_string(p.pocket_mm[i]) +
                                  " mm at site " + std::to_string(i) +
                                  " does not fit the root of tooth " +
                                  std::to_string(tooth.tooth.fdi));
  }
  const int n = p.segments;
  const int wall_levels = 8;
  // Cross-section by angle: A margin, wall down to B, floor to C, D, E, F, G (top).
  std::vector<std::array<Vector3, 7 + wall_levels>> rings(
      n);  // (r, z) points as Vector3(r, z, 0)
  GingivaModel out;
  out.site_angle = p.site_angle;
  std::vector<double> r_in_at(n), z_m_at(n), z_f_at(n), r_floor_at(n), r_out_at(n);
  const OuterRadii radii(tooth.mesh);
  for (int k = 0; k < n; ++k) {
    const double th = 2 * kPi * k / n;
    // The CEJ height at this angle (the tooth's CEJ curve has 72 points, evenly spaced).
    const double cej_z =
        tooth.cej[static_cast<std::size_t>(std::lround(72.0 * k / n)) % tooth.cej.size()]
            .z();
    const double c2 = std::cos(th) * std::cos(th);
    const double papilla = p.papilla_mm * c2 * c2;
    const double z_m = cej_z + p.margin_above_cej_mm -
                       AroundTooth(p.recession_mm, p.site_angle, th) + papilla;
    const double z_f = z_m - PocketAroundTooth(p.pocket_mm, p.site_angle, th);
    double widest = 0;
    for (int j = 0; j <= 12; ++j)
      widest = std::max(widest, radii.At(th, z_f + (z_m - z_f) * j / 12.0));
    const double r_in = widest + p.gap_mm;
    const double thickness =
        (p.thickness_mm > 0 ? p.thickness_mm : GingivaThicknessMm(tooth.tooth)) *
        (0.35 + 0.65 * std::sin(th) * std::sin(th));
    const double r_out = r_in + thickness;
    const double r_floor = std::max(0.3, radii.At(th, z_f) - 0.3);
    auto& ring = rings[k];
    int i = 0;
    for (int j = 0; j < wall_levels; ++j)
      ring[i++] = Vector3(r_in, z_m + (z_f - z_m) * j / wall_levels, 0);  // A ..
    ring[i++] = Vector3(r_in, z_f, 0);                                    // B
    ring[i++] = Vector3(r_floor, z_f, 0);                                 // C
    ring[i++] = Vector3(r_floor, z_f - 1.0, 0);                           // D
    ring[i++] = Vector3(r_out, z_f - 1.0, 0);                             // E
    ring[i++] = Vector3(r_out, z_m - 0.8, 0);                             // F
    ring[i++] = Vector3(r_in + 0.75 * thickness, z_m - 0.25, 0);          // G
    ring[i++] = Vector3(r_in + 0.35 * thickness, z_m - 0.03, 0);          // rounded top
    r_in_at[k] = r_in;
    r_floor_at[k] = r_floor;
    r_out_at[k] = r_out;
    z_m_at[k] = z_m;
    z_f_at[k] = z_f;
  }
  const int m = 7 + wall_levels;
  std::vector<Vector3> vertices;
  vertices.reserve(static_cast<std::size_t>(n) * m);
  for (int k = 0; k < n; ++k) {
    const double th = 2 * kPi * k / n;
    for (const Vector3& rz : rings[k])
      vertices.emplace_back(rz.x() * std::cos(th), rz.x() * std::sin(th), rz.y());
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
  out.wall_r = r_in_at;
  out.floor_r = r_floor_at;
  out.outer_r = r_out_at;
  out.crest_drop_mm = p.crest_drop_mm;
  out.crest_up = p.crest_up;
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

std::array<double, 6> LineAnglesClearOfCuts(const ToothModel& tooth,
                                            const GingivaParams& params,
                                            const std::vector<ClipPlane>& cuts) {
  GingivaParams p = params;
  if (cuts.empty()) return p.site_angle;
  // (each pass moves a line only further toward its mid site: a few passes
  // settle it, the collar changing little as its pocket's knot moves)
  for (int pass = 0; pass < 4; ++pass) {
    const GingivaModel g = GenerateGingiva(tooth, p);
    auto clear = [&](double phi) {
      const auto k = static_cast<std::size_t>(g.SegmentAt(phi));
      const double r = g.sulcus_r[k];
      const Vector3 at(r * std::cos(phi), r * std::sin(phi),
                       0.5 * (g.margin_z[k] + g.floor_z[k]));
      for (const ClipPlane& c : cuts)
        if ((at - c.q).dot(c.normal) > -kLineClearOfCutMm) return false;
      return true;
    };
    bool moved = false;
    for (const int s : {0, 2, 3, 5}) {
      const double mid = s < 3 ? kPi / 2 : 3 * kPi / 2;
      double& phi = p.site_angle[static_cast<std::size_t>(s)];
      const double dir = mid > phi ? 1.0 : -1.0, from = kSiteAngles[s];
      while (!clear(phi) && std::abs(phi + dir * kPi / 360 - from) <= kPi / 6 + 1e-9) {
        phi += dir * kPi / 360;
        moved = true;
      }
    }
    if (!moved) break;
  }
  return p.site_angle;
}

namespace {

// The rim on each plane is where the sampling cut it; both neighbours' rims
// are brought onto the field's zero set in the plane (where the two fields
// agree), so that neither share's cap shows past the other's surface as a
// dark hairline. Each rim vertex moves within its plane, at most a tenth of a
// cell per Newton step; a move that would flip a face or flatten it to a
// sliver (a cap triangle between three rim vertices) is taken back.
TriangleMesh RimsOntoField(const TriangleMesh& mesh, const GingivaShareField& field,
                           const std::vector<ClipPlane>& planes, double cell_mm) {
  const std::vector<Vector3>& before = mesh.vertices();
  std::vector<Vector3> vertices = before;
  for (Vector3& v : vertices) {
    const ClipPlane* on = nullptr;
    int count = 0;
    for (const ClipPlane& c : planes)
      if (std::abs((v - c.q).dot(c.normal)) < 1e-9) on = &c, ++count;
    if (count != 1) continue;  // (on no plane, or where two planes meet)
    for (int it = 0; it < 4; ++it) {
      constexpr double h = 1e-3;
      const double f = field.Uncut(v);
      Vector3 g;
      for (int a = 0; a < 3; ++a) g[a] = (field.Uncut(v + h * Vector3::Unit(a)) - f) / h;
      g -= g.dot(on->normal) * on->normal;
      if (g.squaredNorm() < 1e-12) break;
      Vector3 step = -f * g / g.squaredNorm();
      if (step.norm() > 0.1 * cell_mm) step *= 0.1 * cell_mm / step.norm();
      v += step;
      if (std::abs(f) < 1e-5) break;  // (this step was the last, a tiny one)
    }
    v -= (v - on->q).dot(on->normal) * on->normal;  // (exactly on it again)
  }
  for (bool undone = true; undone;) {
    undone = false;
    for (const TriangleMesh::Face& f : mesh.faces()) {
      if (vertices[f[0]] == before[f[0]] && vertices[f[1]] == before[f[1]] &&
          vertices[f[2]] == before[f[2]])
        continue;
      const Vector3 n0 = (before[f[1]] - before[f[0]]).cross(before[f[2]] - before[f[0]]);
      const Vector3 n1 =
          (vertices[f[1]] - vertices[f[0]]).cross(vertices[f[2]] - vertices[f[0]]);
      if (n1.dot(n0) > 0.25 * n0.squaredNorm() && n1.norm() > 1e-6) continue;
      for (int k = 0; k < 3; ++k) vertices[f[k]] = before[f[k]];
      undone = true;
    }
  }
  return TriangleMesh(std::move(vertices), mesh.faces());
}

// Per vertex, the unit gradient of the share's uncut field (central
// differences), zero where it is not finite or vanishes.
std::vector<Vector3> FieldNormals(const TriangleMesh& mesh,
                                  const GingivaShareField& field) {
  constexpr double h = 0.01;  // mm
  std::vector<Vector3> normals;
  normals.reserve(mesh.num_vertices());
  for (const Vector3& v : mesh.vertices()) {
    Vector3 g;
    for (int a = 0; a < 3; ++a)
      g[a] =
          field.Uncut(v + h * Vector3::Unit(a)) - field.Uncut(v - h * Vector3::Unit(a));
    const double norm = g.norm();
    normals.push_back(std::isfinite(norm) && norm > 1e-9 ? Vector3(g / norm)
                                                         : Vector3::Zero());
  }
  return normals;
}

}  // namespace

GingivaModel GenerateGingiva(const ToothModel& tooth, const GingivaParams& params,
                             const std::vector<GingivaNeighbour>& neighbours,
                             double cell_mm, GingivaSurface surface) {
  GingivaModel out = GenerateGingiva(tooth, params);
  if (neighbours.empty()) return out;
  const GingivaShareField field(tooth, out, neighbours, surface);
  // Sampled whole and cut exactly at the planes toward the neighbours: the
  // neighbours' shares, each sampled on its own grid, meet on the plane in the
  // same rim (up to the sampling's error) and without a saw-tooth.
  const std::vector<ClipPlane> planes = field.cuts();
  // (sampled only to two cells past the cut: what lies beyond is cut away,
  // and sampling it would only cost time)
  const auto near_side = [&field, cell_mm](const Vector3& p) {
    return std::max(field.Uncut(p), field.Cut(p) - 2 * cell_mm);
  };
  // The felt surface keeps OpenMesh's decimation: its meshes, and with them its
  // sphere-trees and every reading measured on them (the lessons' figures, the
  // recorded attempts replayed in the tests), stay as they were. The seen one,
  // only drawn, takes Sulcus's own, about twice as fast again.
  const TriangleMesh iso = Isosurface(near_side, field.box(), cell_mm);
  TriangleMesh mesh = RimsOntoField(
      ClipByPlanes(surface == GingivaSurface::kSeen ? Simplify(iso, 0.02)
                                                    : SimplifyWithOpenMesh(iso, 0.02),
                   planes),
      field, planes, cell_mm);
  if (mesh.num_faces() == 0)
    throw std::invalid_argument("the gingiva of tooth " +
                                std::to_string(tooth.tooth.fdi) + " is empty");
  out.normals = FieldNormals(mesh, field);
  out.caps.assign(mesh.num_faces(), 0);
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const TriangleMesh::Face& face = mesh.faces()[f];
    for (const ClipPlane& c : planes) {
      const auto on = [&](int k) {
        return std::abs((mesh.vertices()[face[k]] - c.q).dot(c.normal)) < 1e-9;
      };
      if (on(0) && on(1) && on(2)) out.caps[f] = 1;
    }
  }
  out.mesh = std::move(mesh);
  return out;
}

}  // namespace sulcus
