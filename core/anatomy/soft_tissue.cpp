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
#include "core/anatomy/tooth.h"

namespace sulcus {
namespace {

constexpr double kPi = std::numbers::pi;

// One arch's occlusal curve as a function of signed arc length s (negative on
// the patient's right), with its tangent (toward +s) and outward normal.
class ArchCurve {
 public:
  ArchCurve(bool upper, const ArchParams& params) {
    points_.resize(2 * kHalf + 1);
    for (int i = 0; i <= 2 * kHalf; ++i) {
      const double s = (i - kHalf) * kStep;
      points_[i] = ArchPoint(upper, s < 0, std::abs(s), params);
    }
  }
  Vector3 Point(double s) const {
    const double x = std::clamp(s / kStep + kHalf, 0.0, 2.0 * kHalf - 1e-9);
    const int i = static_cast<int>(x);
    const double t = x - i;
    return (1 - t) * points_[i] + t * points_[i + 1];
  }
  Vector3 Tangent(double s) const {
    return (Point(s + 0.1) - Point(s - 0.1)).normalized();
  }
  Vector3 Normal(double s) const {  // horizontal, out of the arch (buccal)
    const Vector3 t = Tangent(s);
    return Vector3(-t.y(), t.x(), 0).normalized();
  }
  // The s whose curve point is nearest p (in plan), from a starting guess.
  double Project(const Vector3& p, double s0) const {
    double s = s0;
    for (int i = 0; i < 5; ++i) {
      Vector3 d = p - Point(s);
      d.z() = 0;
      s += d.dot(Tangent(s));
    }
    return s;
  }

 private:
  static constexpr int kHalf = 2000;     // samples each side of the midline
  static constexpr double kStep = 0.05;  // mm: the curve to 100 mm from the midline
  std::vector<Vector3> points_;
};

// A closed mesh through rings of equal size (each a closed loop), capped at
// both ends by a vertex at the ring's centroid; made outward.
TriangleMesh Loft(const std::vector<std::vector<Vector3>>& rings) {
  const int n = static_cast<int>(rings.size()),
            m = static_cast<int>(rings.front().size());
  std::vector<Vector3> v;
  std::vector<TriangleMesh::Face> f;
  auto centroid = [&](const std::vector<Vector3>& r) {
    Vector3 c = Vector3::Zero();
    for (const Vector3& p : r) c += p;
    return Vector3(c / static_cast<double>(r.size()));
  };
  v.push_back(centroid(rings.front()));
  for (const auto& r : rings) v.insert(v.end(), r.begin(), r.end());
  v.push_back(centroid(rings.back()));
  const int last = static_cast<int>(v.size()) - 1;
  auto id = [&](int ring, int i) { return 1 + ring * m + (i % m); };
  for (int i = 0; i < m; ++i) f.push_back({0, id(0, i + 1), id(0, i)});
  for (int k = 0; k + 1 < n; ++k) {
    for (int i = 0; i < m; ++i) {
      f.push_back({id(k, i), id(k, i + 1), id(k + 1, i + 1)});
      f.push_back({id(k, i), id(k + 1, i + 1), id(k + 1, i)});
    }
  }
  for (int i = 0; i < m; ++i) f.push_back({last, id(n - 1, i), id(n - 1, i + 1)});
  TriangleMesh mesh(std::move(v), std::move(f));
  if (mesh.Volume() < 0) mesh.FlipOrientation();
  return mesh;
}

// A rounded rectangle (superellipse of exponent e) spanning [u0, u1] along
// `u` and [z0, z1] along +z, about `origin`; m points, counter-clockwise.
std::vector<Vector3> Section(const Vector3& origin, const Vector3& u, double u0,
                             double u1, double z0, double z1, int m, double e = 4.0) {
  std::vector<Vector3> ring;
  const double cu = 0.5 * (u0 + u1), hu = 0.5 * (u1 - u0), cz = 0.5 * (z0 + z1),
               hz = 0.5 * (z1 - z0);
  for (int i = 0; i < m; ++i) {
    const double a = 2 * kPi * i / m, c = std::cos(a), s = std::sin(a);
    const double x = std::copysign(std::pow(std::abs(c), 2 / e), c),
                 y = std::copysign(std::pow(std::abs(s), 2 / e), s);
    ring.push_back(origin + (cu + hu * x) * u + Vector3(0, 0, cz + hz * y));
  }
  return ring;
}

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

// The placed teeth of an arch (no third molars) and their meshes, with each
// tooth's centre on the curve.
struct ArchTeeth {
  std::vector<PlacedTooth> placed;
  std::vector<TriangleMesh> meshes;
  std::vector<double> s;  // signed arc of each tooth's centre
};

ArchTeeth MakeTeeth(bool upper, const ArchParams& arch) {
  ArchTeeth t;
  t.placed = PlaceArch(upper, arch);
  for (const PlacedTooth& p : t.placed) {
    t.meshes.push_back(PlacedMesh(p, GenerateTooth(p.tooth.fdi, {.resolution = 3}).mesh));
    const bool right = p.tooth.quadrant == 1 || p.tooth.quadrant == 4;
    t.s.push_back((right ? -1 : 1) * ArchCentreMm(upper, p.tooth.position));
  }
  return t;
}

// The same arch's teeth are generated once per process: every soft tissue of a
// scene is shaped around them.
const ArchTeeth& Teeth(bool upper, const ArchParams& arch) {
  static std::mutex mutex;
  static std::map<std::tuple<bool, double, double, double, double, bool>, ArchTeeth> made;
  const auto key = std::tuple(upper, arch.k_lower, arch.k_upper,
                              arch.upper_lift_mm + arch.occlusion_mm,
                              arch.lower_setback_mm, arch.third_molars);
  std::lock_guard lock(mutex);
  auto it = made.find(key);
  if (it == made.end()) it = made.emplace(key, MakeTeeth(upper, arch)).first;
  return it->second;
}

// The last tooth's distal end, mm along the arch.
double ArchEnd(bool upper) { return ArchCentreMm(upper, 7) + 5.5; }

using Vector2 = Eigen::Vector2d;

// 0 below 0, 1 above 1, a cubic between with level ends.
double SmoothStep(double x) {
  const double t = std::clamp(x, 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

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

// The jaw of one arch: a bar along the curve whose section holds every root
// (1.5 mm of bone around it, 2.5 mm beyond the apex), its top at the crest;
// with the bone between the roots of a tooth whose furcation the scene
// involves (InterradicularBone).
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
    std::string list;
    for (const std::string& n : known) list += (list.empty() ? "" : ", ") + n;
    throw std::invalid_argument("unknown anatomy '" + name + "'; known: " + list);
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

const std::vector<std::string>& LesionKinds() {
  static const std::vector<std::string> kinds = {"ulcer", "leukoplakia", "erythroplakia"};
  return kinds;
}

std::vector<std::string> LesionRegions(const std::string& anatomy) {
  if (anatomy == "tongue")
    return {"dorsum", "lateral_border_left", "lateral_border_right", "ventral"};
  if (anatomy.rfind("jaw", 0) == 0) return {};
  return {"centre"};
}

Vector3 LesionCentre(const std::string& anatomy, const std::string& region,
                     const TriangleMesh& mesh) {
  return RegionSpot(anatomy, region, mesh).point;
}

SurfacePoint RegionSpot(const std::string& anatomy, const std::string& region,
                        const TriangleMesh& mesh) {
  const auto regions = LesionRegions(anatomy);
  if (std::find(regions.begin(), regions.end(), region) == regions.end())
    throw std::invalid_argument("'" + anatomy + "' has no region '" + region +
                                "' for a lesion");
  const std::vector<Vector3> normals = mesh.VertexNormalSums();
  const Aabb b = mesh.Bounds();
  const Vector3 mid = 0.5 * (b.min + b.max);
  const double length = b.max.y() - b.min.y();
  // The side facing the mouth and a point the lesion is nearest.
  Vector3 facing = Vector3::UnitZ(), anchor = mid;
  if (anatomy == "tongue") {
    if (region == "dorsum") {
      facing = Vector3::UnitZ();
      anchor = Vector3(0, b.max.y() - 0.3 * length, b.max.z());
    } else if (region == "ventral") {
      facing = -Vector3::UnitZ();
      anchor = Vector3(0, b.max.y() - 4, b.max.z() - 5);
    } else {
      const double side =
          region == "lateral_border_left" ? 1 : -1;  // the patient's left is +x
      facing = side * Vector3::UnitX();
      anchor = Vector3(side == 1 ? b.max.x() : b.min.x(), b.max.y() - 0.35 * length,
                       b.max.z() - 3);
    }
  } else if (anatomy == "cheek_left" || anatomy == "cheek_right") {
    const double side = anatomy == "cheek_left" ? 1 : -1;
    facing = -side * Vector3::UnitX();  // toward the midline
    anchor = Vector3(side == 1 ? b.min.x() : b.max.x(), mid.y(), mid.z());
  } else if (anatomy == "lip_upper" || anatomy == "lip_lower") {
    facing = -Vector3::UnitY();  // toward the teeth
    anchor = Vector3(0, b.min.y(), mid.z());
  } else if (anatomy == "palate" || anatomy == "soft_palate") {
    facing = -Vector3::UnitZ();
    anchor = Vector3(0, mid.y(), anatomy == "palate" ? b.max.z() : mid.z());
  } else if (anatomy == "floor_of_mouth") {
    facing = Vector3::UnitZ();
    anchor = Vector3(0, b.max.y(), b.max.z());
  }
  double best = std::numeric_limits<double>::infinity();
  SurfacePoint at{mid, facing};
  for (std::size_t i = 0; i < mesh.num_vertices(); ++i) {
    if (normals[i].norm() == 0 || normals[i].normalized().dot(facing) < 0.5) continue;
    const double d = (mesh.vertices()[i] - anchor).norm();
    if (d < best) {
      best = d;
      at = {mesh.vertices()[i], normals[i].normalized()};
    }
  }
  return at;
}

}  // namespace sulcus
