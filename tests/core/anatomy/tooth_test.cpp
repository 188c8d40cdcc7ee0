#include "core/anatomy/tooth.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

namespace sulcus {
namespace {

// The mesh's extent along x or y over the crown (z > 0), or along x on the plane
// z = 0 (where edges cross it), measured on the mesh, not from the parameters.
double CrownWidth(const TriangleMesh& m, int axis) {
  double lo = 1e9, hi = -1e9;
  for (const Vector3& v : m.vertices()) {
    if (v.z() > 0) {
      lo = std::min(lo, v[axis]);
      hi = std::max(hi, v[axis]);
    }
  }
  return hi - lo;
}

double CervixWidth(const TriangleMesh& m) {
  double lo = 1e9, hi = -1e9;
  for (const auto& f : m.faces()) {
    for (int k = 0; k < 3; ++k) {
      const Vector3& a = m.vertices()[f[k]];
      const Vector3& b = m.vertices()[f[(k + 1) % 3]];
      if ((a.z() > 0) == (b.z() > 0)) continue;
      const Vector3 p = a + (b - a) * (a.z() / (a.z() - b.z()));
      lo = std::min(lo, p.x());
      hi = std::max(hi, p.x());
    }
  }
  return hi - lo;
}

std::vector<int> AllFdi() {
  std::vector<int> out;
  for (int q = 1; q <= 4; ++q) {
    for (int t = 1; t <= 8; ++t) out.push_back(10 * q + t);
  }
  return out;
}

class EveryTooth : public ::testing::TestWithParam<int> {};

TEST_P(EveryTooth, IsAValidSolidWithClinicalDimensions) {
  const ToothModel m = GenerateTooth(GetParam());
  const MeshReport r = m.mesh.Check();
  EXPECT_TRUE(r.IsSolid()) << "closed " << r.closed() << " manifold " << r.manifold()
                           << " oriented " << r.oriented() << " degenerate "
                           << r.degenerate_faces;
  EXPECT_EQ(r.num_faces, 5120u);  // about the paper's 4,000 at the default resolution
  EXPECT_EQ(r.euler_characteristic, 2);
  const ToothDimensions& d = m.dimensions;
  const Aabb box = r.bounds;
  // Within 10 % of the typical adult dimensions.
  EXPECT_NEAR(box.max.z(), d.crown_height, 0.1 * d.crown_height);
  EXPECT_NEAR(-box.min.z(), d.longest_root(), 0.1 * d.longest_root());
  EXPECT_NEAR(CrownWidth(m.mesh, 0), d.md_crown, 0.1 * d.md_crown);
  EXPECT_NEAR(CrownWidth(m.mesh, 1), d.bl, 0.1 * d.bl);
  EXPECT_NEAR(CervixWidth(m.mesh), d.md_cervix, 0.1 * d.md_cervix);
}

INSTANTIATE_TEST_SUITE_P(Fdi, EveryTooth, ::testing::ValuesIn(AllFdi()));

TEST(Tooth, CejLiesOnTheSurfaceAndIsScalloped) {
  const ToothModel m = GenerateTooth(11);
  ASSERT_EQ(m.cej.size(), 72u);
  // On the surface: the nearest mesh vertex is within a triangle's size.
  for (const Vector3& p : m.cej) {
    double nearest = 1e9;
    for (const Vector3& v : m.mesh.vertices())
      nearest = std::min(nearest, (v - p).norm());
    EXPECT_LT(nearest, 0.6);
  }
  // Higher at the proximal surfaces (x) than at the labial one (y).
  EXPECT_GT(m.cej[0].z(), m.cej[18].z() + 1.0);
}

TEST(Tooth, DeterministicAndResolutionAParameter) {
  const ToothModel a = GenerateTooth(36), b = GenerateTooth(36);
  EXPECT_EQ(a.mesh.vertices(), b.mesh.vertices());
  EXPECT_EQ(GenerateTooth(36, {.resolution = 3}).mesh.num_faces(), 1280u);
  EXPECT_THROW(GenerateTooth(36, {.resolution = 9}), std::invalid_argument);
}

TEST(Tooth, RootsByType) {
  EXPECT_EQ(GenerateTooth(16).dimensions.roots, 3);
  EXPECT_EQ(GenerateTooth(36).dimensions.roots, 2);
  EXPECT_EQ(GenerateTooth(14).dimensions.roots, 2);
  EXPECT_EQ(GenerateTooth(43).dimensions.roots, 1);
}

TEST(Tooth, InvalidFdiNumbersNameTheFault) {
  auto message = [](int fdi) {
    try {
      FdiTooth::Parse(fdi);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message(19), "FDI 19 does not exist: the tooth digit is 1 to 8");
  EXPECT_EQ(
      message(50),
      "FDI 50 does not exist: expected 11 to 48 (quadrant 1 to 4, then tooth 1 to 8)");
  EXPECT_EQ(message(20), "FDI 20 does not exist: the tooth digit is 1 to 8");
  EXPECT_EQ(
      message(5),
      "FDI 5 does not exist: expected 11 to 48 (quadrant 1 to 4, then tooth 1 to 8)");
  EXPECT_EQ(FdiTooth::Parse(36).type(), ToothType::kFirstMolar);
  EXPECT_FALSE(FdiTooth::Parse(36).upper());
}

}  // namespace
}  // namespace sulcus

// Arches (core/anatomy/arch.h).
#include "core/anatomy/arch.h"

namespace sulcus {
namespace {

TEST(Arch, TwentyEightTeethInArchOrderWithProperFrames) {
  for (bool upper : {false, true}) {
    const auto teeth = PlaceArch(upper);
    ASSERT_EQ(teeth.size(), 14u);
    EXPECT_EQ(teeth.front().tooth.fdi, upper ? 17 : 47);
    EXPECT_EQ(teeth.back().tooth.fdi, upper ? 27 : 37);
    EXPECT_EQ(PlaceArch(upper, {.third_molars = true}).size(), 16u);
    for (const PlacedTooth& p : teeth) {
      const Matrix3& R = p.X_WT.rotation();
      EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
      EXPECT_NEAR((R.transpose() * R - Matrix3::Identity()).norm(), 0.0, 1e-12);
      // Mirrored exactly on the patient's lower left and upper right.
      EXPECT_EQ(p.mirrored, p.tooth.quadrant == 3 || p.tooth.quadrant == 1)
          << p.tooth.fdi;
      // Buccal points out of the arch: away from the midline at the molars, forward at
      // the incisors.
      const Vector3 c = p.X_WT.translation();
      if (p.tooth.position >= 6) {
        EXPECT_GT(p.buccal_W.x() * c.x(), 0) << p.tooth.fdi;
      }
      if (p.tooth.position == 1) {
        EXPECT_GT(p.buccal_W.y(), 0.9) << p.tooth.fdi;
      }
      // Mesial points toward the midline.
      EXPECT_LT(p.mesial_W.x() * c.x(), 0) << p.tooth.fdi;
      // The crown points up (lower) or down (upper).
      EXPECT_GT(R.col(2).z() * (upper ? -1 : 1), 0.9) << p.tooth.fdi;
    }
  }
}

TEST(Arch, NeighboursTouchAtTheirContacts) {
  const auto teeth = PlaceArch(false);
  for (std::size_t i = 0; i + 1 < teeth.size(); ++i) {
    // Contacts are shared points on the arch: the distal contact of the tooth
    // nearer the midline is the mesial contact of the next one.
    const PlacedTooth& a = teeth[i];
    const PlacedTooth& b = teeth[i + 1];
    const bool a_is_mesial_of_b = a.tooth.position < b.tooth.position;
    const Vector3 shared_a = a_is_mesial_of_b ? a.contact_distal_W : a.contact_mesial_W;
    const Vector3 shared_b = a_is_mesial_of_b ? b.contact_mesial_W : b.contact_distal_W;
    if (a.tooth.position == 1 && b.tooth.position == 1) {
      EXPECT_NEAR((a.contact_mesial_W - b.contact_mesial_W).norm(), 0.0,
                  1e-9);  // at the midline
    } else {
      EXPECT_NEAR((shared_a - shared_b).norm(), 0.0, 1e-9)
          << a.tooth.fdi << " " << b.tooth.fdi;
    }
  }
  // The first molars are about 45 mm apart (CLINICAL arch size), the incisors in front.
  Vector3 m36 = Vector3::Zero(), m46 = Vector3::Zero();
  for (const auto& p : teeth) {
    if (p.tooth.fdi == 36) m36 = p.X_WT.translation();
    if (p.tooth.fdi == 46) m46 = p.X_WT.translation();
  }
  EXPECT_NEAR((m36 - m46).norm(), 45, 6);
}

TEST(Arch, PlacedMirroredTeethStayValidSolids) {
  const auto teeth = PlaceArch(false);
  for (const PlacedTooth& p : teeth) {
    if (!p.mirrored) continue;
    const TriangleMesh m =
        PlacedMesh(p, GenerateTooth(p.tooth.fdi, {.resolution = 3}).mesh);
    EXPECT_TRUE(m.Check().IsSolid()) << p.tooth.fdi;
  }
}

}  // namespace
}  // namespace sulcus

// Probes (core/anatomy/probe.h).
#include "core/anatomy/probe.h"

namespace sulcus {
namespace {

TEST(Probe, ValidSolidsWithTheTipAtTheOrigin) {
  for (const char* name : {"williams", "unc15", "who", "explorer23", "explorer1112"}) {
    const ProbeModel p = MakeProbe(name);
    for (const TriangleMesh* m : {&p.mesh, &p.collision_mesh}) {
      const MeshReport r = m->Check();
      EXPECT_TRUE(r.IsSolid()) << name;
      EXPECT_NEAR(r.bounds.min.z(), 0.0, 1e-9) << name;  // nothing below the tip's end
    }
    // The collision part is the working end and shank, far shorter than the probe.
    EXPECT_LT(p.collision_mesh.Bounds().extent().norm(),
              0.4 * p.mesh.Bounds().extent().norm())
        << name;
    // The handle rises away from the working end.
    EXPECT_GT(p.mesh.Bounds().max.z(), p.working_length_mm + 20) << name;
  }
  EXPECT_THROW(MakeProbe("nabers"), std::invalid_argument);
}

TEST(Probe, MarkingsAsInClinicalMd) {
  auto lines = [](const ProbeModel& p) {
    std::vector<double> v;
    for (const ProbeMarking& m : p.markings) {
      if (!m.band) v.push_back(m.from_mm);
    }
    return v;
  };
  EXPECT_EQ(lines(MakeProbe("williams")),
            (std::vector<double>{1, 2, 3, 5, 7, 8, 9, 10}));  // no 4 or 6
  const ProbeModel unc = MakeProbe("unc15");
  EXPECT_EQ(lines(unc).size(), 15u);
  int bands = 0;
  for (const ProbeMarking& m : unc.markings) bands += m.band;
  EXPECT_EQ(bands, 3);
  const ProbeModel who = MakeProbe("who");
  EXPECT_TRUE(who.ball_tip);
  EXPECT_EQ(lines(who), (std::vector<double>{8.5, 11.5}));
  EXPECT_DOUBLE_EQ(who.markings[0].from_mm, 3.5);
  EXPECT_DOUBLE_EQ(who.markings[0].to_mm, 5.5);
  // The WHO ball: 0.5 mm across at its widest, near the tip.
  double widest = 0;
  for (const Vector3& v : who.mesh.vertices()) {
    if (v.z() < 0.5) widest = std::max(widest, std::hypot(v.x(), v.y()));
  }
  EXPECT_NEAR(2 * widest, 0.5, 0.02);
}

}  // namespace
}  // namespace sulcus
