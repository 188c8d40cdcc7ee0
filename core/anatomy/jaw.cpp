// The jaws: bone around every root of an arch, its crest per tooth, and the bone
// between the roots of a tooth whose furcation a scene involves.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include "core/anatomy/gingiva.h"
#include "core/anatomy/mesh_contact.h"
#include "core/anatomy/soft_tissue_parts.h"

namespace sulcus {
namespace soft_tissue {
namespace {

// The jaw's section is taken in bands of kBandMm from the crest toward the
// apices, each band's faces from the roots within it, so that the bone
// follows the roots' inclination (an upper incisor's root leans back 4 to 5 mm
// over its length) instead of standing as a wall at their widest.
constexpr int kBands = 24;
constexpr double kBandMm = 1.0;

struct Extent {
  // Offsets along the arch's outward normal, in each band below the crest.
  std::array<double, kBands> n_min, n_max;
  double far =
      -1e9;  // the deepest root point, as distance away from the crowns (sign * z)
  bool any = false;
  Extent() { n_min.fill(1e9), n_max.fill(-1e9); }
};

// The middle of a multi-rooted tooth's roots (their tops' mean) in its tooth
// frame's xy: where the line between them runs.
Vector2 RootsMiddle(const ToothModel& tooth) {
  Vector2 mid = Vector2::Zero();
  for (const Vector3& top : tooth.root_tops)
    mid += top.head<2>() / static_cast<double>(tooth.root_tops.size());
  return mid;
}

// Where a multi-rooted tooth's roots part, below its CEJ, measured on its mesh
// (as Teeth generates it) down the line through the roots' middle.
double MeasureFurcationRoof(const FdiTooth& t) {
  const ToothModel tooth = GenerateTooth(t.fdi, {.resolution = 3});
  const Vector2 mid = RootsMiddle(tooth);
  std::vector<Vector3> line;
  for (double z = 0; z > -tooth.dimensions.root_length; z -= 0.1)
    line.emplace_back(mid.x(), mid.y(), z);
  const std::vector<bool> inside = InsideSolid(tooth.mesh, line);
  const auto out = std::find(inside.begin(), inside.end(), false);
  return out == inside.end() ? tooth.dimensions.root_length
                             : -line[out - inside.begin()].z();
}

// How far a furcation's bone is missing in from its entrance (Hamp: class 1
// less than 3 mm, 2 more than 3 mm but not through; 3 through, handled by the
// caller): 2 and 4 mm.
double FurcationDefectMm(int hamp) { return hamp == 1 ? 2.0 : hamp == 2 ? 4.0 : 0.0; }

// The bone between a multi-rooted tooth's roots where its crest has dropped
// below the furcation, in its (unmirrored) tooth frame: a prism between the
// roots from 1 mm under the crest up to 0.3 mm short of the roof of the
// furcation (found on the tooth's own mesh, straight above the prism's
// middle), its faces at the entrances flush with the roots and each moved in
// by the entrance's defect (FurcationDefectMm), never to less than 1 mm of
// bone; with no entrance involved (class 0 everywhere, or no classes given),
// the whole prism: the bone a furcation keeps when attachment is lost around
// the tooth but not between its roots. None when an entrance is class 3
// (through and through: no bone between the roots above the crest), for a
// single-rooted tooth, or where the crest lies above the prism.
std::optional<TriangleMesh> InterradicularBone(
    const FdiTooth& t, double crest_drop, const std::map<std::string, int>& classes) {
  int worst = 0;
  for (const auto& [entrance, hamp] : classes) worst = std::max(worst, hamp);
  if (worst == 3 || !FurcationAboveCrest(t.fdi, crest_drop)) return std::nullopt;
  const ToothDimensions d = Dimensions(t);
  const double a = d.md_cervix / 2,
               b = d.bl / 2 * 0.82;  // tooth.cpp's cervical half widths
  // The roots' tops (tooth.cpp): lower molar mesial, distal; upper molar
  // mesiobuccal, distobuccal, palatal; upper premolar buccal, palatal.
  const std::vector<Vector3> tops = GenerateTooth(t.fdi, {.resolution = 3}).root_tops;
  // Half-planes n . p <= c (n unit, in the tooth's xy), counter-clockwise,
  // each with the entrance it faces ("" for a root's side).
  struct Side {
    Vector2 n;
    double c;
    std::string entrance;
  };
  std::vector<Side> sides;
  if (t.position >= 6 && !t.upper()) {  // between the roots' axes; B (+y) and L
    const double m = tops[0].x(), dist = -tops[1].x();
    sides = {{{1, 0}, m, ""},
             {{0, 1}, 0.7 * b, "B"},
             {{-1, 0}, dist, ""},
             {{0, -1}, 0.7 * b, "L"}};
  } else if (t.position >= 6) {  // MB, DB and palatal roots: B, D and M
    const Vector2 mb = tops[0].head<2>(), db = tops[1].head<2>(), pal = tops[2].head<2>();
    const Vector2 n_m = Vector2(mb.y() - pal.y(), -(mb.x() - pal.x())).normalized();
    const Vector2 n_d = Vector2(-(db.y() - pal.y()), db.x() - pal.x()).normalized();
    sides = {{n_m, n_m.dot(mb) + 0.2 * a, "M"},
             {{0, 1}, 0.75 * b, "B"},
             {n_d, n_d.dot(db) + 0.2 * a, "D"}};
  } else {  // the upper first premolar: buccal and palatal roots; M (+x) and D
    sides = {{{1, 0}, 0.5 * a, "M"},
             {{0, 1}, tops[0].y(), ""},
             {{-1, 0}, 0.5 * a, "D"},
             {{0, -1}, -tops[1].y(), ""}};
  }
  auto corners = [&](double scale) {
    std::vector<Vector2> poly;
    for (std::size_t i = 0; i < sides.size(); ++i) {
      const Side& p = sides[i];
      const Side& q = sides[(i + 1) % sides.size()];
      auto c_of = [&](const Side& s) {
        const auto it = classes.find(s.entrance);
        return s.c - (it == classes.end() ? 0.0 : scale * FurcationDefectMm(it->second));
      };
      const Eigen::Matrix2d m =
          (Eigen::Matrix2d() << p.n.x(), p.n.y(), q.n.x(), q.n.y()).finished();
      poly.push_back(m.inverse() * Vector2(c_of(p), c_of(q)));
    }
    return poly;
  };
  // The defects as deep as their classes say, or less where they would leave
  // under 1 mm of bone (the inradius of what is left at least 0.5 mm).
  auto thick_enough = [&](const std::vector<Vector2>& poly) {
    double area = 0;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Vector2& p = poly[i];
      const Vector2& q = poly[(i + 1) % poly.size()];
      area += p.x() * q.y() - q.x() * p.y();
    }
    Vector2 mid = Vector2::Zero();
    for (const Vector2& p : poly) mid += p / static_cast<double>(poly.size());
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Vector2 e = (poly[(i + 1) % poly.size()] - poly[i]).normalized();
      if (e.x() * (mid - poly[i]).y() - e.y() * (mid - poly[i]).x() < 0.5) return false;
    }
    return area > 0;
  };
  double scale = 1.0;
  while (scale > 0.05 && !thick_enough(corners(scale))) scale *= 0.8;
  const std::vector<Vector2> poly = corners(scale);
  Vector2 mid = Vector2::Zero();
  for (const Vector2& p : poly) mid += p / static_cast<double>(poly.size());
  const double roof = -FurcationRoofMm(t.fdi);
  const double z0 = -crest_drop - 1.0, z1 = roof - 0.3;
  std::vector<std::vector<Vector3>> rings(2);
  for (const Vector2& p : poly) {
    rings[0].emplace_back(p.x(), p.y(), z0);
    rings[1].emplace_back(p.x(), p.y(), z1);
  }
  return Loft(rings);
}

}  // namespace

TriangleMesh Jaw(bool upper, const ArchParams& arch, const std::map<int, double>& drops,
                 const std::map<int, std::map<std::string, int>>& furcation) {
  const ArchCurve curve(upper, arch);
  const ArchTeeth& teeth = Teeth(upper, arch);
  const double sign = upper ? 1.0 : -1.0;  // away from the occlusal plane
  const double end = ArchEnd(upper) + 7;   // past the last molar: the retromolar bone
  const int stations = static_cast<int>(2 * end / 0.75) + 1;
  std::vector<Extent> ext(stations);
  // The crest: each tooth's own (its CEJ's centre, the tooth frame's origin,
  // `drop` beyond it) at its centre, running straight from one tooth's centre
  // to the next's (as a share of the gingiva's interdental crest does), level
  // beyond the last teeth.
  std::vector<double> crest(stations, 0.0);
  auto station_s = [&](int i) { return -end + 2 * end * i / (stations - 1); };
  auto station_of = [&](double s) {
    return static_cast<int>(std::lround((s + end) / (2 * end) * (stations - 1)));
  };
  std::vector<std::size_t> by_s(teeth.placed.size());  // the teeth in arch order
  for (std::size_t k = 0; k < by_s.size(); ++k) by_s[k] = k;
  std::sort(by_s.begin(), by_s.end(),
            [&](std::size_t a, std::size_t b) { return teeth.s[a] < teeth.s[b]; });
  std::vector<double> crest_of(teeth.placed.size());
  for (std::size_t k = 0; k < teeth.placed.size(); ++k) {
    const PlacedTooth& p = teeth.placed[k];
    const auto it = drops.find(p.tooth.fdi);
    const double drop = it == drops.end() ? 1.5 : it->second;
    crest_of[k] = p.X_WT.translation().z() + sign * drop;
  }
  for (int i = 0; i < stations && !by_s.empty(); ++i) {
    const double s = station_s(i);
    const auto next = std::partition_point(by_s.begin(), by_s.end(),
                                           [&](std::size_t k) { return teeth.s[k] < s; });
    if (next == by_s.begin()) {
      crest[i] = crest_of[by_s.front()];
    } else if (next == by_s.end()) {
      crest[i] = crest_of[by_s.back()];
    } else {
      const std::size_t a = *(next - 1), b = *next;
      crest[i] = crest_of[a] + (crest_of[b] - crest_of[a]) * (s - teeth.s[a]) /
                                   (teeth.s[b] - teeth.s[a]);
    }
  }
  // Across each tooth's cervix no more than 0.4 mm beyond its own crest: a
  // deep defect at one tooth does not bare its neighbours' roots.
  for (std::size_t k = 0; k < teeth.placed.size(); ++k) {
    const double half = Dimensions(teeth.placed[k].tooth).md_cervix / 2 + 0.5;
    for (int i = 0; i < stations; ++i)
      if (std::abs(station_s(i) - teeth.s[k]) <= half &&
          sign * (crest[i] - crest_of[k]) > 0.4)
        crest[i] = crest_of[k] + sign * 0.4;
  }
  for (std::size_t k = 0; k < teeth.placed.size(); ++k) {
    const double crest_z = crest_of[k];
    for (const Vector3& v : teeth.meshes[k].vertices()) {
      const int i = station_of(curve.Project(v, teeth.s[k]));
      const double along = sign * (v.z() - crest_z);  // > 0: in the bone
      if (along < 0 || i < 0 || i >= stations) continue;
      const int band = std::min(kBands - 1, static_cast<int>(along / kBandMm));
      for (int j = std::max(0, i - 2); j <= std::min(stations - 1, i + 2); ++j) {
        const double n = (v - curve.Point(station_s(j))).dot(curve.Normal(station_s(j)));
        Extent& e = ext[j];
        e.any = true;
        e.n_min[band] = std::min(e.n_min[band], n);
        e.n_max[band] = std::max(e.n_max[band], n);
        e.far = std::max(e.far, sign * v.z());
      }
    }
  }
  // Stations without roots (the ends) take the nearest rooted station's
  // section; bands past the apices the deepest band's that holds a root.
  int first = 0, last = stations - 1;
  while (first < stations && !ext[first].any) ++first;
  while (last >= 0 && !ext[last].any) --last;
  for (int i = 0; i < first; ++i) ext[i] = ext[first];
  for (int i = last + 1; i < stations; ++i) ext[i] = ext[last];
  for (Extent& e : ext) {
    int b = 0;
    while (b < kBands && e.n_max[b] < -1e8) ++b;
    for (int c = 0; c < b && b < kBands; ++c)
      e.n_min[c] = e.n_min[b], e.n_max[c] = e.n_max[b];
    for (int c = 1; c < kBands; ++c)
      if (e.n_max[c] < -1e8) e.n_min[c] = e.n_min[c - 1], e.n_max[c] = e.n_max[c - 1];
  }
  // Smooth the section along the arch and down it (the bone does not follow
  // each root's bulge): the widest extent within 4 stations (3 mm) and 1
  // band, then the mean of that over the same window. The mean of widest
  // extents taken over windows that all contain a cell is at least that
  // cell's own, so every root stays inside, and the outer surface ramps
  // between teeth instead of stepping where one root's extent gives way to
  // the next.
  // The far edge (the bone's depth) the same way over 16 stations (12 mm): it
  // would otherwise follow each root's length, a notch at the short-rooted
  // incisors and a peak at each long canine, where the jaw's edge is a smooth
  // curve.
  constexpr int kSmooth = 4, kSmoothFar = 16, kSmoothBands = 1;
  std::vector<Extent> widest = ext;
  for (int i = 0; i < stations; ++i) {
    for (int j = std::max(0, i - kSmoothFar); j <= std::min(stations - 1, i + kSmoothFar);
         ++j) {
      if (std::abs(i - j) <= kSmooth) {
        for (int b = 0; b < kBands; ++b) {
          for (int c = std::max(0, b - kSmoothBands);
               c <= std::min(kBands - 1, b + kSmoothBands); ++c) {
            widest[i].n_min[b] = std::min(widest[i].n_min[b], ext[j].n_min[c]);
            widest[i].n_max[b] = std::max(widest[i].n_max[b], ext[j].n_max[c]);
          }
        }
      }
      widest[i].far = std::max(widest[i].far, ext[j].far);
    }
  }
  std::vector<Extent> smooth = widest;
  for (int i = 0; i < stations; ++i) {
    double far = 0;
    int count_far = 0;
    for (int b = 0; b < kBands; ++b) {
      double n_min = 0, n_max = 0;
      int count = 0;
      for (int j = std::max(0, i - kSmooth); j <= std::min(stations - 1, i + kSmooth);
           ++j) {
        for (int c = std::max(0, b - kSmoothBands);
             c <= std::min(kBands - 1, b + kSmoothBands); ++c) {
          n_min += widest[j].n_min[c];
          n_max += widest[j].n_max[c];
          ++count;
        }
      }
      smooth[i].n_min[b] = n_min / count;
      smooth[i].n_max[b] = n_max / count;
    }
    for (int j = std::max(0, i - kSmoothFar); j <= std::min(stations - 1, i + kSmoothFar);
         ++j) {
      far += widest[j].far;
      ++count_far;
    }
    smooth[i].far = far / count_far;
  }
  // The gingiva over the alveolar process: a share of the arch's gingiva is
  // the tooth about its CEJ, the sulcus and the gingiva's thickness wide
  // (buccal and lingual). At the crest the jaw is 0.2 mm narrower, so its top
  // edge stays hidden in the gingiva, whose wall draws in below the crest; the
  // jaw's mucosa comes out of the gingiva just below the crest along one line
  // (the mucogingival junction) and falls back to the bone's width over 4 mm.
  // Where no tooth stands (the ends), no flare.
  // (each tooth's gingiva as thick as GingivaThicknessMm gives it; the
  // band's faces between teeth are set in 0.5 mm from the collars)
  auto gingiva_out = [&](std::size_t k) {
    return GingivaParams{}.gap_mm + GingivaThicknessMm(teeth.placed[k].tooth) - 0.2;
  };
  auto band_out = [&](std::size_t k) {
    return GingivaParams{}.gap_mm + GingivaThicknessMm(teeth.placed[k].tooth) - 0.5;
  };
  constexpr double kFlareMm = 4.0;
  std::vector<double> gum_in(stations, 0), gum_out(stations, 0);
  {
    // Each tooth's points about its CEJ, where a share takes its width.
    std::vector<std::vector<Vector3>> cervix(teeth.placed.size());
    for (std::size_t k = 0; k < teeth.placed.size(); ++k) {
      const RigidTransform X_TW = teeth.placed[k].X_WT.inverse();
      for (const Vector3& v : teeth.meshes[k].vertices()) {
        const double z_T = (X_TW * v).z();
        if (z_T >= -0.5 && z_T <= 1.5) cervix[k].push_back(v);
      }
    }
    std::vector<double> in(stations, 1e9), out(stations, -1e9);
    for (std::size_t k = 0; k < teeth.placed.size(); ++k) {
      for (const Vector3& v : cervix[k]) {
        const int i = station_of(curve.Project(v, teeth.s[k]));
        for (int j = std::max(0, i - 1); j <= std::min(stations - 1, i + 1); ++j) {
          const double n =
              (v - curve.Point(station_s(j))).dot(curve.Normal(station_s(j)));
          in[j] = std::min(in[j], n - gingiva_out(k));
          out[j] = std::max(out[j], n + gingiva_out(k));
        }
      }
    }
    // Between two teeth the gingiva's buccal and lingual faces run straight
    // from one tooth's outer extent to the next's (square to the line between
    // the two), wider than either tooth near its contact: the jaw's top
    // follows those lines too, 0.5 mm inside them.
    std::vector<double> face_in(stations, 1e9), face_out(stations, -1e9);
    for (std::size_t m = 0; m + 1 < by_s.size(); ++m) {
      const std::size_t k = by_s[m], l = by_s[m + 1];
      const Vector3 ck = teeth.placed[k].X_WT.translation(),
                    cl = teeth.placed[l].X_WT.translation();
      const Eigen::Vector2d e = (cl - ck).head<2>().normalized();
      for (const double side : {1.0, -1.0}) {
        const Vector3 perp = side * Vector3(-e.y(), e.x(), 0);
        auto extent = [&](std::size_t t, const Vector3& c) {
          double most = -1e9;
          for (const Vector3& v : cervix[t]) most = std::max(most, (v - c).dot(perp));
          return c + (most + band_out(t)) * perp;
        };
        const Vector3 pk = extent(k, ck), pl = extent(l, cl);
        for (int q = 0; q <= 20; ++q) {
          const Vector3 p = pk + (pl - pk) * (q / 20.0);
          const int i = station_of(curve.Project(p, 0.5 * (teeth.s[k] + teeth.s[l])));
          if (i < 0 || i >= stations) continue;
          const double n =
              (p - curve.Point(station_s(i))).dot(curve.Normal(station_s(i)));
          face_in[i] = std::min(face_in[i], n);
          face_out[i] = std::max(face_out[i], n);
        }
      }
    }
    for (int i = 0; i < stations; ++i) {
      double a = 0, b = 0, w = 0;
      for (int j = std::max(0, i - 2); j <= std::min(stations - 1, i + 2); ++j) {
        if (out[j] < -1e8 && face_out[j] < -1e8) continue;
        a += std::min(in[j], face_in[j]);
        b += std::max(out[j], face_out[j]);
        w += 1;
      }
      if (w == 0) continue;
      // How much wider than the bone (smoothed section) on each side; fading
      // out where the stations near it hold no tooth.
      const double have = w / (std::min(stations - 1, i + 2) - std::max(0, i - 2) + 1);
      gum_in[i] = have * std::max(0.0, smooth[i].n_min[0] - 1.5 - a / w);
      gum_out[i] = have * std::max(0.0, b / w - smooth[i].n_max[0] - 1.5);
    }
  }
  std::vector<std::vector<Vector3>> rings;
  for (int i = 0; i < stations; ++i) {
    const double s = station_s(i);
    const Extent& e = smooth[i];
    const double top = crest[i];
    // The bone's far edge: 2.5 mm past the deepest apex; its near edge, the crest.
    const double far = sign * (e.far + 2.5);
    Vector3 origin = curve.Point(s);
    origin.z() = 0;
    // Tapered and rounded at both ends of the arch.
    const double taper =
        std::min(1.0, std::sqrt(std::max(0.05, (end - std::abs(s)) / 4.0)));
    // The bone's faces at depth h below the crest, 1.5 mm outside the roots
    // there (interpolated between the bands' middles).
    auto faces = [&](double h, double& lo, double& hi) {
      const double x = std::clamp(h / kBandMm - 0.5, 0.0, kBands - 1.0);
      const int b = std::min(kBands - 2, static_cast<int>(x));
      const double t = x - b;
      lo = e.n_min[b] + t * (e.n_min[b + 1] - e.n_min[b]) - 1.5;
      hi = e.n_max[b] + t * (e.n_max[b + 1] - e.n_max[b]) + 1.5;
    };
    double lo_far, hi_far;
    faces(std::abs(far - top), lo_far, hi_far);
    // The section: down the outer (buccal) side from the crest to the far
    // edge, rounded there, and up the inner side; the flat top at the crest.
    const Vector3 u = curve.Normal(s);
    const double depth = std::abs(far - top),
                 round = std::min({3.0, 0.5 * (hi_far - lo_far) * taper, 0.5 * depth});
    constexpr int kSide = 28;
    std::vector<Vector3> ring;
    for (int side = 0; side < 2; ++side) {
      for (int j = 0; j < kSide; ++j) {
        const int jj =
            side == 0 ? j : kSide - 1 - j;  // outer: crest to far; inner: far to crest
        const double h = depth * std::pow(jj / (kSide - 1.0), 1.6);
        // (the flare under the gingiva leaves the crest straight down, in line
        // with the gingiva's face, and curves in to the bone over kFlareMm)
        const double f = 1 - SmoothStep(h / kFlareMm);
        const double below_round = h - (depth - round);
        const double shrink =
            below_round > 0
                ? std::sqrt(std::max(0.0, 1 - std::pow(below_round / round, 2)))
                : 1.0;
        double lo, hi;
        faces(h, lo, hi);
        const double mid = 0.5 * (lo + hi),
                     w = 0.5 * (hi - lo) * taper * (0.15 + 0.85 * shrink);
        const double a = side == 0 ? mid + w + taper * gum_out[i] * f
                                   : mid - w - taper * gum_in[i] * f;
        ring.push_back(origin + a * u + Vector3(0, 0, top + sign * h));
      }
    }
    rings.push_back(std::move(ring));
  }
  TriangleMesh jaw = Loft(rings);
  // The bone between the roots of every multi-rooted tooth whose crest has
  // dropped below its furcation: as its classes leave it, and whole where
  // the scene gives none (class 0: the furcation not involved).
  for (const PlacedTooth& p : teeth.placed) {
    const auto drop = drops.find(p.tooth.fdi);
    if (drop == drops.end() || !FurcationAboveCrest(p.tooth.fdi, drop->second)) continue;
    const auto it = furcation.find(p.tooth.fdi);
    const std::optional<TriangleMesh> bone = InterradicularBone(
        p.tooth, drop->second,
        it == furcation.end() ? std::map<std::string, int>{} : it->second);
    if (bone) jaw = UniteSolids(jaw, PlacedMesh(p, *bone));
  }
  return jaw;
}

}  // namespace soft_tissue

using namespace soft_tissue;  // the shapes the soft tissues share

double FurcationRoofMm(int fdi) {
  const FdiTooth t = FdiTooth::Parse(fdi);
  if (Dimensions(t).roots < 2) return 0;
  static std::mutex mutex;
  static std::map<int, double> measured;  // by tooth type: both sides alike
  const int key = (t.upper() ? 10 : 30) + t.position;
  std::lock_guard lock(mutex);
  const auto it = measured.find(key);
  if (it != measured.end()) return it->second;
  return measured[key] = MeasureFurcationRoof(t);
}

bool FurcationAboveCrest(int fdi, double crest_drop_mm) {
  if (!FdiTooth::Valid(fdi)) return false;
  const double roof = FurcationRoofMm(fdi);  // (0: one root)
  return roof > 0 && roof + 0.3 <= crest_drop_mm - 0.1;
}

double CrestDropMm(double pocket_plus_recession_mm) {
  return std::max(1.5, pocket_plus_recession_mm - 0.5);
}

}  // namespace sulcus
