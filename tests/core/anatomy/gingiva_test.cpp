// The gingiva's geometry measured on its mesh: closed and oriented, the margin
// at each site, and the pocket floor at the scene's depth below it.
#include "core/anatomy/gingiva.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

#include "core/anatomy/soft_tissue.h"

namespace sulcus {
namespace {

// The highest crossing of the vertical line through (x, y) with the mesh.
std::optional<double> TopHit(const TriangleMesh& mesh, double x, double y) {
  std::optional<double> best;
  const auto& v = mesh.vertices();
  for (const auto& f : mesh.faces()) {
    const Vector3 &a = v[f[0]], &b = v[f[1]], &c = v[f[2]];
    const double d = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    if (std::abs(d) < 1e-14) continue;
    const double u = ((x - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (y - a.y())) / d;
    const double w = ((b.x() - a.x()) * (y - a.y()) - (x - a.x()) * (b.y() - a.y())) / d;
    if (u < -1e-9 || w < -1e-9 || u + w > 1 + 1e-9) continue;  // an edge belongs to both faces
    const double z = a.z() + u * (b.z() - a.z()) + w * (c.z() - a.z());
    if (!best || z > *best) best = z;
  }
  return best;
}

TEST(Gingiva, PocketFloorLiesAtTheDepthBelowTheMarginMeasuredOnTheMesh) {
  // Every permanent tooth (third molars included), with pockets of 2 to 7 mm and recession.
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
      EXPECT_NEAR(*margin, g.margin[s].z(), 0.1) << "the site lies on the margin; tooth " << fdi << " site " << s;
      EXPECT_NEAR(*margin - *floor, p.pocket_mm[s], 0.1) << "tooth " << fdi << " site " << s;
      // The probe tip (0.5 mm across) fits: no point of the tooth comes within
      // 0.25 mm of the site's vertical line between the margin and the floor.
      double closest = 1e9;
      for (const Vector3& v : tooth.mesh.vertices())
        if (v.z() >= *floor && v.z() <= *margin)
          closest = std::min(closest, std::hypot(v.x() - g.margin[s].x(), v.y() - g.margin[s].y()));
      EXPECT_GE(closest, 0.25) << "tooth " << fdi << " site " << s;
    }
  }
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

TEST(SoftTissue, EveryPieceIsASolid) {
  for (const std::string& name : SoftTissueNames()) {
    const TriangleMesh m = MakeSoftTissue(name);
    EXPECT_TRUE(m.Check().IsSolid()) << name;
  }
  EXPECT_THROW(MakeSoftTissue("uvula"), std::invalid_argument);
}

}  // namespace
}  // namespace sulcus
