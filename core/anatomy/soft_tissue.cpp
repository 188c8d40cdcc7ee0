#include "core/anatomy/soft_tissue.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <mutex>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <tuple>

#include "core/anatomy/gingiva.h"
#include "core/anatomy/mesh_contact.h"
#include "core/anatomy/soft_tissue_parts.h"
#include "core/anatomy/tooth.h"
#include "core/base/text.h"

namespace sulcus {
namespace soft_tissue {
namespace {

// The buccal extent of the teeth (both arches) at each station of a curve:
// the largest outward offset of any tooth point near it.
double BuccalExtent(const ArchCurve& curve, const std::vector<const ArchTeeth*>& arches,
                    double s, double width) {
  double best = 3.0;
  for (const ArchTeeth* a : arches) {
    for (std::size_t k = 0; k < a->placed.size(); ++k) {
      const double s_k = curve.Project(a->placed[k].X_WT.translation(), a->s[k]);
      if (std::abs(s_k - s) > 8) continue;
      for (const Vector3& v : a->meshes[k].vertices()) {
        const double sv = curve.Project(v, s_k);
        if (std::abs(sv - s) > width) continue;
        best = std::max(best, (v - curve.Point(sv)).dot(curve.Normal(sv)));
      }
    }
  }
  return best;
}

// A lip's section about `origin`: its inner (mucosal) face at `inner` along
// `u` (outward), from the vestibule's fold at `fold` to the free edge at
// `edge` (z). The free edge is the vermilion: a rounded rim `thickness` thick
// (a half ellipse); toward the fold the lip thins to 60 % of that and its
// corners are squarer (a superellipse of exponent 4), where the vestibule's
// mucosa turns. The inner face keeps to `inner` or outside it. The outer face
// (the skin) is up to `groove` mm deeper away from the vermilion: none over
// the fifth of the height next to the free edge, all of it from nearly half
// way to the fold (the philtrum, on the upper lip). m points.
// Point i of m around a lip's section: x across it (> 0 on the outer face,
// the skin's side) and y from the fold (-1) to the free edge (+1), each in
// [-1, 1].
void LipRingPoint(int i, int m, double* x, double* y) {
  const double a = 2 * kPi * i / m, c = std::cos(a), s = std::sin(a);
  const double e = s >= 0 ? 2.0 : 4.0;  // s > 0: the edge's half
  *x = std::copysign(std::pow(std::abs(c), 2 / e), c);
  *y = std::copysign(std::pow(std::abs(s), 2 / e), s);
}
constexpr int kLipRing = 32;  // points around a lip's section

std::vector<Vector3> LipSection(const Vector3& origin, const Vector3& u, double inner,
                                double thickness, double edge, double fold, int m,
                                double groove = 0) {
  std::vector<Vector3> ring;
  const double zc = 0.5 * (edge + fold), hz = 0.5 * std::abs(edge - fold),
               toward_edge = edge > fold ? 1 : -1;
  for (int i = 0; i < m; ++i) {
    double x, y;
    LipRingPoint(i, m, &x, &y);
    const double t = 0.5 * (1 - y);  // 0 at the edge, 1 at the fold
    double half = 0.5 * thickness * (1 - 0.4 * t);
    if (x > 0) half -= 0.5 * groove * x * std::clamp((t - 0.2) / 0.25, 0.0, 1.0);
    ring.push_back(origin + (inner + half * (1 + x)) * u +
                   Vector3(0, 0, zc + toward_edge * hz * y));
  }
  return ring;
}

// A slab outside the teeth along `curve` from s0 to s1: its inner face a
// vestibule's width (`gap`) outside the teeth, `thickness` thick, z from z0 to
// z1 (tapered to its ends over `z_round` stations). A lip (`lip_edge` +1: its
// free edge at z1, -1: at z0) takes LipSection's profile, a cheek (0) a
// rounded rectangle.
TriangleMesh OuterSlab(const ArchCurve& curve,
                       const std::vector<const ArchTeeth*>& arches, double s0, double s1,
                       double gap, double thickness, double z0, double z1,
                       double z_round = 2, int lip_edge = 0, double fissure_half = 3.0) {
  const int stations = std::max(8, static_cast<int>((s1 - s0) / 1.0));
  std::vector<double> inner(stations + 1);
  for (int i = 0; i <= stations; ++i)
    inner[i] = BuccalExtent(curve, arches, s0 + (s1 - s0) * i / stations, 1.0) + gap;
  // Smoothed: the mucosa drapes over the teeth's bulges.
  std::vector<double> smooth = inner;
  for (int i = 0; i <= stations; ++i)
    for (int j = std::max(0, i - 3); j <= std::min(stations, i + 3); ++j)
      smooth[i] = std::max(smooth[i], inner[j]);
  std::vector<std::vector<Vector3>> rings;
  for (int i = 0; i <= stations; ++i) {
    const double s = s0 + (s1 - s0) * i / stations;
    const double t = std::min(i, stations - i) / std::max(1.0, z_round);
    const double shrink = std::min(1.0, 0.35 + 0.65 * std::sqrt(t));
    Vector3 o = curve.Point(s);
    o.z() = 0;
    const double zc = 0.5 * (z0 + z1), hz = 0.5 * (z1 - z0) * shrink;
    const double t_i = thickness * std::max(0.5, shrink);
    if (lip_edge == 0) {
      rings.push_back(Section(o, curve.Normal(s), smooth[i], smooth[i] + t_i, zc - hz,
                              zc + hz, 24, 3.0));
    } else {
      // The oral fissure is an oval: toward the commissures each lip's free
      // edge comes toward the other lip's (as the 2.5th power of the
      // distance from the midline), `fissure_half` at the ends, where the two
      // meet; at its ends the lip's height shrinks toward that edge. The lip
      // is fullest at the midline and thins to 60 % toward the commissures;
      // the upper lip's edge dips 0.8 mm at the midline (its tubercle), and
      // its skin has the philtrum, a groove 0.8 mm deep and about 6 mm wide.
      const double mid = s - 0.5 * (s0 + s1), w = mid / (0.5 * (s1 - s0));
      const double f = std::pow(std::abs(w), 2.5);
      const bool upper = lip_edge < 0;
      const double tubercle = upper ? 0.8 * std::exp(-std::pow(mid / 3.5, 2)) : 0.0;
      const double edge =
          (lip_edge > 0 ? z1 : z0) + lip_edge * (fissure_half * f + tubercle);
      const double fold = edge + ((lip_edge > 0 ? z0 : z1) - edge) * shrink;
      const double philtrum = upper ? 0.8 * std::exp(-std::pow(mid / 3.0, 4)) : 0.0;
      rings.push_back(LipSection(o, curve.Normal(s), smooth[i], t_i * (1 - 0.4 * w * w),
                                 edge, fold, kLipRing, philtrum));
    }
  }
  return Loft(rings);
}

// Heights of the two arches' teeth: the lower incisal edge, the upper, and the
// crests (lower: its highest; upper: its lowest), for sizing soft tissue.
struct Levels {
  double lower_edge, upper_edge, lower_crest, upper_crest;
};

Levels LevelsOf(const ArchTeeth& lower, const ArchTeeth& upper) {
  Levels l{-1e9, 1e9, -1e9, 1e9};
  for (const TriangleMesh& m : lower.meshes)
    l.lower_edge = std::max(l.lower_edge, m.Bounds().max.z());
  for (const TriangleMesh& m : upper.meshes)
    l.upper_edge = std::min(l.upper_edge, m.Bounds().min.z());
  for (const PlacedTooth& p : lower.placed)
    l.lower_crest = std::max(l.lower_crest, p.X_WT.translation().z() - 1.5);
  for (const PlacedTooth& p : upper.placed)
    l.upper_crest = std::min(l.upper_crest, p.X_WT.translation().z() + 1.5);
  return l;
}

// The lingual limit of the lower teeth across the mouth at height y: the half
// width of the space the tongue lies in.
double LingualHalfWidth(const ArchTeeth& lower, double y) {
  double half = 1e9;
  for (const TriangleMesh& m : lower.meshes) {
    for (const Vector3& v : m.vertices()) {
      if (std::abs(v.y() - y) < 1.0) half = std::min(half, std::abs(v.x()));
    }
  }
  return half;
}

// A section of the tongue at `y`: `half` wide each side, its widest (the
// lateral borders) at `mid`; above them the dorsum, convex across (a
// superellipse of exponent 2.3, so it falls about 1.6 mm from the midline to
// four fifths of the way out) with a median groove `groove` deep; below them
// the sides and the underside down to `bottom`, squarer (exponent 3).
std::vector<Vector3> TongueSection(double y, double half, double top, double mid,
                                   double bottom, double groove, int m) {
  std::vector<Vector3> ring;
  for (int i = 0; i < m; ++i) {
    const double a = 2 * kPi * i / m, c = std::cos(a), s = std::sin(a);
    const double e = s >= 0 ? 2.3 : 3.0;
    const double x = half * std::copysign(std::pow(std::abs(c), 2 / e), c);
    double z = s >= 0 ? mid + (top - mid) * std::pow(s, 2 / e)
                      : mid - (mid - bottom) * std::pow(-s, 2 / e);
    if (s > 0) z -= groove * std::exp(-std::pow(x / 2.5, 2)) * s;
    ring.emplace_back(x, y, z);
  }
  return ring;
}

TriangleMesh Tongue(const ArchTeeth& lower, const Levels& lv) {
  // From the tip, 5.5 mm behind the lower incisors' lingual surfaces (3 mm
  // behind their lingual gingiva: the tongue at rest as a patient holds it with
  // the mouth open, the floor of the mouth and the ventral surface within reach
  // of an instrument), back 45 mm, where its base turns down into the throat.
  double front = -1e9;  // the central incisors' lingual extent
  for (std::size_t k = 0; k < lower.placed.size(); ++k)
    if (lower.placed[k].tooth.position == 1)
      front = std::max(front, lower.meshes[k].Bounds().min.y());
  const double tip = front - 5.5, back = tip - 45.0;
  const int stations = 72;
  const double step = (tip - back) / stations;
  // Half width: 2 mm inside the lower teeth, behind the last molars its widest.
  // Each tooth's lingual bulge would print on the borders as a ridge: the
  // room is eroded (the least within 3 mm) and then averaged over the same
  // 3 mm, which leaves it nowhere wider than the room it came from.
  std::vector<double> room(stations + 1);
  double widest = 0;
  for (int i = 0; i <= stations; ++i) {
    const double r = LingualHalfWidth(lower, tip - i * step);
    if (r < 100) widest = std::max(widest, r - 2.0);
    room[i] = r < 100 ? r - 2.0 : widest;
  }
  const int reach = static_cast<int>(std::ceil(3.0 / step));
  std::vector<double> eroded(stations + 1), width(stations + 1, 0.0);
  for (int i = 0; i <= stations; ++i) {
    eroded[i] = room[i];
    for (int j = std::max(0, i - reach); j <= std::min(stations, i + reach); ++j)
      eroded[i] = std::min(eroded[i], room[j]);
  }
  for (int i = 0; i <= stations; ++i) {
    int n = 0;
    for (int j = std::max(0, i - reach); j <= std::min(stations, i + reach); ++j, ++n)
      width[i] += eroded[j];
    width[i] /= n;
  }
  std::vector<std::vector<Vector3>> rings;
  const double lower_z = lv.lower_crest - 8.0;  // where it joins the floor of the mouth
  for (int i = 0; i <= stations; ++i) {
    const double y = tip - i * step;
    const double from_tip = tip - y;
    const double w = width[i];
    // The tip rounded like a half disc.
    const double r_tip = 0.8 * w;
    const double round =
        from_tip < r_tip ? std::sqrt(std::max(0.0, 1 - std::pow(1 - from_tip / r_tip, 2)))
                         : 1.0;
    // Its base (the last 14 mm) bends down; over the last 8 mm its corners are
    // rounded off in plan, to 55 % of its width at the end.
    const double base = std::max(0.0, from_tip - 31.0);
    const double t = std::clamp((base - 6.0) / 8.0, 0.0, 1.0);
    const double half =
        std::max(0.8, w * std::max(0.12, round) * (0.55 + 0.45 * std::sqrt(1 - t * t)));
    // The dorsum level with the lower occlusal plane, rising toward the back and
    // falling to the tip; the base bends down (an arc of 20 mm radius, its
    // whole section) toward the oropharynx. The ventral surface free under the
    // first 12 mm, then down to the floor of the mouth.
    const double turn = 20.0 - std::sqrt(20.0 * 20.0 - base * base);  // 5.7 mm at the end
    const double bottom_free = from_tip < 12 ? (from_tip / 12.0) : 1.0;
    double top = lv.lower_edge - 1.5 +
                 4.0 * std::pow(std::min(from_tip, 31.0) / 45.0, 1.5) - 2.5 * (1 - round);
    const double bottom =
        std::min(top - 4.0 - (top - 4.0 - lower_z) * bottom_free, top - 2.5) - turn;
    top -= turn;
    // The lateral borders 4.5 mm below the dorsum (less where it is thin).
    const double mid = top - std::min(4.5, 0.5 * (top - bottom));
    // The median groove: 0.5 mm deep from 12 mm behind the tip (growing in from
    // 4 mm), fading out over the base.
    const double groove = 0.5 * std::clamp((from_tip - 4.0) / 8.0, 0.0, 1.0) *
                          std::clamp(1 - base / 10.0, 0.0, 1.0);
    rings.push_back(TongueSection(y, half, top, mid, bottom, groove, 48));
  }
  return Loft(rings);
}

TriangleMesh FloorOfMouth(const ArchTeeth& lower, const Levels& lv,
                          const ArchParams& arch) {
  // A horseshoe of mucosa inside the lower arch, from first molar to first
  // molar, 7 mm below the crest, from 0.5 mm inside the roots (in the jaw's
  // lingual bone) 9 mm toward the tongue.
  const ArchCurve curve(false, arch);
  const double end = ArchCentreMm(false, 6);
  std::vector<std::vector<Vector3>> rings;
  const int stations = 48;
  for (int i = 0; i <= stations; ++i) {
    const double s = -end + 2 * end * i / stations;
    double lingual = 0;
    for (std::size_t k = 0; k < lower.placed.size(); ++k) {
      if (std::abs(lower.s[k] - s) > 4) continue;
      for (const Vector3& v : lower.meshes[k].vertices()) {
        lingual = std::min(lingual, (v - curve.Point(s)).dot(curve.Normal(s)));
      }
    }
    Vector3 o = curve.Point(s);
    o.z() = 0;
    const double top = lv.lower_crest - 7.0;
    rings.push_back(Section(o, curve.Normal(s), lingual - 9.5, lingual - 0.5, top - 3.0,
                            top, 20, 3.0));
  }
  return Loft(rings);
}

TriangleMesh Palate(const ArchTeeth& upper, const Levels& lv, bool soft) {
  // The hard palate: a vault between the upper teeth's palatal sides, from
  // behind the incisors to the second molars' distal surfaces; the soft palate
  // hangs from its back edge.
  double front = -1e9, back = 1e9;
  for (std::size_t k = 0; k < upper.placed.size(); ++k) {
    const Aabb b = upper.meshes[k].Bounds();
    if (upper.placed[k].tooth.position == 1) front = std::max(front, b.min.y());
    back = std::min(back, b.min.y());
  }
  auto half_width = [&](double y) {
    double half = 1e9;
    for (const TriangleMesh& m : upper.meshes)
      for (const Vector3& v : m.vertices())
        if (std::abs(v.y() - y) < 1.0) half = std::min(half, std::abs(v.x()));
    return half > 100 ? 0.0 : half;
  };
  const double vault = 11.0;  // palatal vault above the crest at the midline
  std::vector<std::vector<Vector3>> rings;
  const int m = 28;
  if (!soft) {
    const double y0 = front - 1.0, y1 = back;
    const int stations = 40;
    for (int i = 0; i <= stations; ++i) {
      const double y = y0 + (y1 - y0) * i / stations;
      double half = half_width(y);
      if (half == 0) half = half_width(y0 - 3);
      const double rise = std::sqrt(std::min(1.0, (y0 - y) / 8.0));
      half = std::max(1.0, half * std::max(0.2, rise));
      std::vector<Vector3> ring;
      // Lower (oral) surface: a vault from the teeth's palatal sides (at the
      // crest) to `vault` above it; the bone and mucosa 3.5 to 5.5 mm thick.
      for (int j = 0; j < m; ++j) {
        const double a = 2 * kPi * j / m, c = std::cos(a), s = std::sin(a);
        const double x = half * c;
        const double under =
            lv.upper_crest - 1.0 + vault * rise * std::sqrt(std::max(0.0, 1 - c * c));
        ring.emplace_back(x, y, s < 0 ? under - 1.0 : under + 2.5 + 2.0 * std::abs(s));
      }
      rings.push_back(std::move(ring));
    }
    return Loft(rings);
  }
  // Soft palate: 14 mm long, hanging 35 degrees down from the hard palate's back.
  const double half0 = std::max(8.0, 0.8 * half_width(back + 2));
  const int stations = 16;
  for (int i = 0; i <= stations; ++i) {
    const double t = static_cast<double>(i) / stations;
    const double y = back + 1 - 14 * t * std::cos(0.6);
    const double top = lv.upper_crest - 1.0 + vault + 3.5 - 14 * t * std::sin(0.6);
    const double half = half0 * (1 - 0.45 * t * t);
    rings.push_back(
        Section(Vector3(0, y, 0), Vector3::UnitX(), -half, half, top - 3.5, top, m, 2.4));
  }
  return Loft(rings);
}

}  // namespace
}  // namespace soft_tissue

using namespace soft_tissue;  // the shapes the soft tissues share

const std::vector<std::string>& SoftTissueNames() {
  static const std::vector<std::string> names = {
      "jaw_lower",   "jaw_upper", "lip_upper",      "lip_lower", "cheek_left",
      "cheek_right", "tongue",    "floor_of_mouth", "palate",    "soft_palate"};
  return names;
}

std::vector<double> LipSkinCoverage(const TriangleMesh& lip) {
  // (Loft's vertices: a cap's centre, the rings in order, the other cap's centre)
  const std::size_t n = lip.num_vertices();
  if (n < 2 + kLipRing || (n - 2) % kLipRing != 0) return {};
  std::vector<double> skin(n, 0.0);
  for (std::size_t v = 1; v + 1 < n; ++v) {
    double x, y;
    LipRingPoint(static_cast<int>((v - 1) % kLipRing), kLipRing, &x, &y);
    if (x <= 0) continue;  // the mucosa, facing the teeth
    // The vermilion border a third of the way from the free edge to the fold
    // (a real one 6 to 9 mm from the free edge; the lips here are 18 to 20 mm
    // from edge to fold), sharp as a real one is: over a tenth of that.
    skin[v] = SmoothStep((0.5 * (1 - y) - 0.3) / 0.1);
  }
  return skin;
}

std::string TongueRegion(const Vector3& n) {
  if (n.z() > 0.6) return "dorsum";
  if (n.z() < -0.6) return "ventral surface";
  return "lateral border";
}

TriangleMesh MakeSoftTissue(const std::string& name, const ArchParams& arch,
                            const std::map<int, double>& drops,
                            const std::map<int, std::map<std::string, int>>& furcation) {
  const auto& known = SoftTissueNames();
  if (std::find(known.begin(), known.end(), name) == known.end()) {
    throw std::invalid_argument("unknown anatomy '" + name + "'; known: " + Join(known));
  }
  if (name == "jaw_lower") return Jaw(false, arch, drops, furcation);
  if (name == "jaw_upper") return Jaw(true, arch, drops, furcation);
  const ArchTeeth& lower = Teeth(false, arch);
  const ArchTeeth& upper = Teeth(true, arch);
  const Levels lv = LevelsOf(lower, upper);
  if (name == "tongue") return Tongue(lower, lv);
  if (name == "floor_of_mouth") return FloorOfMouth(lower, lv, arch);
  if (name == "palate") return Palate(upper, lv, false);
  if (name == "soft_palate") return Palate(upper, lv, true);
  // Lips and cheeks: 2.5 mm of vestibule outside the teeth; the lips from
  // commissure to commissure (about the canines' distal surfaces), the cheeks
  // from there to 8 mm behind the last molars, from fold to fold.
  const double commissure = ArchCentreMm(true, 3) + 4.5;
  if (name == "lip_upper" || name == "lip_lower") {
    const bool up = name == "lip_upper";
    const ArchCurve curve(up, arch);
    const std::vector<const ArchTeeth*> teeth = {up ? &upper : &lower};
    // The upper lip's edge 2 mm above the upper incisal edge, the lower's 1 mm
    // below the lower's; each up (down) to its vestibule's fold.
    // The two edges meet at the commissures (3 mm each at the least, as
    // when the mouth is closed and the edges pass each other).
    const double edge = up ? lv.upper_edge + 2.0 : lv.lower_edge - 1.0;
    const double fold = up ? lv.upper_crest + 9.0 : lv.lower_crest - 9.0;
    const double meet =
        std::max(3.0, 0.5 * ((lv.upper_edge + 2.0) - (lv.lower_edge - 1.0)));
    return OuterSlab(curve, teeth, -commissure, commissure, 2.5, 9.0,
                     std::min(edge, fold), std::max(edge, fold), 6, up ? -1 : 1, meet);
  }
  const bool left = name == "cheek_left";
  const ArchCurve curve(true, arch);
  const double s0 = commissure - 5, s1 = ArchEnd(true) + 8;
  return OuterSlab(curve, {&upper, &lower}, left ? s0 : -s1, left ? s1 : -s0, 2.5, 5.0,
                   lv.lower_crest - 9.0, lv.upper_crest + 9.0, 5);
}

}  // namespace sulcus
