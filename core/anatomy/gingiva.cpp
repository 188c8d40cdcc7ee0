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

const std::array<double, 6>& SiteAngles() {
  static const std::array<double, 6> a = {kPi / 4,     kPi / 2,     3 * kPi / 4,
                                          7 * kPi / 4, 3 * kPi / 2, 5 * kPi / 4};
  return a;
}

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
  out.site_angle = SiteAngles();
  std::vector<double> r_in_at(n), z_m_at(n), z_f_at(n), r_floor_at(n), r_out_at(n);
  for (int k = 0; k < n; ++k) {
    const double th = 2 * kPi * k / n;
    // The CEJ height at this angle (the tooth's CEJ curve has 72 points, evenly spaced).
    const double cej_z =
        tooth.cej[static_cast<std::size_t>(std::lround(72.0 * k / n)) % tooth.cej.size()]
            .z();
    const double c2 = std::cos(th) * std::cos(th);
    const double papilla = p.papilla_mm * c2 * c2;
    const double z_m =
        cej_z + p.margin_above_cej_mm - AroundTooth(p.recession_mm, th) + papilla;
    const double z_f = z_m - AroundTooth(p.pocket_mm, th);
    double widest = 0;
    for (int j = 0; j <= 12; ++j)
      widest =
          std::max(widest, OuterRadius(tooth.mesh, th, z_f + (z_m - z_f) * j / 12.0));
    const double r_in = widest + p.gap_mm;
    const double thickness =
        (p.thickness_mm > 0 ? p.thickness_mm : GingivaThicknessMm(tooth.tooth)) *
        (0.35 + 0.65 * std::sin(th) * std::sin(th));
    const double r_out = r_in + thickness;
    const double r_floor = std::max(0.3, OuterRadius(tooth.mesh, th, z_f) - 0.3);
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

namespace {

// A table around the tooth (one value per segment, from +x) at angle th,
// linearly interpolated.
double Around(const std::vector<double>& table, double th) {
  const int n = static_cast<int>(table.size());
  double x = th / (2 * kPi) * n;
  x -= n * std::floor(x / n);
  const int i = static_cast<int>(x) % n;
  const double t = x - std::floor(x);
  return table[i] + t * (table[(i + 1) % n] - table[i]);
}

constexpr double kIntoBoneMm =
    1.0;  // how far a share reaches past the crest, into the jaw
constexpr double kPapillaTip = 0.6;  // the papilla's ridge rounded over this (mm)
constexpr double kPapillaSlope =
    0.8;  // its least fall from the ridge toward each tooth (mm per mm)
constexpr double kPapillaSteepest = 2.0;  // its steepest (mm per mm)
constexpr double kBelowSiteMarginMm =
    0.15;  // how far below a line-angle site's margin the papilla's top passes
constexpr double kPastCutFall =
    2.0;  // how fast a collar's top falls past its cut (mm per mm)
constexpr double kFaceInsetMm =
    0.5;  // the interdental band's faces inside the collars' outer extents
constexpr double kPapillaRoll =
    1.5;  // its top's fall outward past the line between the sulci's walls (mm per mm)

// How far a share's outer wall has drawn in at height z below the crest: 2 mm
// per mm, so that the share ends inside the jaw (whose top, soft_tissue.cpp,
// stays inside the gingiva).
double DrawnIn(double crest, double z) { return 2.0 * std::max(0.0, crest - z); }

// The bone crest's height (tooth frame z) above (x, y).
double CrestZ(const GingivaModel& g, double x, double y) {
  const Vector3& u = g.crest_up;
  return (-g.crest_drop_mm - u.x() * x - u.y() * y) / u.z();
}

// max(0, x) with its corner rounded over [0, r] (a parabola there; 0 below
// it, r / 2 below x above it): bends rounded without moving what lies before them.
double SmoothRamp(double x, double r) {
  return x <= 0 ? 0.0 : x < r ? x * x / (2 * r) : x - 0.5 * r;
}

// |x| with its corner rounded over [-r, r] the same way.
double SmoothAbs(double x, double r) { return SmoothRamp(std::abs(x), r); }

// One tooth's collar as fields, at a point in that tooth's frame.
struct CollarAt {
  // In the sulcus or above it: inside > 0 and above > 0; in the root below the
  // floor: root > 0.
  double inside, above, root;
  double band;    // < 0 within the collar's outer wall, above its base
  double top;     // the gingiva's top: the margin at the wall, falling outward
  double bottom;  // its base, rising beyond the outer wall
};

// How far the seen gingiva's outer face lies inside the felt one's at angle th
// and height z: the free gingiva thin at its margin (kSeenEdgeMm outside the
// tooth there), thickening downward and meeting the felt face at the bone
// crest (where the jaw's mucosa takes over from it; a collar without a crest:
// 1 mm below the floor), a smoothstep between. 0 where the tooth is not in
// the table.
constexpr double kSeenEdgeMm = 0.45;
// The seen interdental band's faces lie this much further in than the
// collars' (mm): the papilla between two teeth is a shallow groove in the
// gingiva over the roots, not a plate across the embrasure.
constexpr double kSeenGrooveMm = 0.4;
double SeenInset(const GingivaModel& g, const ToothRadii& seen, double th, double z) {
  const double r_out = Around(g.outer_r, th), z_m = Around(g.margin_z, th);
  const double tooth_m = seen.At(th, z_m);
  if (tooth_m <= 0) return 0;
  const double at_margin = std::max(0.0, r_out - tooth_m - kSeenEdgeMm);
  const double z_end = g.crest_drop_mm > 0
                           ? CrestZ(g, r_out * std::cos(th), r_out * std::sin(th))
                           : Around(g.floor_z, th) - 1.0;
  const double t = std::clamp((z_m - z) / std::max(0.5, z_m - z_end), 0.0, 1.0);
  return at_margin * (1 - t * t * (3 - 2 * t));
}

// `seen`: the tooth's surface, for the seen gingiva (GingivaSurface), whose
// sulcus closes onto the tooth (kSeenWallMm) and whose free gingiva thins to
// its margin (SeenInset); null for the felt one.
CollarAt Collar(const GingivaModel& g, const Vector3& q,
                const ToothRadii* seen = nullptr) {
  const double r = std::hypot(q.x(), q.y());
  const double th = std::atan2(q.y(), q.x());
  const double z_f = Around(g.floor_z, th), z_m = Around(g.margin_z, th);
  const double r_floor = Around(g.floor_r, th);
  double wall = Around(g.wall_r, th), r_out = Around(g.outer_r, th), r_out_here = r_out;
  CollarAt c;
  c.inside = wall - r;
  c.root = r_floor - r;
  if (seen) {
    // (below the floor too the seen gingiva holds the root as closely, the
    // tissue attached to it; across a furcation's entrance from root to root)
    const double tooth_r = seen->At(th, q.z());
    if (tooth_r > 0) {
      c.inside = std::min(wall, tooth_r + kSeenWallMm) - r;
      c.root = tooth_r + kSeenWallMm - r;
    }
    // (the margin's top from the tooth at the margin out to the thin edge)
    const double edge_r = seen->At(th, z_m);
    if (edge_r > 0) wall = std::min(wall, edge_r + kSeenWallMm);
    r_out_here = r_out - SeenInset(g, *seen, th, q.z());
    r_out -= SeenInset(g, *seen, th, z_m);
  }
  c.above = q.z() - z_f;
  double base = z_f - 1.0, outer = r_out_here;
  if (g.crest_drop_mm > 0) {
    // Down over the alveolar process to the crest and into the jaw, the outer
    // wall drawing in below the crest.
    const double z_crest = CrestZ(g, q.x(), q.y());
    base = std::min(base, z_crest - kIntoBoneMm);
    outer -= DrawnIn(z_crest, q.z());
  }
  c.band = std::max(r - outer, base - q.z());
  // (beyond the outer wall it falls away, so that a collar two teeth away
  // never shapes the gingiva between these two)
  // The free gingiva thins toward its margin: its top falls gently from the
  // margin for a few tenths of a millimetre, then rolls over into the outer
  // face (from a millimetre inside it), so the margin is a rounded edge close
  // to the tooth and not a ledge (the bends rounded).
  // (The seen gingiva's margin is its thin edge: the top falls gently past
  // it, less steeply than the outer face leans out below it, so that the face
  // and not the top's fall shapes the free gingiva.)
  const double lip = std::max(wall + 0.6, r_out - 1.0);
  c.top = seen ? z_m - 0.4 * SmoothRamp(r - wall, 0.5) - 1.0 * SmoothRamp(r - r_out, 0.6)
               : z_m - 0.4 * SmoothRamp(r - wall, 0.5) - 1.5 * SmoothRamp(r - lip, 0.8) -
                     2.0 * SmoothRamp(r - r_out, 1.0);
  c.bottom = base + 2.0 * std::max(0.0, r - Around(g.outer_r, th));
  return c;
}

// The tooth's widest point along the horizontal direction th, over its crown:
// where it meets the neighbour that lies that way.
Vector3 ContactPoint(const ToothModel& tooth, double th) {
  double best = 0, at = 0;
  for (int j = 0; j <= 24; ++j) {
    const double z = tooth.dimensions.crown_height * j / 24.0,
                 r = OuterRadius(tooth.mesh, th, z);
    if (r > best) best = r, at = z;
  }
  return Vector3(best * std::cos(th), best * std::sin(th), at);
}

// max(a, b) with the crease rounded over k (a polynomial smooth maximum): the
// gingiva's edges are rounded, and the grid does not alias a sharp one.
double SmoothMax(double a, double b, double k) {
  const double h = std::max(0.0, 1.0 - std::abs(a - b) / k);
  return std::max(a, b) + 0.25 * k * h * h;
}

// The union of up to kMaxTerms fields with its creases filleted over k: the
// smooth minimum folded in ascending order, so that two shares holding the
// same terms near their cut (and others far above these) compute the same
// value whatever order their links come in.
constexpr int kMaxTerms = 8;
struct Union {
  std::array<double, kMaxTerms> v{};
  int n = 0;
  void Add(double x) {
    v[n++] = x;
  }  // (the constructor allows at most 3 neighbours: 7 terms)
  double Smooth(double k) {
    std::sort(v.begin(), v.begin() + n);
    double m = v[0];
    for (int i = 1; i < n; ++i) m = -SmoothMax(-m, -v[i], k);
    return m;
  }
};

}  // namespace

GingivaShareField::GingivaShareField(const ToothModel& tooth, const GingivaModel& own,
                                     const std::vector<GingivaNeighbour>& neighbours,
                                     GingivaSurface surface)
    : own_(&own) {
  if (neighbours.size() > 3)
    throw std::invalid_argument("a gingiva share has at most 3 neighbours");
  if (surface == GingivaSurface::kSeen) {
    // Each tooth's surface over the heights its collar spans (and a little more).
    const auto radii = [](const ToothModel& t, const GingivaModel& g) {
      const double lo = *std::min_element(g.floor_z.begin(), g.floor_z.end()) - 4.0;
      const double hi = *std::max_element(g.margin_z.begin(), g.margin_z.end()) + 1.0;
      return ToothRadii(t.mesh, lo, hi);
    };
    radii_.reserve(neighbours.size() + 1);  // (no reallocation: the links point into it)
    radii_.push_back(radii(tooth, own));
    for (const GingivaNeighbour& n : neighbours)
      if (n.tooth && n.gingiva && !n.gingiva->floor_z.empty())
        radii_.push_back(radii(*n.tooth, *n.gingiva));
    seen_ = &radii_[0];
  }
  double reach = 0;
  for (const double r : own.outer_r) reach = std::max(reach, r);
  for (const GingivaNeighbour& n : neighbours) {
    if (!n.tooth || !n.gingiva || n.gingiva->outer_r.empty())
      throw std::invalid_argument("gingiva neighbour without its tooth or collar model");
    const Matrix3 At =
        n.A.transpose();            // the neighbour's frame to this one (A is orthogonal)
    const Vector3 c = -(At * n.b);  // its axis' origin here
    Link l{};
    l.n = &n;
    l.e = Eigen::Vector2d(c.x(), c.y());
    l.L = l.e.norm();
    if (l.L < 1e-6)
      throw std::invalid_argument("gingiva neighbour on the tooth's own axis");
    l.e /= l.L;
    const double th_e = std::atan2(l.e.y(), l.e.x());
    // Toward this tooth, horizontal in the neighbour's frame (this origin is at b there).
    const double th_back = std::atan2(n.b.y(), n.b.x());
    // The plane halfway between the two contact points, its normal halfway
    // between the two horizontal directions: both shares compute the same one.
    const Vector3 p_i = ContactPoint(tooth, th_e);
    const Vector3 p_j = At * (ContactPoint(*n.tooth, th_back) - n.b);
    l.q = 0.5 * (p_i + p_j);
    const Vector3 e_j = At * Vector3(std::cos(th_back), std::sin(th_back), 0);
    l.normal = (Vector3(l.e.x(), l.e.y(), 0) - e_j).normalized();
    // The interdental band's buccal and lingual faces: vertical planes (the
    // two axes' mean vertical) through each tooth's outer extent square to the
    // line between them, each point taken in its own tooth's frame.
    l.up = (Vector3::UnitZ() + At * Vector3::UnitZ()).normalized();
    const Vector3& up = l.up;
    for (int side = 0; side < 2; ++side) {
      const double sign = side == 0 ? 1.0 : -1.0;
      const double th_i = th_e + sign * kPi / 2;
      const Vector3 b_i =
          Around(own.outer_r, th_i) * Vector3(std::cos(th_i), std::sin(th_i), 0);
      // The same side seen from the neighbour: this side's direction in its
      // frame (its angle toward this tooth turned the other way, unless the
      // arch's mirror lies between the two frames, as it does between the
      // central incisors, where it is turned the same way).
      const Vector3 d_j = n.A * Vector3(std::cos(th_i), std::sin(th_i), 0);
      const double th_j = std::atan2(d_j.y(), d_j.x());
      const Vector3 b_j = At * (Around(n.gingiva->outer_r, th_j) *
                                    Vector3(std::cos(th_j), std::sin(th_j), 0) -
                                n.b);
      Vector3 normal = (b_j - b_i).cross(up).normalized();
      if (normal.dot(b_i) < 0) normal = -normal;  // outward, away from the axes
      // (set in a little from the two collars' outer extents: the gingiva
      // bulges over each root and dips between them, the fillet making the
      // dip a shallow groove)
      l.face_point[side] = b_i - kFaceInsetMm * normal;
      l.face_normal[side] = normal;
      l.face_th[side][0] = th_i;
      l.face_th[side][1] = th_j;
      // (and the same face moved in to the line between the two sulci's
      // walls on that side)
      const Vector3 w_i =
          Around(own.wall_r, th_i) * Vector3(std::cos(th_i), std::sin(th_i), 0);
      const Vector3 w_j = At * (Around(n.gingiva->wall_r, th_j) *
                                    Vector3(std::cos(th_j), std::sin(th_j), 0) -
                                n.b);
      l.wall_point[side] =
          b_i + std::max((w_i - b_i).dot(normal), (w_j - b_i).dot(normal)) * normal;
    }
    l.across_dir = l.normal.cross(up).normalized();
    for (int side = 0; side < 2; ++side)
      l.own_site_gap[side] = l.other_site_gap[side] = 1e9;
    for (int s = 0; s < 6; ++s) {
      const Vector3 mine = own.floor[s] - l.q,
                    theirs = At * (n.gingiva->floor[s] - n.b) - l.q;
      const int side_mine = mine.dot(l.across_dir) >= 0 ? 0 : 1,
                side_theirs = theirs.dot(l.across_dir) >= 0 ? 0 : 1;
      l.own_site_gap[side_mine] =
          std::min(l.own_site_gap[side_mine], std::max(0.0, -mine.dot(l.normal)));
      l.other_site_gap[side_theirs] =
          std::min(l.other_site_gap[side_theirs], std::max(0.0, theirs.dot(l.normal)));
    }
    // The two margins where they face each other (each raised into the
    // papilla), in this frame.
    const double r_j = Around(n.gingiva->wall_r, th_back);
    const Vector3 m_j = At * (Vector3(r_j * std::cos(th_back), r_j * std::sin(th_back),
                                      Around(n.gingiva->margin_z, th_back)) -
                              n.b);
    const double r_i = Around(own.wall_r, th_e);
    const Vector3 dir_e(std::cos(th_e), std::sin(th_e), 0);
    l.papilla = 0.5 * (r_i * dir_e + Vector3(0, 0, Around(own.margin_z, th_e)) + m_j);
    // The papilla's slopes down to each tooth: steep enough that its top
    // passes just below the margin at that tooth's line-angle sites facing
    // the cut, beside the probe there, unless a site lies under the contact
    // (within kUnderContactMm of the cut), where the margin beside it is
    // the papilla's; and never steeper than kPapillaSteepest, so that a
    // papilla stays a papilla.
    l.slope[0] = l.slope[1] = kPapillaSlope;
    for (int s = 0; s < 6; ++s) {
      const Vector3 points[2] = {own.margin[s], At * (n.gingiva->margin[s] - n.b)};
      for (int t = 0; t < 2; ++t) {
        const double a =
            (points[t] - l.q).dot(l.normal);  // negative on this tooth's side
        if ((t == 0) != (a < 0) || std::abs(a) < kUnderContactMm) continue;
        const double h = (points[t] - l.papilla).dot(l.up);
        l.slope[t] = std::clamp((kBelowSiteMarginMm - h) / SmoothAbs(a, kPapillaTip),
                                l.slope[t], kPapillaSteepest);
      }
    }
    const Vector3 f_j = At * (Vector3(r_j * std::cos(th_back), r_j * std::sin(th_back),
                                      Around(n.gingiva->floor_z, th_back)) -
                              n.b);
    l.base = 0.5 * (r_i * dir_e + Vector3(0, 0, Around(own.floor_z, th_e)) + f_j) - l.up;
    l.crest_own = l.crest_other = -std::numeric_limits<double>::infinity();
    if (own.crest_drop_mm > 0 && n.gingiva->crest_drop_mm > 0) {
      // Down to the crest between the two as well (each tooth's crest in its
      // own frame, the mean of the two points).
      const Vector3 c_i =
          r_i * dir_e +
          Vector3(0, 0, CrestZ(own, r_i * std::cos(th_e), r_i * std::sin(th_e)));
      const Vector3 at_j(r_j * std::cos(th_back), r_j * std::sin(th_back), 0);
      const Vector3 c_j =
          At *
          (Vector3(at_j.x(), at_j.y(), CrestZ(*n.gingiva, at_j.x(), at_j.y())) - n.b);
      const Vector3 crest_base = 0.5 * (c_i + c_j) - kIntoBoneMm * l.up;
      // (heights for the draw-in along the world's vertical, as the crest and
      // the jaw are level: along the teeth's axes, tipped as lower molars and
      // incisors are, one face would draw in a millimetre or more too low)
      l.crest_own = c_i.dot(own.crest_up);
      l.crest_other = c_j.dot(own.crest_up);
      if (crest_base.dot(l.up) < l.base.dot(l.up)) l.base = crest_base;
    }
    const double d = l.q.head<2>().dot(l.e);
    for (const Vector3& b : l.face_point)
      reach = std::max(reach, std::hypot(d, b.head<2>().norm()) + 0.5);
    reach = std::max(reach, d + 0.5);
    if (seen_) l.seen = &radii_[links_.size() + 1];
    links_.push_back(l);
  }
  double z_lo = 1e9, z_hi = -1e9;
  for (std::size_t k = 0; k < own.floor_z.size(); ++k) {
    z_lo = std::min(z_lo, own.floor_z[k] - 1.0);
    z_hi = std::max(z_hi, own.margin_z[k]);
  }
  if (own.crest_drop_mm > 0)
    z_lo = std::min(z_lo, (-own.crest_drop_mm - own.crest_up.head<2>().norm() * reach) /
                                  own.crest_up.z() -
                              kIntoBoneMm);
  box_.Extend(Vector3(-reach, -reach, z_lo - 2.0));
  box_.Extend(Vector3(reach, reach, z_hi + 2.0));
}

double GingivaShareField::Uncut(const Vector3& p) const {
  constexpr double kRound = 0.35;  // edges rounded over this (mm), about a grid cell
  // Where two pieces of the gingiva meet (a collar and the band between two
  // teeth, the papilla and the margin over a tooth) the crease is filleted
  // over these, as tissue is: the margin runs in a scallop from papilla to
  // papilla, and the attached gingiva has no edges.
  constexpr double kFilletSides = 0.8, kFilletTop = 1.0;
  // How far past the cut a tooth's sulcus still opens the gingiva: the two
  // sulci meet under the contact, but neither hollows out the other tooth's
  // side of it (at a line angle beside a contact the neighbour's exaggerated
  // sulcus would otherwise take the gingiva from under the margin).
  constexpr double kSulcusPastCut = 0.3;
  // Each collar's heights are in its own tooth's frame, so each is compared
  // with the point there: above = how far above the highest top, below = how
  // far below the lowest base.
  const CollarAt own = Collar(*own_, p, seen_);
  Union band, above, below;
  band.Add(own.band);
  double own_top_past_cuts =
      0;  // (each collar's top falls away past the cut: see the loop)
  below.Add(own.bottom - p.z());
  // Under a contact the two sulci meet. The floor there (the col) is the
  // shallower tooth's floor at its interproximal site and falls to the
  // deeper tooth's floor at that tooth's site (the two sites lie a few tenths
  // of a millimetre either side of the cut; the sulci are wider than the space
  // between the roots, so nearness to a root cannot decide): a probe reads
  // each tooth's own floor at its line angles and, walking under the contact
  // from the shallower side, meets the shallower floor first. The slope runs
  // over the whole space between the two sites, so that the 0.3 mm grid does
  // not round a cliff at one site into a floor too high there. The same from
  // both sides.
  double own_above = own.above, cavity = -1e9, own_side = 1e9;
  for (const Link& l : links_) {
    const Vector3 q = l.n->A * p + l.n->b;
    const CollarAt other = Collar(*l.n->gingiva, q, l.seen);
    // (each link's terms kept to its neighbour's side of this tooth's axis:
    // by the cut toward the other neighbour, where that neighbour's share
    // does not hold them, they lie far above the fillets' reach)
    const double u = l.e.x() * p.x() + l.e.y() * p.y(), behind = 2.0 * std::max(0.0, -u);
    band.Add(other.band + behind);
    const double across_signed = (p - l.q).dot(l.normal);
    // Each collar's margin holds on its own side of the cut and falls away
    // past it (the papilla joins the two there): a collar raised into its
    // papilla beside the contact does not lift its neighbour's margin at the
    // line angle.
    above.Add(q.z() - other.top + behind +
              kPastCutFall * SmoothRamp(-across_signed, 0.3));
    own_top_past_cuts += kPastCutFall * SmoothRamp(across_signed, 0.3);
    below.Add(other.bottom - q.z() + behind);
    own_side = std::min(own_side, kSulcusPastCut - across_signed);
    // (the two floors meet in this, whichever sulcus holds the point: a
    // sliver of one sulcus reaching past the other's wall would otherwise
    // carry its floor with it)
    const bool other_deeper = other.above > own.above;
    const double into_deeper = other_deeper ? across_signed : -across_signed;
    const double t_side = std::clamp(0.5 + (p - l.q).dot(l.across_dir) / 2.0, 0.0,
                                     1.0);  // 1 on the across_dir side
    const double* deep_gap = other_deeper ? l.other_site_gap : l.own_site_gap;
    const double* shallow_gap = other_deeper ? l.own_site_gap : l.other_site_gap;
    // (reached 0.05 mm before the deeper site, left 0.15 mm after the shallower)
    const double deep =
        std::max(0.1, t_side * deep_gap[0] + (1 - t_side) * deep_gap[1] - 0.05);
    const double shallow = std::clamp(
        t_side * shallow_gap[0] + (1 - t_side) * shallow_gap[1] - 0.15, 0.0, 1.0);
    const double col = std::min(own.above, other.above) +
                       std::clamp((into_deeper + shallow) / (deep + shallow), 0.0, 1.0) *
                           std::abs(own.above - other.above);
    own_above += col - own.above;  // (own.above itself away from this cut)
    const double other_above = col;
    const double other_cavity = std::max(std::min(other.inside, other_above), other.root);
    cavity = std::max(cavity, std::min(other_cavity, kSulcusPastCut + across_signed));
    double faces = std::max(-u, u - l.L);
    // (below the crest the faces draw in as each collar's wall does; the
    // crest runs straight from one tooth's to the other's)
    double drawn_in = 0;
    if (std::isfinite(l.crest_own)) {
      const double t_along = std::clamp(u / l.L, 0.0, 1.0);
      drawn_in = DrawnIn(l.crest_own + t_along * (l.crest_other - l.crest_own),
                         p.dot(own_->crest_up));
    }
    double to_face = -1e9, to_wall = -1e9;  // (negative inside the band's buccal and
                                            // lingual faces; the walls' line)
    for (int side = 0; side < 2; ++side) {
      // (the seen gingiva's faces set in as its collars' are, the mean of the
      // two teeth's: the same from both sides)
      double inset = 0;
      if (seen_) {
        inset = 0.5 * (SeenInset(*own_, *seen_, l.face_th[side][0], p.z()) +
                       SeenInset(*l.n->gingiva, *l.seen, l.face_th[side][1], q.z())) +
                kSeenGrooveMm;
      }
      to_face =
          std::max(to_face, (p - l.face_point[side]).dot(l.face_normal[side]) + inset);
      to_wall = std::max(to_wall, (p - l.wall_point[side]).dot(l.face_normal[side]));
    }
    faces = std::max(faces, to_face + drawn_in);
    band.Add(faces);
    // The papilla: highest by the contact, falling away from the cut and,
    // more gently, buccally and lingually; heights along the two teeth's mean vertical.
    const double across = SmoothAbs(across_signed, kPapillaTip),
                 aside = std::abs((p - l.q).dot(l.across_dir));
    // (its top rolls over into the faces as the collars' does, from the
    // line between the two sulci's walls: a papilla is a pyramid, its tip
    // between the teeth and no further out than their margins, not a fin
    // standing out of the embrasure)
    above.Add((p - l.papilla).dot(l.up) + l.slope[across_signed < 0 ? 0 : 1] * across +
              0.3 * SmoothRamp(aside - 1.0, 1.5) +
              kPapillaRoll * SmoothRamp(to_wall, 0.8) + behind);
    below.Add((l.base - p).dot(l.up) + 0.5 * std::abs(across_signed) + behind);
  }
  above.Add(p.z() - own.top + own_top_past_cuts);
  const double own_cavity = std::max(std::min(own.inside, own_above), own.root);
  cavity = std::max(cavity, std::min(own_cavity, own_side));
  double f = SmoothMax(band.Smooth(kFilletSides), above.Smooth(kFilletTop), kRound);
  f = SmoothMax(f, below.Smooth(kRound), kRound);
  return SmoothMax(f, cavity, kRound);
}

double GingivaShareField::Cut(const Vector3& p) const {
  double cut = -1e9;
  for (const Link& l : links_) cut = std::max(cut, (p - l.q).dot(l.normal));
  return cut;
}

std::vector<GingivaShareField::CutPlane> GingivaShareField::cuts() const {
  std::vector<CutPlane> out;
  for (const Link& l : links_) out.push_back({l.q, l.normal});
  return out;
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
  TriangleMesh mesh = RimsOntoField(
      ClipByPlanes(Simplify(Isosurface(near_side, field.box(), cell_mm), 0.02), planes),
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
