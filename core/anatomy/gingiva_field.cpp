// The field of a tooth's share of the gingiva: the felt collar with its open
// sulcus, the seen tissue closed round the tooth, papillae and cols toward the
// neighbours (GingivaShareField in gingiva.h). The model and the meshing are in
// gingiva.cpp.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "core/anatomy/gingiva.h"

namespace sulcus {

namespace {

constexpr double kPi = std::numbers::pi;

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
// per mm, so that the share ends inside the jaw (whose top, jaw.cpp,
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
  const OuterRadii radii(tooth.mesh);
  for (int j = 0; j <= 24; ++j) {
    const double z = tooth.dimensions.crown_height * j / 24.0, r = radii.At(th, z);
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
    const ClipPlane cut = CutToward(tooth, *n.tooth, n.A, n.b);
    l.q = cut.q;
    l.normal = cut.normal;
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

ClipPlane CutToward(const ToothModel& tooth, const ToothModel& next, const Matrix3& A,
                    const Vector3& b) {
  const Matrix3 At = A.transpose();  // the neighbour's frame to this one
  const Vector3 c = -(At * b);       // its axis' origin here
  const double th_e = std::atan2(c.y(), c.x());
  const double th_back = std::atan2(b.y(), b.x());  // toward this tooth, there
  const Vector3 p_i = ContactPoint(tooth, th_e);
  const Vector3 p_j = At * (ContactPoint(next, th_back) - b);
  const Vector3 e_j = At * Vector3(std::cos(th_back), std::sin(th_back), 0);
  return {0.5 * (p_i + p_j),
          (Vector3(std::cos(th_e), std::sin(th_e), 0) - e_j).normalized()};
}

std::vector<GingivaShareField::CutPlane> GingivaShareField::cuts() const {
  std::vector<CutPlane> out;
  for (const Link& l : links_) out.push_back({l.q, l.normal});
  return out;
}

}  // namespace sulcus
