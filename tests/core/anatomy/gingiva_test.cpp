// The gingiva's geometry measured on its mesh: closed and oriented, the margin
// at each site, and the pocket floor at the scene's depth below it.
#include "core/anatomy/gingiva.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <vector>

#include "core/anatomy/mesh_contact.h"
#include "core/anatomy/soft_tissue.h"

namespace sulcus {
namespace {

// The highest crossing of the vertical line through (x, y) with the mesh
// (below `below`).
std::optional<double> TopHit(const TriangleMesh& mesh, double x, double y,
                             double below = 1e9) {
  std::optional<double> best;
  const auto& v = mesh.vertices();
  for (const auto& f : mesh.faces()) {
    const Vector3 &a = v[f[0]], &b = v[f[1]], &c = v[f[2]];
    const double d =
        (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    if (std::abs(d) < 1e-14) continue;
    const double u = ((x - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (y - a.y())) / d;
    const double w = ((b.x() - a.x()) * (y - a.y()) - (x - a.x()) * (b.y() - a.y())) / d;
    if (u < -1e-9 || w < -1e-9 || u + w > 1 + 1e-9)
      continue;  // an edge belongs to both faces
    const double z = a.z() + u * (b.z() - a.z()) + w * (c.z() - a.z());
    if (z < below && (!best || z > *best)) best = z;
  }
  return best;
}

TEST(Gingiva, PocketFloorLiesAtTheDepthBelowTheMarginMeasuredOnTheMesh) {
  // Every permanent tooth (third molars included), with pockets of 2 to 7 mm and
  // recession.
  std::vector<int> teeth;
  for (int q = 1; q <= 4; ++q)
    for (int p = 1; p <= 8; ++p) teeth.push_back(10 * q + p);
  for (int fdi : teeth) {
    const ToothModel tooth = GenerateTooth(fdi);
    GingivaParams p;
    p.pocket_mm = {3, 2, 7, 4, 5, 6};
    p.recession_mm = {1, 0, 0.5, 0, 2, 0};
    const GingivaModel g = GenerateGingiva(tooth, p);
    const MeshReport report = g.mesh.Check();
    EXPECT_TRUE(report.IsSolid()) << fdi;
    for (int s = 0; s < 6; ++s) {
      const double th = g.site_angle[s];
      const Vector3 dir(std::cos(th), std::sin(th), 0);
      // In the sulcus (the site point): the first surface from above is the floor.
      const auto floor = TopHit(g.mesh, g.margin[s].x(), g.margin[s].y());
      ASSERT_TRUE(floor) << fdi << " site " << s;
      // Just outside the sulcus' wall: the top of the gingiva is the margin.
      const Vector3 wall = g.margin[s] + (0.5 * p.gap_mm + 0.02) * dir;
      const auto margin = TopHit(g.mesh, wall.x(), wall.y());
      ASSERT_TRUE(margin);
      EXPECT_NEAR(*margin, g.margin[s].z(), 0.1)
          << "the site lies on the margin; tooth " << fdi << " site " << s;
      EXPECT_NEAR(*margin - *floor, p.pocket_mm[s], 0.1)
          << "tooth " << fdi << " site " << s;
      // The probe tip (0.5 mm across) fits: no point of the tooth comes within
      // 0.25 mm of the site's vertical line between the margin and the floor.
      double closest = 1e9;
      for (const Vector3& v : tooth.mesh.vertices())
        if (v.z() >= *floor && v.z() <= *margin)
          closest = std::min(
              closest, std::hypot(v.x() - g.margin[s].x(), v.y() - g.margin[s].y()));
      EXPECT_GE(closest, 0.25) << "tooth " << fdi << " site " << s;
    }
  }
}

// The gingiva measures its tooth with thousands of horizontal rays; OuterRadii
// tests only the faces at a ray's height and must answer exactly as the scan
// of every face does, hits, misses and the heights past the tooth's ends.
TEST(Gingiva, OuterRadiiAnswerAsTheScanOfEveryFaceDoes) {
  for (const int fdi : {11, 36, 47}) {
    const ToothModel tooth = GenerateTooth(fdi);
    const OuterRadii radii(tooth.mesh);
    const Aabb box = tooth.mesh.Bounds();
    int hits = 0, misses = 0;
    for (int a = 0; a < 37; ++a) {
      const double th = 2 * std::numbers::pi * a / 37;
      for (int k = -3; k <= 83; ++k) {
        const double z = box.min.z() + (box.max.z() - box.min.z()) * k / 80.0;
        const double scan = OuterRadius(tooth.mesh, th, z);
        ASSERT_EQ(radii.At(th, z), scan) << fdi << " at " << th << ", " << z;
        (scan > 0 ? hits : misses) += 1;
      }
    }
    EXPECT_GT(hits, 2000) << fdi;  // of 3,219 rays (a molar's miss between its roots)
    EXPECT_GT(misses, 100) << fdi << ": above and below the tooth";
  }
  // And the same tooth again is the same tooth (GenerateTooth makes each once).
  const ToothModel a = GenerateTooth(36), b = GenerateTooth(36);
  EXPECT_EQ(a.mesh.vertices(), b.mesh.vertices());
  EXPECT_EQ(a.cej, b.cej);
  EXPECT_NE(GenerateTooth(36, {.resolution = 3}).mesh.num_faces(), a.mesh.num_faces());
}

TEST(Gingiva, MarginFollowsTheCejAndRecession) {
  const ToothModel tooth = GenerateTooth(46);
  GingivaParams p;
  const GingivaModel healthy = GenerateGingiva(tooth, p);
  p.recession_mm = {0, 2, 0, 0, 0, 0};
  const GingivaModel receded = GenerateGingiva(tooth, p);
  EXPECT_NEAR(healthy.margin[1].z() - receded.margin[1].z(), 2.0, 1e-9);
  // 1.5 mm above the CEJ at the buccal site (the CEJ point at 90 degrees).
  EXPECT_NEAR(healthy.margin[1].z(), tooth.cej[18].z() + 1.5, 1e-9);
  p.pocket_mm = {2, 2, 2, 2, 14.5, 2};
  EXPECT_THROW(GenerateGingiva(tooth, p), std::invalid_argument);
}

// The gingiva over the cervix is as thick as the tooth's place in the mouth
// makes it unless the parameters say: 1.0 mm buccally over an incisor, 1.2
// over a canine, 1.5 over a molar (measured on the tables: from the sulcus'
// outer wall to the collar's outer face at the buccal site).
TEST(Gingiva, ThicknessFollowsTheToothUnlessGiven) {
  for (const auto& [fdi, mm] : std::vector<std::pair<int, double>>{
           {11, 1.0}, {31, 1.0}, {13, 1.2}, {45, 1.5}, {46, 1.5}}) {
    const GingivaModel g = GenerateGingiva(GenerateTooth(fdi), {});
    const int buccal = g.SegmentAt(g.site_angle[1]);
    EXPECT_NEAR(g.outer_r[buccal] - g.wall_r[buccal], mm, 1e-6) << fdi;
  }
  GingivaParams p;
  p.thickness_mm = 2.0;
  const GingivaModel given = GenerateGingiva(GenerateTooth(11), p);
  const int buccal = given.SegmentAt(given.site_angle[1]);
  EXPECT_NEAR(given.outer_r[buccal] - given.wall_r[buccal], 2.0, 1e-6);
  p.thickness_mm = -1;
  EXPECT_THROW(GenerateGingiva(GenerateTooth(11), p), std::invalid_argument);
}

TEST(SoftTissue, EveryPieceIsASolid) {
  for (const std::string& name : SoftTissueNames()) {
    const TriangleMesh m = MakeSoftTissue(name);
    EXPECT_TRUE(m.Check().IsSolid()) << name;
  }
  EXPECT_THROW(MakeSoftTissue("uvula"), std::invalid_argument);
}

}  // namespace
}  // namespace sulcus

// Findings on the anatomy (core/anatomy/findings.h).
#include "core/anatomy/findings.h"

namespace sulcus {
namespace {

TEST(Findings, CariesSitsOnTheSurfaceItNames) {
  const ToothModel molar = GenerateTooth(36);
  const Vector3 occlusal = CariesCentre(molar, ToothSurface::kOcclusal);
  const Vector3 mesial = CariesCentre(molar, ToothSurface::kMesial);
  const Vector3 distal = CariesCentre(molar, ToothSurface::kDistal);
  const Vector3 buccal = CariesCentre(molar, ToothSurface::kBuccal);
  const Vector3 lingual = CariesCentre(molar, ToothSurface::kLingual);
  EXPECT_GT(occlusal.z(), 0.6 * molar.dimensions.crown_height);
  EXPECT_LT(std::hypot(occlusal.x(), occlusal.y()), 2.0);  // in the central fossa
  EXPECT_GT(mesial.x(), 0.4 * molar.dimensions.md_crown);
  EXPECT_LT(distal.x(), -0.4 * molar.dimensions.md_crown);
  EXPECT_GT(buccal.y(), 0.3 * molar.dimensions.bl);
  EXPECT_LT(lingual.y(), -0.3 * molar.dimensions.bl);
  for (const Vector3* p : {&mesial, &distal, &buccal, &lingual}) {
    EXPECT_GT(p->z(), 0.0);  // on the crown, above the CEJ
    EXPECT_LT(p->z(), molar.dimensions.crown_height);
  }
  // A 2 mm occlusal lesion covers the vertices within 2 mm of its centre and no other.
  const std::vector<double> cover = CariesCoverage(molar, {0, 0, 0, 0, 2.0});
  int covered = 0;
  for (std::size_t i = 0; i < cover.size(); ++i) {
    const double d = (molar.mesh.vertices()[i] - occlusal).norm();
    EXPECT_EQ(cover[i] > 0, d < 2.0) << i;
    covered += cover[i] > 0;
  }
  EXPECT_GT(covered, 5);
}

TEST(Findings, InflammationAtTheNamedSitesOnly) {
  const GingivaModel g = GenerateGingiva(GenerateTooth(46));
  const std::vector<double> w = InflammationCoverage(
      g.mesh.vertices(), {false, true, false, false, false, false});  // B
  for (std::size_t i = 0; i < w.size(); ++i) {
    const Vector3& v = g.mesh.vertices()[i];
    const double th = std::atan2(v.y(), v.x());  // B is at +pi/2
    if (std::abs(th - std::numbers::pi / 2) < 0.2) {
      EXPECT_EQ(w[i], 1.0);
    }
    if (v.y() < 0) {
      EXPECT_EQ(w[i], 0.0);  // nothing on the lingual side
    }
  }
}

}  // namespace
}  // namespace sulcus

#include "core/anatomy/mesh_contact.h"

namespace sulcus {
namespace {

TEST(Findings, CalculusSitsOnTheToothAboveOrInTheSulcus) {
  const ToothModel tooth = GenerateTooth(31);
  const GingivaModel g = GenerateGingiva(tooth);
  for (int site : {1, 4, 5}) {
    for (bool sub : {false, true}) {
      const TriangleMesh c = MakeCalculus(tooth, &g, site, sub);
      ASSERT_TRUE(c.Check().IsSolid());
      // Attached to the tooth (the meshes meet) and standing out of it.
      EXPECT_TRUE(MeshesIntersect(c, tooth.mesh)) << site << sub;
      const std::vector<bool> inside = InsideSolid(tooth.mesh, c.vertices());
      EXPECT_GT(std::count(inside.begin(), inside.end(), false), 10) << site << sub;
      // At its site, above the margin or between floor and margin.
      Vector3 centre = Vector3::Zero();
      for (const Vector3& v : c.vertices()) centre += v;
      centre /= static_cast<double>(c.num_vertices());
      const double th = std::atan2(centre.y(), centre.x());
      EXPECT_LT(std::abs(std::remainder(th - SiteAngles()[site], 2 * std::numbers::pi)),
                0.05)
          << site;
      if (sub) {
        EXPECT_GT(centre.z(), g.floor[site].z()) << site;
        EXPECT_LT(centre.z(), g.margin[site].z()) << site;
      } else {
        EXPECT_GT(centre.z(), g.margin[site].z()) << site;
      }
    }
  }
}

}  // namespace
}  // namespace sulcus

#include <random>

#include "core/anatomy/arch.h"

namespace sulcus {
namespace {

// The lower arch's teeth 44, 45, 46 and 47 with their collars, and the map
// between neighbours' frames as the scene builds it.
struct ArchRun {
  std::vector<PlacedTooth> placed;
  std::vector<ToothModel> teeth;
  std::vector<GingivaModel> collars;
  std::vector<GingivaParams> params;
  // 44 to 47, with these sites' pockets and recession (44's, 45's, 46's, 47's), or the
  // defaults.
  explicit ArchRun(const std::vector<GingivaParams>& given = {}) {
    for (const PlacedTooth& p : PlaceArch(false))
      if (p.tooth.fdi >= 44 && p.tooth.fdi <= 47) placed.push_back(p);
    for (std::size_t k = 0; k < placed.size(); ++k) {
      teeth.push_back(GenerateTooth(placed[k].tooth.fdi));
      const auto at = static_cast<std::size_t>(placed[k].tooth.fdi - 44);
      params.push_back(at < given.size() ? given[at] : GingivaParams{});
      collars.push_back(GenerateGingiva(teeth.back(), params.back()));
    }
  }
  // The teeth `fdis` of one arch (in arch order), with default collars.
  ArchRun(bool upper, const std::vector<int>& fdis) {
    for (const PlacedTooth& p : PlaceArch(upper))
      if (std::find(fdis.begin(), fdis.end(), p.tooth.fdi) != fdis.end())
        placed.push_back(p);
    for (const PlacedTooth& p : placed) {
      teeth.push_back(GenerateTooth(p.tooth.fdi));
      params.emplace_back();
      collars.push_back(GenerateGingiva(teeth.back(), params.back()));
    }
  }
  GingivaNeighbour Link(std::size_t i, std::size_t j) const {
    auto mirror = [&](std::size_t k) {
      return Matrix3(Vector3(placed[k].mirrored ? -1 : 1, 1, 1).asDiagonal());
    };
    GingivaNeighbour n;
    n.tooth = &teeth[j];
    n.gingiva = &collars[j];
    const Matrix3 Rt = placed[j].X_WT.rotation().transpose();
    n.A = mirror(j) * Rt * placed[i].X_WT.rotation() * mirror(i);
    n.b = mirror(j) * Rt * (placed[i].X_WT.translation() - placed[j].X_WT.translation());
    return n;
  }
  std::vector<GingivaNeighbour> Links(std::size_t i) const {
    std::vector<GingivaNeighbour> v;
    if (i > 0) v.push_back(Link(i, i - 1));
    if (i + 1 < placed.size()) v.push_back(Link(i, i + 1));
    return v;
  }
};

TEST(Gingiva, ArchSharesAreSolidsThatMeetFaceToFace) {
  const ArchRun arch;
  ASSERT_EQ(arch.placed.size(), 4u);
  std::vector<TriangleMesh> shares;
  for (std::size_t i = 0; i < arch.placed.size(); ++i) {
    const GingivaModel g = GenerateGingiva(arch.teeth[i], {}, arch.Links(i));
    shares.push_back(g.mesh);
    EXPECT_TRUE(g.mesh.Check().IsSolid()) << arch.placed[i].tooth.fdi;
    EXPECT_GT(g.mesh.num_faces(), 1000u);
    // The site truth is the collar's.
    for (int s = 0; s < 6; ++s) EXPECT_EQ(g.floor[s], arch.collars[i].floor[s]);
  }
  // Near each cut the two shares' fields agree at the same point: the
  // gingiva is one tissue across it, with no step or crack.
  std::mt19937 rng(7);
  for (std::size_t i = 0; i + 1 < arch.placed.size(); ++i) {
    const std::vector<GingivaNeighbour> li = arch.Links(i), lj = arch.Links(i + 1);
    const GingivaShareField fi(arch.teeth[i], arch.collars[i], li),
        fj(arch.teeth[i + 1], arch.collars[i + 1], lj);
    const GingivaNeighbour to_j = arch.Link(i, i + 1);
    const std::vector<GingivaNeighbour> only{to_j};
    const GingivaShareField cut_ij(arch.teeth[i], arch.collars[i], only);
    std::uniform_real_distribution<double> u(0, 1);
    int near = 0, tissue = 0;
    double worst = 0;
    for (int k = 0; k < 40000; ++k) {
      const Aabb& b = fi.box();
      const Vector3 p =
          b.min + Vector3(u(rng), u(rng), u(rng)).cwiseProduct(b.max - b.min);
      if (std::abs(cut_ij.Cut(p)) > 0.3) continue;
      ++near;
      const double a = fi.Uncut(p), c = fj.Uncut(to_j.A * p + to_j.b);
      tissue += a < 0;
      // (within 1 mm of the surface, where the isosurface is drawn: farther
      // out the fillets may fold in a third tooth's terms on one side only)
      if (std::min(std::abs(a), std::abs(c)) < 1.0)
        worst = std::max(worst, std::abs(a - c));
    }
    EXPECT_GT(near, 500);
    EXPECT_GT(tissue, 20) << "the gingiva reaches the cut";
    EXPECT_LT(worst, 0.02) << arch.placed[i].tooth.fdi << "|"
                           << arch.placed[i + 1].tooth.fdi;

    // The two meshes end on the cut in the same rim: each rim vertex of one
    // lies on the other's rim (each is its own share's surface cut exactly by
    // the plane and brought onto the field there; the rims differ only by
    // the chords between their vertices).
    const GingivaShareField::CutPlane c = cut_ij.cuts().front();
    auto rim = [&](const TriangleMesh& m, bool other) {
      std::vector<std::pair<Vector3, Vector3>> edges;
      auto here = [&](const Vector3& v) {
        return other ? Vector3(to_j.A.transpose() * (v - to_j.b)) : v;
      };
      auto on = [&](const Vector3& v) {
        return std::abs((v - c.q).dot(c.normal)) < 1e-6;
      };
      for (const TriangleMesh::Face& f : m.faces())
        for (int k = 0; k < 3; ++k) {
          const Vector3 a = here(m.vertices()[f[k]]),
                        b = here(m.vertices()[f[(k + 1) % 3]]);
          if (on(a) && on(b) && f[k] < f[(k + 1) % 3]) edges.emplace_back(a, b);
        }
      return edges;
    };
    const auto rim_i = rim(shares[i], false), rim_j = rim(shares[i + 1], true);
    ASSERT_GT(rim_i.size(), 20u);
    ASSERT_GT(rim_j.size(), 20u);
    auto to_segment = [](const Vector3& p, const std::pair<Vector3, Vector3>& e) {
      const Vector3 d = e.second - e.first;
      const double t =
          std::clamp((p - e.first).dot(d) / std::max(d.squaredNorm(), 1e-18), 0.0, 1.0);
      return (p - e.first - t * d).norm();
    };
    // (every vertex on the plane is on the rim: the caps are triangulated
    // without inner points; the cap's own edges join rim vertices too)
    std::vector<std::array<double, 3>> ends;
    for (const auto& e : rim_i)
      for (const Vector3& v : {e.first, e.second}) ends.push_back({v.x(), v.y(), v.z()});
    std::sort(ends.begin(), ends.end());
    ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
    int close = 0;
    double far = 0;
    for (const auto& a : ends) {
      const Vector3 v(a[0], a[1], a[2]);
      double best = 1e9;
      for (const auto& o : rim_j) best = std::min(best, to_segment(v, o));
      close += best < 0.02;
      far = std::max(far, best);
    }
    std::printf(
        "rim %d|%d: %d of %zu vertices within 0.02 mm of the other's rim, farthest %.3f "
        "mm\n",
        arch.placed[i].tooth.fdi, arch.placed[i + 1].tooth.fdi, close, ends.size(), far);
    // (a few where a move was taken back, or at the papilla's rolled tip,
    // where the field's gradient turns within a step)
    EXPECT_GT(close, 0.8 * static_cast<double>(ends.size()));
    EXPECT_LT(far, 0.2);
  }
}

TEST(Gingiva, ShareNormalsAreTheSurfacesAndAgreeAcrossTheSeam) {
  // A share's drawing normals (the gradient of its field) point out of its
  // surface as its faces do, and where two shares' rims meet, both take the
  // same normal there: the seam does not show in the shading.
  const ArchRun arch;
  std::vector<GingivaModel> shares;
  for (std::size_t i = 0; i < arch.placed.size(); ++i)
    shares.push_back(GenerateGingiva(arch.teeth[i], {}, arch.Links(i)));
  for (std::size_t i = 0; i < shares.size(); ++i) {
    const GingivaModel& g = shares[i];
    ASSERT_EQ(g.normals.size(), g.mesh.num_vertices());
    const std::vector<Vector3> sums = g.mesh.VertexNormalSums();
    const std::vector<ClipPlane> cuts =
        GingivaShareField(arch.teeth[i], arch.collars[i], arch.Links(i)).cuts();
    int unit = 0, along = 0, off_rim = 0;
    for (std::size_t v = 0; v < sums.size(); ++v) {
      const Vector3& n = g.normals[v];
      if (std::abs(n.norm() - 1) < 1e-9) ++unit;
      // (not at a rim, whose faces' mean turns halfway into the flat cap)
      const Vector3& p = g.mesh.vertices()[v];
      if (std::any_of(cuts.begin(), cuts.end(), [&](const ClipPlane& c) {
            return std::abs((p - c.q).dot(c.normal)) < 1e-6;
          }))
        continue;
      ++off_rim;
      if (n.dot(sums[v].normalized()) > 0.7) ++along;
    }
    std::printf(
        "share %d: %d of %zu normals unit, %d of %d off the rims within 45 degrees of "
        "the faces' mean\n",
        arch.placed[i].tooth.fdi, unit, sums.size(), along, off_rim);
    EXPECT_GT(unit, 0.99 * static_cast<double>(sums.size()));
    EXPECT_GT(along, 0.95 * off_rim);
  }
  // A collar (no neighbours) has none: it is drawn from its faces.
  EXPECT_TRUE(arch.collars[0].normals.empty());
  for (std::size_t i = 0; i + 1 < arch.placed.size(); ++i) {
    const GingivaNeighbour to_j = arch.Link(i, i + 1);
    const Matrix3 back = to_j.A.transpose();  // j's frame to i's
    const TriangleMesh& mi = shares[i].mesh;
    const TriangleMesh& mj = shares[i + 1].mesh;
    int pairs = 0, agree = 0;
    double worst_deg = 0;
    for (std::size_t a = 0; a < mi.num_vertices(); ++a) {
      const Vector3& p = mi.vertices()[a];
      for (std::size_t b = 0; b < mj.num_vertices(); ++b) {
        const Vector3 q = back * (mj.vertices()[b] - to_j.b);
        if ((p - q).norm() > 0.02) continue;
        ++pairs;
        const double c = std::clamp(
            shares[i].normals[a].dot(back * shares[i + 1].normals[b]), -1.0, 1.0);
        agree += c > std::cos(10 * std::numbers::pi / 180);
        worst_deg = std::max(worst_deg, std::acos(c) * 180 / std::numbers::pi);
      }
    }
    std::printf(
        "seam %d|%d: %d vertex pairs within 0.02 mm, %d with normals within 10 degrees, "
        "worst %.1f degrees\n",
        arch.placed[i].tooth.fdi, arch.placed[i + 1].tooth.fdi, pairs, agree, worst_deg);
    // (How many rim vertices coincide depends on the two shares' tessellation
    // and on the size of their caps: 12 to 20 per seam on today's teeth and
    // gingiva 1.5 mm thick; enough for the normals' agreement to be measured.)
    ASSERT_GE(pairs, 10);
    EXPECT_GT(agree, 0.9 * pairs);
  }
}

TEST(Gingiva, UnderAContactTheSulciMeetAboveTheCol) {
  // 45 and 46: halfway between 45's distal sulcus and 46's mesial one (under
  // their contact) the gingiva is open from above down to the col, and tissue
  // below it.
  const ArchRun arch;
  std::size_t i45 = 0, i46 = 0;
  for (std::size_t k = 0; k < arch.placed.size(); ++k) {
    if (arch.placed[k].tooth.fdi == 45) i45 = k;
    if (arch.placed[k].tooth.fdi == 46) i46 = k;
  }
  const std::vector<GingivaNeighbour> links = arch.Links(i45);
  const GingivaShareField f(arch.teeth[i45], arch.collars[i45], links);
  const GingivaNeighbour to46 = arch.Link(i45, i46);
  const Matrix3 back = to46.A.transpose();  // 46's frame to 45's
  const GingivaModel& g45 = arch.collars[i45];
  const GingivaModel& g46 = arch.collars[i46];
  const std::size_t distal =
      g45.sulcus_r.size() / 2;  // 45's distal is -x, 46's mesial +x
  const Vector3 d45(-g45.sulcus_r[distal], 0, g45.floor_z[distal]);
  const Vector3 m46 = back * (Vector3(g46.sulcus_r[0], 0, g46.floor_z[0]) - to46.b);
  Vector3 mid = 0.5 * (d45 + m46);
  const double col = std::max(d45.z(), m46.z()), deeper = std::min(d45.z(), m46.z());
  for (double above : {0.4, 1.0, 2.0}) {
    mid.z() = col + above;
    EXPECT_GT(f.Uncut(mid), 0) << "open " << above << " mm above the col";
  }
  mid.z() = deeper - 0.4;
  EXPECT_LT(f.Uncut(mid), 0) << "tissue below the col";
}

TEST(Gingiva, OnTheArchEverySiteReadsItsOwnDepthBesideADeeperNeighbour) {
  // The probing scene's sextant: interproximal pockets that differ across
  // each contact (44 D 2 mm next to 45 M 3 mm, 45 D 4 next to 46 M 5, 46 D 7
  // next to 47 M 6). At every site point, the first surface below the margin
  // on the shares (this tooth's and its neighbours', which hold the far side
  // of each cut) is the site's own floor; and where a probe walks under the
  // contact from a site toward the cut, the floor never falls past the
  // deeper of the two floors.
  auto params = [](std::array<double, 6> pocket, std::array<double, 6> recession) {
    GingivaParams p;
    p.pocket_mm = pocket;
    p.recession_mm = recession;
    return p;
  };
  const ArchRun arch({params({2, 1, 2, 2, 2, 2}, {}), params({3, 2, 4, 3, 2, 3}, {}),
                      params({5, 4, 7, 5, 4, 6}, {1, 1, 1, 0, 0, 0}),
                      params({6, 4, 5, 4, 3, 5}, {})});
  std::vector<TriangleMesh> shares;
  for (std::size_t i = 0; i < arch.placed.size(); ++i)
    shares.push_back(GenerateGingiva(arch.teeth[i], arch.params[i], arch.Links(i)).mesh);
  for (std::size_t i = 0; i < arch.placed.size(); ++i) {
    // This tooth's share and its neighbours', in this tooth's frame.
    std::vector<TriangleMesh> here{shares[i]};
    for (std::size_t j : {i - 1, i + 1}) {
      if (j >= arch.placed.size()) continue;
      const GingivaNeighbour to = arch.Link(i, j);  // this frame to j's
      TriangleMesh m = shares[j];
      m.Transform(to.A.transpose(), -(to.A.transpose() * to.b));
      here.push_back(std::move(m));
    }
    const GingivaModel& g = arch.collars[i];
    const std::vector<GingivaNeighbour> links = arch.Links(i);
    const GingivaShareField field(arch.teeth[i], arch.collars[i],
                                  links);  // (for its cuts)
    for (int s = 0; s < 6; ++s) {
      std::optional<double> floor;
      for (const TriangleMesh& m : here) {
        const auto h = TopHit(m, g.margin[s].x(), g.margin[s].y(), g.margin[s].z() - 0.3);
        if (h && (!floor || *h > *floor)) floor = h;
      }
      ASSERT_TRUE(floor) << arch.placed[i].tooth.fdi << " site " << s;
      // (0.2 mm: the shares are sampled on a 0.3 mm grid with their edges
      // rounded, and the floor falls steeply from the cut to a deeper site)
      EXPECT_NEAR(g.margin[s].z() - *floor, g.margin[s].z() - g.floor[s].z(), 0.2)
          << "tooth " << arch.placed[i].tooth.fdi << " site " << s;
      // Just outside the sulcus' wall, seen from the buccal or lingual side
      // (where a student looks), the top of the gingiva is the site's margin,
      // its edge rounded and falling 0.4 mm per mm outward: what the probe's
      // marks are read against. (0.3 mm out: the wall on the 0.3 mm grid may
      // lie a few hundredths from where the field has it. Straight out from a
      // line angle beside a contact would be the neighbour's sulcus.)
      const Vector3 dir(0, s < 3 ? 1 : -1, 0);
      const double out =
          (0.5 * arch.params[i].gap_mm + 0.3) / std::abs(std::sin(g.site_angle[s]));
      const Vector3 wall = g.margin[s] + out * dir;
      std::optional<double> top;
      for (const TriangleMesh& m : here) {
        const auto h = TopHit(m, wall.x(), wall.y());
        if (h && (!top || *h > *top)) top = h;
      }
      ASSERT_TRUE(top) << arch.placed[i].tooth.fdi << " site " << s;
      const double th = std::atan2(wall.y(), wall.x());
      const double beyond = std::hypot(wall.x(), wall.y()) - g.wall_r[g.SegmentAt(th)];
      const double expected = g.margin[s].z() - 0.4 * beyond;
      // A site within half a millimetre of a cut lies under the contact,
      // where the margin beside it is the papilla's, up to a millimetre higher.
      const bool under_contact =
          field.Cut(g.margin[s]) > -GingivaShareField::kUnderContactMm;
      std::printf(
          "margin %d site %d: mesh %.2f expected %.2f%s (truth %.2f, %.2f mm beyond the "
          "wall, %.2f mm from the cut)\n",
          arch.placed[i].tooth.fdi, s, *top, expected, under_contact ? " to +1" : "",
          g.margin[s].z(), beyond, -field.Cut(g.margin[s]));
      EXPECT_GE(*top, expected - 0.25)
          << "tooth " << arch.placed[i].tooth.fdi << " site " << s;
      EXPECT_LE(*top, expected + (under_contact ? 1.0 : 0.25))
          << "tooth " << arch.placed[i].tooth.fdi << " site " << s;
    }
    // Under each contact (from the line angles' sites to the contact, along
    // the sulcus' middle): a floor everywhere, never below the deeper
    // tooth's deepest floor.
    double deepest = 1e9;
    for (int s = 0; s < 6; ++s) deepest = std::min(deepest, g.floor[s].z());
    for (std::size_t j : {i - 1, i + 1}) {
      if (j >= arch.placed.size()) continue;
      const GingivaNeighbour to = arch.Link(i, j);
      for (int s = 0; s < 6; ++s)
        deepest =
            std::min(deepest, (to.A.transpose() * (arch.collars[j].floor[s] - to.b)).z());
    }
    const int n = static_cast<int>(g.sulcus_r.size());
    for (int k = 0; k < n; ++k) {
      const double th = 2 * std::numbers::pi * k / n, c = std::cos(th);
      if (std::abs(c) < std::cos(std::numbers::pi / 4) - 1e-9)
        continue;  // buccal and lingual: above
      if ((c > 0 && i == 0) || (c < 0 && i + 1 == arch.placed.size()))
        continue;  // no neighbour that way
      const double r = g.sulcus_r[k];
      std::optional<double> floor;
      for (const TriangleMesh& m : here) {
        const auto h = TopHit(m, r * c, r * std::sin(th), g.margin_z[k] - 0.3);
        if (h && (!floor || *h > *floor)) floor = h;
      }
      ASSERT_TRUE(floor) << arch.placed[i].tooth.fdi << " at "
                         << th * 180 / std::numbers::pi << " degrees";
      EXPECT_GE(*floor, deepest - 0.15) << arch.placed[i].tooth.fdi << " at "
                                        << th * 180 / std::numbers::pi << " degrees";
    }
  }
}

}  // namespace
}  // namespace sulcus

namespace sulcus {
namespace {

// Between the central incisors the arch's mirror lies between the two teeth's
// frames (one tooth is placed mirrored, the other not). The interdental
// band's labial face must join the labial sides of both teeth: when it joined
// one tooth's labial side to the other's lingual, it slanted across the
// midline and cut a V-notch down the papilla's face (here up to 0.6 mm
// deeper at the midline than 1 mm beside it; now at most 0.2 mm, a shallow
// interdental groove).
// Measured on the shares' fields from in front at heights between the
// CEJ and the papilla's tip: how far out the gingiva reaches at the midline
// and 1 mm either side of it.
TEST(Gingiva, TheMidlinePapillaHasNoNotch) {
  for (const bool upper : {true, false}) {
    const ArchRun arch(upper,
                       upper ? std::vector<int>{11, 21} : std::vector<int>{41, 31});
    const std::vector<PlacedTooth>& placed = arch.placed;
    ASSERT_EQ(placed.size(), 2u);
    ASSERT_NE(placed[0].mirrored, placed[1].mirrored);
    const std::vector<GingivaNeighbour> links[2] = {arch.Links(0), arch.Links(1)};
    const GingivaShareField fields[2] = {{arch.teeth[0], arch.collars[0], links[0]},
                                         {arch.teeth[1], arch.collars[1], links[1]}};
    // (the world's x = 0 is the midline; +y labial, the crowns toward z = 0)
    const double cej_z =
        0.5 * (placed[0].X_WT.translation().z() + placed[1].X_WT.translation().z());
    const double toward_crown = upper ? -1 : 1;
    auto outermost = [&](double x, double z) {
      const std::size_t k = (x < 0) == (placed[0].X_WT.translation().x() < 0) ? 0 : 1;
      const RigidTransform X_TW = placed[k].X_WT.inverse();
      const double y0 =
          upper ? 0.0 : -2.0;  // (the lower arch lies 2 mm behind the upper)
      for (double y = y0 + 6; y > y0 - 2; y -= 0.02)
        if (fields[k].Uncut(ArchMirror(placed[k].mirrored, X_TW * Vector3(x, y, z))) < 0)
          return y - y0;
      return -1e9;
    };
    int compared = 0;
    for (const double below_cej : {0.6, 0.8, 1.0, 1.2, 1.5, 1.9, 2.5}) {
      const double z = cej_z + toward_crown * below_cej;
      const double mid = outermost(0, z), left = outermost(-1, z),
                   right = outermost(1, z);
      if (left < -1e8 || right < -1e8) continue;  // (past the margin beside the papilla)
      ASSERT_GT(mid, -1e8) << "no gingiva at the midline " << below_cej
                           << " mm toward the crowns";
      std::printf(
          "%s %.1f mm toward the crowns from the CEJ: the gingiva reaches %.2f at the "
          "midline, %.2f and %.2f 1 mm either side\n",
          upper ? "11|21" : "41|31", below_cej, mid, left, right);
      EXPECT_GE(mid, std::min(left, right) - 0.3)
          << (upper ? "upper" : "lower") << " at " << below_cej << " mm";
      ++compared;
    }
    EXPECT_GE(compared, 3) << (upper ? "upper" : "lower");
  }
}

// The window draws the gingiva as the eye sees it: the same tissue with the
// sulcus closed round the tooth (GingivaSurface::kSeen). Along the path a
// probe tip walks around each tooth (the sulcus' middle, from 0.3 mm above
// the floor to 0.3 mm below the margin, interproximal sites under the
// contacts included), the felt gingiva leaves the tip its room and the seen
// one holds tissue (or the neighbour's tooth, where the path passes the
// contact): without this, the papillae were drawn as a labial and a lingual
// shell over a hollow col, and a dark line ran between every tooth and its margin.
TEST(Gingiva, TheSeenGingivaClosesTheSulcusAndFillsThePapillae) {
  const ArchRun runs[2] = {ArchRun(), ArchRun(true, {12, 11, 21, 22})};
  for (const ArchRun& arch : runs) {
    const std::size_t n = arch.placed.size();
    ASSERT_EQ(n, 4u);
    std::vector<TriangleMesh> seen;
    std::vector<std::vector<GingivaNeighbour>> links;
    for (std::size_t i = 0; i < n; ++i) links.push_back(arch.Links(i));
    for (std::size_t i = 0; i < n; ++i) {
      const GingivaModel g =
          GenerateGingiva(arch.teeth[i], {}, links[i], 0.3, GingivaSurface::kSeen);
      EXPECT_TRUE(g.mesh.Check().IsSolid()) << arch.placed[i].tooth.fdi;
      EXPECT_EQ(g.normals.size(), g.mesh.num_vertices());
      for (int s = 0; s < 6; ++s)
        EXPECT_EQ(g.floor[s], arch.collars[i].floor[s])
            << "the site truth is the felt gingiva's";
      seen.push_back(g.mesh);
    }
    for (std::size_t i = 0; i < n; ++i) {
      const GingivaModel& c = arch.collars[i];
      const GingivaShareField felt(arch.teeth[i], c, links[i]);
      const int segments = static_cast<int>(c.sulcus_r.size());
      // The path, in this tooth's frame.
      std::vector<Vector3> path;
      for (int k = 0; k < segments; ++k) {
        const double th = 2 * std::numbers::pi * k / segments;
        for (double z = c.floor_z[k] + 0.3; z <= c.margin_z[k] - 0.3; z += 0.25)
          path.emplace_back(c.sulcus_r[k] * std::cos(th), c.sulcus_r[k] * std::sin(th),
                            z);
      }
      ASSERT_GT(path.size(), 300u);
      std::vector<bool> held(path.size(), false);
      // In any share of the seen gingiva, or in a neighbour's tooth: each in its own
      // frame.
      for (std::size_t j = 0; j < n; ++j) {
        std::vector<Vector3> there = path;
        if (j != i) {
          const GingivaNeighbour to_j = arch.Link(i, j);
          for (Vector3& p : there) p = to_j.A * p + to_j.b;
        }
        const std::vector<bool> in_share = InsideSolid(seen[j], there);
        const std::vector<bool> in_tooth = j != i ? InsideSolid(arch.teeth[j].mesh, there)
                                                  : std::vector<bool>(there.size());
        for (std::size_t k = 0; k < path.size(); ++k)
          held[k] = held[k] || in_share[k] || in_tooth[k];
      }
      int open_felt = 0, closed_seen = 0;
      for (std::size_t k = 0; k < path.size(); ++k) {
        open_felt += felt.Uncut(path[k]) > 0;
        closed_seen += held[k];
      }
      const double m = static_cast<double>(path.size());
      std::printf(
          "%d: %zu points on the probe's path, %.1f %% open in the felt gingiva, %.1f %% "
          "closed in the seen one\n",
          arch.placed[i].tooth.fdi, path.size(), 100 * open_felt / m,
          100 * closed_seen / m);
      EXPECT_GT(open_felt, 0.95 * m)
          << arch.placed[i].tooth.fdi << ": the felt sulcus is open";
      EXPECT_GT(closed_seen, 0.95 * m)
          << arch.placed[i].tooth.fdi << ": the seen sulcus is closed";
      // The free gingiva thins to its margin in the seen gingiva: buccally and
      // lingually, 0.3 mm toward the root from the margin, from the tooth's
      // surface out to the gingiva's outer face (the felt one holds the sulcus
      // and its full thickness there).
      const GingivaShareField seen_field(arch.teeth[i], c, links[i],
                                         GingivaSurface::kSeen);
      for (const int site : {1, 4}) {
        const double th = c.site_angle[site], z = c.margin[site].z() - 0.3;
        const double r0 = OuterRadius(arch.teeth[i].mesh, th, z);
        auto thickness = [&](const GingivaShareField& f) {
          double outermost = -1;
          for (double r = r0; r < r0 + 4; r += 0.02)
            if (f.Uncut(Vector3(r * std::cos(th), r * std::sin(th), z)) < 0)
              outermost = r - r0;
          return outermost;
        };
        const double felt_t = thickness(felt), seen_t = thickness(seen_field);
        std::printf(
            "%d %s: the gingiva's outer face %.2f mm from the tooth 0.3 mm below the "
            "margin, felt %.2f\n",
            arch.placed[i].tooth.fdi, site == 1 ? "B" : "L", seen_t, felt_t);
        EXPECT_GT(felt_t, 1.5) << arch.placed[i].tooth.fdi << " site " << site;
        EXPECT_GT(seen_t, 0.2) << arch.placed[i].tooth.fdi << " site " << site;
        EXPECT_LT(seen_t, 1.0) << arch.placed[i].tooth.fdi << " site " << site;
      }
    }
  }
}

}  // namespace
}  // namespace sulcus
