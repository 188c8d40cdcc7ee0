// Teeth on the arches touch their neighbours and overlap nothing, measured with
// exact triangle geometry (core/anatomy/mesh_contact.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>

#include "core/anatomy/arch.h"
#include "core/anatomy/mesh_contact.h"
#include "core/anatomy/tooth.h"

namespace sulcus {
namespace {

std::vector<std::pair<PlacedTooth, TriangleMesh>> Mouth(const ArchParams& params) {
  std::map<int, TriangleMesh> teeth;
  std::vector<std::pair<PlacedTooth, TriangleMesh>> out;
  for (bool upper : {false, true}) {
    for (const PlacedTooth& p : PlaceArch(upper, params))
      out.emplace_back(p, PlacedMesh(p, GenerateTooth(p.tooth.fdi).mesh));
  }
  return out;
}

TEST(ArchContact, NeighboursTouchAndNoTwoTeethIntersect) {
  // With the mouth closed (the arches nearest each other; neighbours within an
  // arch are the same at any opening).
  for (const double open : {0.0}) {
    const auto mouth = Mouth({.upper_lift_mm = open, .third_molars = true});
    for (std::size_t i = 0; i < mouth.size(); ++i) {
      for (std::size_t j = i + 1; j < mouth.size(); ++j) {
        const PlacedTooth& a = mouth[i].first;
        const PlacedTooth& b = mouth[j].first;
        const bool neighbours =
            a.tooth.upper() == b.tooth.upper() &&
            (j == i + 1 || (a.tooth.position == 1 && b.tooth.position == 1));
        if (neighbours) {
          const MeshContact c = MeasureContact(mouth[i].second, mouth[j].second);
          std::printf("open %4.1f  %d-%d  %s gap %.3f mm\n", open, a.tooth.fdi,
                      b.tooth.fdi, c.intersect ? "INTERSECT" : "apart", c.gap_mm);
          EXPECT_FALSE(c.intersect) << a.tooth.fdi << "-" << b.tooth.fdi;
          EXPECT_LE(c.gap_mm, 0.3) << a.tooth.fdi << "-" << b.tooth.fdi;
        } else {
          EXPECT_FALSE(MeshesIntersect(mouth[i].second, mouth[j].second))
              << a.tooth.fdi << " and " << b.tooth.fdi << " with the mouth open " << open
              << " mm";
        }
      }
    }
  }
}

}  // namespace
}  // namespace sulcus

#include "core/anatomy/arch_fit.h"

namespace sulcus {
namespace {

TEST(ArchContact, TheClosedMouthsTeethMeet) {
  // At the default occlusion no upper tooth intersects a lower one (the test
  // above); 0.05 mm lower, some do: the arches touch when the mouth is closed.
  ArchParams params;
  params.occlusion_mm -= 0.05;
  std::vector<TriangleMesh> lower, upper;
  for (const PlacedTooth& p : PlaceArch(false, params))
    lower.push_back(PlacedMesh(p, GenerateTooth(p.tooth.fdi).mesh));
  for (const PlacedTooth& p : PlaceArch(true, params))
    upper.push_back(PlacedMesh(p, GenerateTooth(p.tooth.fdi).mesh));
  int crossing = 0;
  for (const TriangleMesh& a : lower)
    for (const TriangleMesh& b : upper) crossing += MeshesIntersect(a, b);
  EXPECT_GT(crossing, 0);
}

TEST(ArchContact, TheTableIsTheFit) {
  for (bool upper : {false, true}) {
    const ArchFit fit = FitArchCentres(upper);
    std::printf("%s:", upper ? "upper" : "lower");
    for (double c : fit.centre_mm) std::printf(" %.3f,", c);
    std::printf("\n");
    for (int pos = 1; pos <= 8; ++pos)
      EXPECT_NEAR(ArchCentreMm(upper, pos), fit.centre_mm[pos - 1], 0.005) << pos;
  }
}

}  // namespace
}  // namespace sulcus

#include "core/anatomy/soft_tissue.h"

namespace sulcus {
namespace {

class SoftTissueAround : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    for (bool upper : {false, true})
      for (const PlacedTooth& p : PlaceArch(upper, {.upper_lift_mm = 20})) {
        placed_.push_back(p);
        teeth_.push_back(PlacedMesh(p, GenerateTooth(p.tooth.fdi).mesh));
      }
  }
  static inline std::vector<PlacedTooth> placed_;
  static inline std::vector<TriangleMesh> teeth_;
};

TEST_F(SoftTissueAround, EveryRootIsInItsJawBelowTheCrest) {
  const std::map<int, double> drops = {
      {46, CrestDropMm(8)}};  // 7 mm pocket and 1 mm recession at 46
  for (bool upper : {false, true}) {
    const TriangleMesh jaw =
        MakeSoftTissue(upper ? "jaw_upper" : "jaw_lower", {.upper_lift_mm = 20}, drops);
    ASSERT_TRUE(jaw.Check().IsSolid());
    for (std::size_t k = 0; k < placed_.size(); ++k) {
      const PlacedTooth& p = placed_[k];
      if (p.tooth.upper() != upper) continue;
      const auto it = drops.find(p.tooth.fdi);
      const double drop = it == drops.end() ? 1.5 : it->second;
      // Points of the tooth 0.5 mm or more beyond the crest (the crest is level,
      // `drop` beyond the CEJ's centre, away from the crown): the root in the
      // bone. Every one of them inside the jaw.
      const Vector3 axis = p.X_WT.rotation().col(2);  // toward the crown
      const double toward_crown = upper ? -1 : 1;
      std::vector<Vector3> root;
      for (const Vector3& v : teeth_[k].vertices())
        if (toward_crown * (v.z() - p.X_WT.translation().z()) < -drop - 0.5)
          root.push_back(v);
      ASSERT_FALSE(root.empty()) << p.tooth.fdi;
      const std::vector<bool> inside = InsideSolid(jaw, root);
      EXPECT_EQ(std::count(inside.begin(), inside.end(), false), 0) << p.tooth.fdi;
      // And the crown stands out of it: the CEJ's centre is above the crest.
      EXPECT_FALSE(InsideSolid(jaw, {p.X_WT.translation() + 1.0 * axis})[0])
          << p.tooth.fdi;
    }
  }
}

// The bone over the front teeth's labial roots follows their lean: an upper
// incisor's root leans back 4 to 5 mm over its length, and a jaw whose face
// stood as a wall at the roots' widest (as it once did) lay 3.2 to 3.8 mm
// outside the front roots 6 mm beyond the crest and more than 4 mm at 9 mm
// (now 1.9 to 2.8 mm at every depth). Measured from the root's most labial
// point at 3, 6 and 9 mm beyond the crest, outward until leaving the jaw.
TEST_F(SoftTissueAround, TheJawsFaceFollowsTheFrontRootsLean) {
  for (bool upper : {false, true}) {
    const TriangleMesh jaw =
        MakeSoftTissue(upper ? "jaw_upper" : "jaw_lower", {.upper_lift_mm = 20});
    const double away = upper ? 1 : -1;  // from the crown toward the apex
    int measured = 0;
    for (std::size_t k = 0; k < placed_.size(); ++k) {
      const PlacedTooth& p = placed_[k];
      if (p.tooth.upper() != upper || p.tooth.position > 3) continue;
      const Vector3 out = Vector3(p.buccal_W.x(), p.buccal_W.y(), 0).normalized();
      const double crest_z = p.X_WT.translation().z() + away * 1.5;
      for (const double depth : {3.0, 6.0, 9.0}) {
        const double z = crest_z + away * depth;
        double most = -1e9;
        Vector3 at;
        for (const Vector3& v : teeth_[k].vertices())
          if (std::abs(v.z() - z) < 0.4 && v.dot(out) > most) most = v.dot(out), at = v;
        if (most < -1e8) continue;  // (the root ends before this depth)
        std::vector<Vector3> ray;
        for (int i = 0; i <= 120; ++i) ray.push_back(at + 0.05 * i * out);
        const std::vector<bool> inside = InsideSolid(jaw, ray);
        const double bone =
            0.05 * (std::find(inside.begin(), inside.end(), false) - inside.begin());
        std::printf("%d  %.0f mm beyond the crest: %.2f mm of jaw over the root\n",
                    p.tooth.fdi, depth, bone);
        EXPECT_GE(bone, 0.5) << p.tooth.fdi << " at " << depth << " mm";
        EXPECT_LE(bone, 3.0) << p.tooth.fdi << " at " << depth << " mm";
        ++measured;
      }
    }
    EXPECT_GE(measured, 12) << (upper ? "upper" : "lower");
  }
}

TEST_F(SoftTissueAround, LipsCheeksTongueAndFloorTouchNoTooth) {
  for (const char* name : {"lip_upper", "lip_lower", "cheek_left", "cheek_right",
                           "tongue", "floor_of_mouth", "soft_palate"}) {
    const TriangleMesh m = MakeSoftTissue(name, {.upper_lift_mm = 20});
    ASSERT_TRUE(m.Check().IsSolid()) << name;
    for (std::size_t k = 0; k < teeth_.size(); ++k)
      EXPECT_FALSE(MeshesIntersect(m, teeth_[k]))
          << name << " and tooth " << placed_[k].tooth.fdi;
  }
}

TEST_F(SoftTissueAround, ThePalateHoldsNoCrown) {
  const TriangleMesh palate = MakeSoftTissue("palate", {.upper_lift_mm = 20});
  ASSERT_TRUE(palate.Check().IsSolid());
  for (std::size_t k = 0; k < placed_.size(); ++k) {
    const PlacedTooth& p = placed_[k];
    if (!p.tooth.upper()) continue;
    std::vector<Vector3> crown;
    for (const Vector3& v : teeth_[k].vertices())
      if ((v - p.X_WT.translation()).dot(p.X_WT.rotation().col(2)) > 0.5)
        crown.push_back(v);
    const std::vector<bool> inside = InsideSolid(palate, crown);
    EXPECT_EQ(std::count(inside.begin(), inside.end(), true), 0) << p.tooth.fdi;
  }
}

// A lip is skin on its outer face from the vermilion border on: at the front
// of the mouth, skin vertices face forward (away from the teeth) and lie
// further from the free edge than any vermilion vertex on that face; no
// vertex facing the teeth is skin.
TEST(SoftTissue, ALipsSkinBeginsAtTheVermilionBorder) {
  for (const char* name : {"lip_upper", "lip_lower"}) {
    const bool upper = std::string(name) == "lip_upper";
    const TriangleMesh lip = MakeSoftTissue(name, {.upper_lift_mm = 20});
    const std::vector<double> skin = LipSkinCoverage(lip);
    ASSERT_EQ(skin.size(), lip.num_vertices()) << name;
    const std::vector<Vector3> normals = lip.VertexNormalSums();
    // Near the midline (|x| < 3 mm): the free edge is the lowest (upper lip)
    // or highest (lower) point there.
    double edge = upper ? 1e9 : -1e9;
    for (const Vector3& v : lip.vertices())
      if (std::abs(v.x()) < 3)
        edge = upper ? std::min(edge, v.z()) : std::max(edge, v.z());
    double skin_nearest = 1e9, vermilion_farthest = 0;
    int skin_count = 0, vermilion_count = 0;
    for (std::size_t i = 0; i < lip.num_vertices(); ++i) {
      const Vector3& v = lip.vertices()[i];
      if (std::abs(v.x()) >= 3) continue;
      const Vector3 n = normals[i].normalized();
      const double from_edge = std::abs(v.z() - edge);
      if (n.y() < -0.5) {
        EXPECT_EQ(skin[i], 0.0) << name << ": a vertex facing the teeth is skin";
      }
      if (n.y() > 0.7 && skin[i] > 0.99)
        skin_nearest = std::min(skin_nearest, from_edge), ++skin_count;
      if (n.y() > 0.7 && skin[i] < 0.01)
        vermilion_farthest = std::max(vermilion_farthest, from_edge), ++vermilion_count;
    }
    std::printf("%s: vermilion up to %.1f mm from the free edge, skin from %.1f mm\n",
                name, vermilion_farthest, skin_nearest);
    EXPECT_GT(skin_count, 0) << name;
    EXPECT_GT(vermilion_count, 0) << name;
    EXPECT_LT(vermilion_farthest, skin_nearest) << name;
    EXPECT_GT(vermilion_farthest, 3.0) << name;
    EXPECT_LT(skin_nearest, 10.0) << name;
  }
  EXPECT_TRUE(LipSkinCoverage(MakeSoftTissue("tongue")).empty());
}

TEST(SoftTissue, LesionsSitOnTheRegionTheyName) {
  const TriangleMesh tongue = MakeSoftTissue("tongue", {.upper_lift_mm = 20});
  const Aabb b = tongue.Bounds();
  const Vector3 left = LesionCentre("tongue", "lateral_border_left", tongue);
  const Vector3 right = LesionCentre("tongue", "lateral_border_right", tongue);
  const Vector3 dorsum = LesionCentre("tongue", "dorsum", tongue);
  const Vector3 ventral = LesionCentre("tongue", "ventral", tongue);
  // The extreme of the tongue's section where each lesion sits, along a direction.
  auto extreme = [&](const Vector3& at, const Vector3& dir) {
    double m = -1e9;
    for (const Vector3& v : tongue.vertices())
      if (std::abs(v.y() - at.y()) < 1.5) m = std::max(m, v.dot(dir));
    return m;
  };
  EXPECT_GT(left.x(), extreme(left, Vector3::UnitX()) - 1.0)
      << "on the patient's left border (+x)";
  EXPECT_GT(left.x(), 5.0);
  EXPECT_LT(right.x(), -extreme(right, -Vector3::UnitX()) + 1.0) << "on the right border";
  EXPECT_GT(dorsum.z(), extreme(dorsum, Vector3::UnitZ()) - 1.0) << "on top";
  EXPECT_LT(std::abs(dorsum.x()), 3.0);
  EXPECT_LT(ventral.z(), dorsum.z() - 3.0);
  EXPECT_GT(ventral.y(), b.max.y() - 12.0) << "under the tip";
  const TriangleMesh cheek = MakeSoftTissue("cheek_left", {.upper_lift_mm = 20});
  const Vector3 c = LesionCentre("cheek_left", "centre", cheek);
  // On its inner side: toward the midline is the mouth, outward the cheek.
  EXPECT_EQ(InsideSolid(cheek, {c - Vector3(1.0, 0, 0), c + Vector3(1.0, 0, 0)}),
            (std::vector<bool>{false, true}));
  EXPECT_THROW(LesionCentre("tongue", "centre", tongue), std::invalid_argument);
  EXPECT_TRUE(LesionRegions("jaw_lower").empty());
}

// The bone between 46's roots as its buccal furcation's class leaves it (the
// crest where the scene's rule puts it: 0.5, 1.5, 3 mm below the entrance 3 mm
// under the CEJ), probed from the buccal entrance inward, in the tooth frame
// (+y buccal), halfway up between the crest and the furcation's roof.
TEST(SoftTissue, TheBoneBetweenTheRootsFollowsTheFurcationClass) {
  const std::vector<PlacedTooth> placed = PlaceArch(false);
  const auto p46 = std::find_if(placed.begin(), placed.end(),
                                [](const PlacedTooth& p) { return p.tooth.fdi == 46; });
  ASSERT_NE(p46, placed.end());
  // The roof: where the tooth ends going down its axis between the roots.
  const TriangleMesh tooth = GenerateTooth(46, {.resolution = 3}).mesh;
  std::vector<Vector3> axis;
  for (double z = 0; z > -8; z -= 0.1) axis.emplace_back(0, 0, z);
  const std::vector<bool> in_tooth = InsideSolid(tooth, axis);
  const double roof =
      axis[std::find(in_tooth.begin(), in_tooth.end(), false) - in_tooth.begin()].z();
  EXPECT_NEAR(FurcationRoofMm(46), -roof, 1e-9);
  EXPECT_EQ(FurcationRoofMm(45), 0.0);
  const double entrance_y = 0.7 * Dimensions(FdiTooth::Parse(46)).bl / 2 * 0.82;
  const double drops[4] = {0, -roof + 0.5, -roof + 1.5, -roof + 3.0};
  for (int hamp = 1; hamp <= 3; ++hamp) {
    SCOPED_TRACE("class " + std::to_string(hamp));
    const TriangleMesh jaw = MakeSoftTissue("jaw_lower", {}, {{46, drops[hamp]}},
                                            {{46, {{"B", hamp}, {"L", 0}}}});
    ASSERT_TRUE(jaw.Check().IsSolid());
    const double z = 0.5 * (-drops[hamp] + roof - 0.3);
    auto bone_at = [&](double y) -> bool {
      return InsideSolid(jaw,
                         {p46->X_WT * ArchMirror(p46->mirrored, Vector3(0, y, z))})[0];
    };
    if (hamp == 3) {
      for (double y = -entrance_y; y <= entrance_y; y += 0.5)
        EXPECT_FALSE(bone_at(y)) << y << ": through and through";
    } else {
      const double defect = hamp == 1 ? 2.0 : 4.0;
      EXPECT_FALSE(bone_at(entrance_y - 0.5 * defect)) << "in the defect";
      EXPECT_TRUE(bone_at(entrance_y - defect - 0.5)) << "past the defect";
      EXPECT_TRUE(bone_at(-entrance_y + 0.5)) << "at the sound lingual entrance";
    }
  }
  // With no class given (or class 0: the furcation not involved) the bone
  // between the roots is whole, however far the crest has dropped around
  // the tooth; with the crest above the furcation there is none to add.
  const TriangleMesh whole = MakeSoftTissue("jaw_lower", {}, {{46, drops[2]}});
  ASSERT_TRUE(whole.Check().IsSolid());
  const double z2 = 0.5 * (-drops[2] + roof - 0.3);
  for (double y = -entrance_y + 0.5; y <= entrance_y - 0.5; y += 0.5)
    EXPECT_TRUE(
        InsideSolid(whole, {p46->X_WT * ArchMirror(p46->mirrored, Vector3(0, y, z2))})[0])
        << y << ": class 0";
  EXPECT_EQ(
      MakeSoftTissue("jaw_lower", {}, {{46, drops[2]}}, {{46, {{"B", 0}, {"L", 0}}}})
          .num_faces(),
      whole.num_faces());
  EXPECT_EQ(MakeSoftTissue("jaw_lower", {}, {{46, 1.5}}).num_faces(),
            MakeSoftTissue("jaw_lower").num_faces());
  std::printf("46: the furcation's roof %.1f mm below the CEJ\n", -roof);
  // The upper first molar (three roots) and first premolar (two, buccal and
  // palatal): their roofs where the roots part, and jaws that stay solid.
  for (const int fdi : {16, 14}) {
    const double r = FurcationRoofMm(fdi);
    std::printf("%d: the furcation's roof %.1f mm below the CEJ\n", fdi, r);
    EXPECT_GT(r, 2.5) << fdi;
    EXPECT_LT(r, 0.8 * Dimensions(FdiTooth::Parse(fdi)).root_length) << fdi;
    const std::map<std::string, int> classes =
        fdi == 16 ? std::map<std::string, int>{{"B", 2}, {"M", 1}}
                  : std::map<std::string, int>{{"M", 1}};
    const TriangleMesh jaw =
        MakeSoftTissue("jaw_upper", {}, {{fdi, r + 1.5}}, {{fdi, classes}});
    EXPECT_TRUE(jaw.Check().IsSolid()) << fdi;
    // Without classes, bone in the middle between the roots' tops, halfway
    // between the crest and the roof; with them, a different bone.
    const TriangleMesh sound = MakeSoftTissue("jaw_upper", {}, {{fdi, r + 1.5}});
    EXPECT_TRUE(sound.Check().IsSolid()) << fdi;
    const std::vector<PlacedTooth> uppers = PlaceArch(true);
    const PlacedTooth& pt =
        *std::find_if(uppers.begin(), uppers.end(),
                      [&](const PlacedTooth& p) { return p.tooth.fdi == fdi; });
    Vector3 mid = Vector3::Zero();
    const std::vector<Vector3> tops = GenerateTooth(fdi, {.resolution = 3}).root_tops;
    for (const Vector3& t : tops) mid += t / static_cast<double>(tops.size());
    mid.z() = -r - 0.9;
    EXPECT_TRUE(InsideSolid(sound, {pt.X_WT * ArchMirror(pt.mirrored, mid)})[0])
        << fdi << ": bone between the roots";
    EXPECT_NE(jaw.num_faces(), sound.num_faces())
        << fdi << ": its classes shape that bone";
  }
}

TEST(SoftTissue, TheTonguesRegionsByTheSurfaceNormal) {
  EXPECT_EQ(TongueRegion(Vector3(0, 0, 1)), "dorsum");
  EXPECT_EQ(TongueRegion(Vector3(0, 0, -1)), "ventral surface");
  EXPECT_EQ(TongueRegion(Vector3(1, 0, 0.2).normalized()), "lateral border");
}

}  // namespace
}  // namespace sulcus
