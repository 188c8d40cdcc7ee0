// Probing along the arch: every interproximal site reads itself at its depth,
// a probe enters a furcation as far as its class leaves the bone open, and the
// six zones cover every point of each sulcus.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <optional>

#include "core/anatomy/arch.h"
#include "core/anatomy/gingiva.h"
#include "core/anatomy/soft_tissue.h"
#include "core/haptics/effects.h"
#include "core/haptics/probe_keys.h"
#include "core/haptics/scripted_device.h"
#include "core/haptics/tip_locator.h"
#include "core/scene/scene.h"
#include "core/session/session.h"
#include "core/spheretree/cache.h"
#include "tests/common/alloc_guard.h"
#include "tests/common/output.h"
#include "tests/core/scene/probing_common.h"

namespace sulcus {
namespace {
namespace fs = std::filesystem;
using probing_test::Cache;
using probing_test::ExactScene;
using probing_test::PlayOffline;
}  // namespace
}  // namespace sulcus

namespace sulcus {
namespace {

// One gingiva per arch: under each contact the two teeth's interproximal
// sites lie within a millimetre of each other, and the floor falls from the
// shallower tooth's to the deeper's across the cut between their shares. A
// stroke down each interproximal site's own line of the probing scene (in from
// above and outside, 1 mm below the margin, then down the tooth's axis tilted
// 4 degrees outward, as the scripted students hold it) reads for that site;
// stopped 0.3 mm above the site's floor it feels only the soft gingiva, pushed
// 0.4 mm past it it presses the firm floor.
TEST(Probing, EveryInterproximalSiteOnTheArchReadsItselfAtItsDepth) {
  const SceneSpec spec =
      LoadSceneSpec(fs::path(SULCUS_SOURCE_DIR) / "scenes" / "periodontal_probing.yaml");
  ASSERT_TRUE(spec.gingiva_joined) << "the probing scene has one gingiva for its sextant";
  const auto scene = CompileScene(spec, Cache());
  int checked = 0;
  for (const ObjectSpec& o : scene->spec.objects) {
    if (o.kind != ObjectSpec::Kind::kGingiva) continue;
    GingivaParams gp;
    gp.pocket_mm = o.pocket_mm;
    gp.recession_mm = o.recession_mm;
    const GingivaModel g = GenerateGingiva(GenerateTooth(o.fdi), gp);
    auto world = [&](const Vector3& p_T) {
      return Vector3(o.X_WO * ArchMirror(o.mirrored, p_T));
    };
    const Matrix3 R = o.X_WO.rotation() *
                      (o.mirrored ? Vector3(-1, 1, 1) : Vector3(1, 1, 1)).asDiagonal();
    for (const int s : {0, 2, 3, 5}) {  // MB, DB, ML, DL
      const double th = g.site_angle[s];
      const Vector3 out(std::cos(th), std::sin(th), 0);
      const double tilt = 4 * std::numbers::pi / 180;
      const Vector3 up_T = std::cos(tilt) * Vector3::UnitZ() + std::sin(tilt) * out;
      const Quaternion q =
          Quaternion::FromTwoVectors(Vector3::UnitZ(), (R * up_T).normalized());
      const Vector3 top = g.margin[s] - 1.0 * Vector3::UnitZ();
      const double pocket = g.margin[s].z() - g.floor[s].z();
      const std::string where = std::to_string(o.fdi) + " site " + std::to_string(s);
      // The reading of one stroke `past` mm past the floor (below it when positive).
      auto stroke = [&](double past) -> std::optional<HapticEvent> {
        std::vector<Keyframe> keys;
        keys.push_back({0.0, world(top + 12.0 * Vector3::UnitZ() + 2.5 * out), q, 0});
        keys.push_back({0.6, world(top + 12.0 * Vector3::UnitZ() + 2.5 * out), q, 0});
        keys.push_back({1.4, world(top), q, 0});
        keys.push_back({1.6, world(top), q, 0});
        const double down = (pocket - 1.0 + past) / std::cos(tilt);
        keys.push_back({1.6 + down / 4.0, world(top - down * up_T), q, 0});
        keys.push_back({2.1 + down / 4.0, world(top - down * up_T), q, 0});
        keys.push_back({3.0 + down / 4.0, world(top + 2.0 * up_T), q,
                        0});  // out of the sulcus: the reading ends
        keys.push_back({3.2 + down / 4.0, world(top + 2.0 * up_T), q,
                        0});  // (a visit's reading comes 0.1 s after the tip has left)
        struct Readings final : TickConsumer {
          void OnTick(const TickRecord& r) override {
            for (int i = 0; i < r.num_events; ++i)
              if (r.events[i].kind == EventKind::kProbeReading)
                events.push_back(r.events[i]);
          }
          std::vector<HapticEvent> events;
        } consumer;
        const auto ticks = static_cast<std::uint64_t>((3.2 + down / 4.0) * 1000);
        const auto session =
            PlayOffline(*scene, std::move(keys), ticks, "site", &consumer);
        EXPECT_EQ(session->loop().faults().total(), 0u) << where;
        std::optional<HapticEvent> deepest;
        for (const HapticEvent& e : consumer.events)
          if (!deepest || e.payload.reading.depth_mm > deepest->payload.reading.depth_mm)
            deepest = e;
        return deepest;
      };
      for (const double past : {-0.3, 0.4}) {
        const std::optional<HapticEvent> e = stroke(past);
        ASSERT_TRUE(e) << where;
        EXPECT_EQ(e->payload.reading.fdi, o.fdi) << where;
        EXPECT_EQ(e->payload.reading.site, s) << where;
        EXPECT_NEAR(e->payload.reading.depth_mm, o.pocket_mm[s] + past, 0.15) << where;
        if (past < 0)
          EXPECT_LT(e->payload.reading.peak_force_n, 0.15)
              << where << ": above the floor, only the soft gingiva";
        else
          EXPECT_GT(e->payload.reading.peak_force_n, 0.3)
              << where << ": pressing the firm floor";
      }
      ++checked;
    }
  }
  EXPECT_EQ(checked, 16);
}

// A WHO probe (its 0.5 mm ball) pushed straight into 46's buccal furcation,
// level halfway between the crest and the furcation's roof, along the line
// between the roots. Each class opens the furcation further (the crest lower,
// the bone between the roots further in), so the exact meshes let the probe in
// further with each class (class 2 to the bone 4 mm in, class 3 through), and
// the haptic probe follows: never into the exact meshes, further with each
// class, and within a millimetre of how far they let it in.
TEST(Probing, AProbeGoesIntoTheFurcationAsFarAsItsClassLeavesTheBoneOpen) {
  const fs::path dir = test::FreshOutputPath("furcation", "probe");
  const double roof = FurcationRoofMm(46), below[4] = {0, 0.5, 1.5, 3.0};
  const double entrance_y = 0.7 * Dimensions(FdiTooth::Parse(46)).bl / 2 * 0.82;
  double exact_in_before = 0, in_before = 0;
  for (int hamp = 1; hamp <= 3; ++hamp) {
    SCOPED_TRACE("class " + std::to_string(hamp));
    const fs::path file = dir / ("class" + std::to_string(hamp) + ".yaml");
    std::ofstream(file) << "tool:\n  probe: who\narch: true\neffects: "
                           "[contact]\nobjects:\n  - tooth: 46\n"
                        << "    furcation: {B: " << hamp << "}\n  - anatomy: jaw_lower\n";
    const auto scene = CompileScene(LoadSceneSpec(file), Cache());
    const ObjectSpec& tooth = scene->spec.objects[0];
    ASSERT_EQ(tooth.fdi, 46);
    const Matrix3 R =
        tooth.X_WO.rotation() *
        (tooth.mirrored ? Vector3(-1, 1, 1) : Vector3(1, 1, 1)).asDiagonal();
    auto world = [&](const Vector3& p_T) {
      return Vector3(tooth.X_WO * ArchMirror(tooth.mirrored, p_T));
    };
    const double z = -0.5 * (roof + below[hamp] + roof + 0.3);
    // The shank toward the buccal (+y), the ball moving in along -y at 2 mm/s.
    const Matrix3 R_WG =
        Quaternion::FromTwoVectors(Vector3::UnitZ(), (R * Vector3::UnitY()).normalized())
            .toRotationMatrix();
    const double start = entrance_y + 4.0, end = -entrance_y - 3.0;
    // How far in the exact meshes let it go along that line (bisection).
    const ExactScene exact(*scene);
    // Whether the probe at a pose is free of the exact meshes.
    auto free_pose = [&](const Matrix3& R_tool, const Vector3& t) {
      return exact.ProbeFree(RigidTransform(R_tool, t));
    };
    auto free_at = [&](double y) { return free_pose(R_WG, world(Vector3(0, y, z))); };
    ASSERT_TRUE(free_at(start));
    double lo = start, hi = end;
    if (free_at(end)) {
      lo = end;
    } else {
      for (int k = 0; k < 20; ++k) (free_at(0.5 * (lo + hi)) ? lo : hi) = 0.5 * (lo + hi);
    }
    const double exact_in = entrance_y - lo;
    EngineData d(*scene->model);
    ResetTool(RigidTransform(R_WG, world(Vector3(0, start, z))), &d);
    const int ticks = static_cast<int>((start - end) / 2.0 * 1000);
    for (int i = 0; i <= ticks + 200; ++i)
      Step(*scene->model,
           RigidTransform(R_WG, world(Vector3(0, std::max(end, start - 0.002 * i), z))),
           &d);
    EXPECT_EQ(d.faults.total(), 0u);
    const Vector3 tip_T =
        ArchMirror(tooth.mirrored, tooth.X_WO.inverse() * d.X_WG.translation());
    const double in = entrance_y - tip_T.y();
    // Where the rendered tool stopped, how far it overlaps the exact meshes:
    // how far back out along its way it must move to be free of them.
    const Vector3 out_W = R * Vector3::UnitY();
    auto free_back = [&](double s) {
      return free_pose(d.X_WG.rotation(), d.X_WG.translation() + s * out_W);
    };
    double overlap = 0;
    if (!free_back(0)) {
      double a = 0, b = 2.0;
      for (int k = 0; k < 16; ++k) (free_back(0.5 * (a + b)) ? b : a) = 0.5 * (a + b);
      overlap = b;
    }
    std::printf(
        "class %d: the ball's centre %.2f mm in from the entrance (exact meshes along "
        "its line: %.2f; tip %.2f %.2f "
        "%.2f, overlapping them by %.2f mm)\n",
        hamp, in, exact_in, tip_T.x(), tip_T.y(), tip_T.z(), overlap);
    // No further than the true geometry lets it: where the rendered tool
    // stopped, it is free of the exact meshes (it may slide up or aside off
    // the straight line, over an edge the line meets: class I's bone ends
    // 0.2 mm under the line's height).
    EXPECT_LE(overlap, 0.1) << "no further than the true geometry lets it";
    // And not held far short of it: a jaw whose crest lies below a furcation
    // gets 2,048 leaves by default (FollowAttachmentLoss; at 512 its
    // spheres filled the class II defect, felt 0.9 mm in where the meshes
    // allow 4).
    EXPECT_EQ(scene->spec.objects[1].trees.leaves, kFurcationJawLeaves);
    EXPECT_GT(in, exact_in - 1.0) << "not held far short of it";
    if (hamp > 1) {
      EXPECT_GT(exact_in, exact_in_before + 0.3)
          << "a higher class opens the furcation further";
      EXPECT_GT(in, in_before + 0.3) << "and the probe feels it";
    }
    exact_in_before = exact_in;
    in_before = in;
  }
}

}  // namespace
}  // namespace sulcus

namespace sulcus {
namespace {

// The six zones on the shipped scenes' real sulci (the sextant and the whole
// mouth): every point of a tooth's sulcus, from the margin to the floor all
// the way round, is in a site (its own tooth's, or under a contact the
// neighbour's, as the cut between the shares has it); each site's own line is
// in that site from just below the margin to the floor (where N puts the tip);
// a tip at a line angle, between a site's line and the mid-site's, is in the
// interdental site, as clinicians chart it. Prints how much of each sulcus
// the neighbours took.
void CheckZones(const char* scene_file) {
  const SceneSpec spec =
      LoadSceneSpec(fs::path(SULCUS_SOURCE_DIR) / "scenes" / scene_file);
  const auto scene = CompileScene(spec, Cache());
  const std::vector<ProbingSite>& sites = scene->effects.sites;
  ASSERT_FALSE(sites.empty());
  const TipLocator locator(sites);
  auto pose = [](const Vector3& p) { return RigidTransform(Quaternion::Identity(), p); };
  int points = 0, nowhere = 0, neighbour = 0, lines = 0, past_cut = 0, moved = 0;
  double most_moved = 0, nearest_col = 1e9, col_sum = 0;
  int col_n = 0;
  for (int i = 0; i < static_cast<int>(sites.size()); ++i) {
    const ProbingSite& s = sites[static_cast<std::size_t>(i)];
    ASSERT_TRUE(s.ring) << s.fdi << " " << s.site;
    const SulcusRing& r = *s.ring;
    const std::string where = std::to_string(s.fdi) + " site " + std::to_string(s.site);
    // The site's own line, 0.3 mm below the margin to 0.1 mm above the floor.
    const double pocket = (s.floor_W - s.margin_W).norm();
    for (double d = 0.3; d <= pocket - 0.1; d += 0.2) {
      const Vector3 p = s.margin_W + d * (s.floor_W - s.margin_W).normalized();
      const TipLocation at = locator.Locate(pose(p));
      EXPECT_EQ(at.site, i) << where << " at " << d << " mm on its own line";
      if (at.site == i) {
        EXPECT_NEAR(at.depth_mm, d, 0.05) << where;
      }
      ++lines;
    }
    // The pocket as built is the site's depth at its line (moved or not), and
    // the deepest of its zone.
    EXPECT_NEAR(pocket, s.pocket_mm, 0.1) << where << ": the pocket at its line";
    double deepest = 0;
    for (int k = 0; k < r.size(); ++k)
      if (r.ZoneAt(2 * std::numbers::pi * k / r.size()) == s.site)
        deepest = std::max(deepest, r.margin_z[static_cast<std::size_t>(k)] -
                                        r.floor_z[static_cast<std::size_t>(k)]);
    EXPECT_NEAR(deepest, s.pocket_mm, 0.1) << where << ": the deepest of its zone";
    // N's pose, pushed straight down the axis to the floor: the same site.
    const RigidTransform over = PoseOverSite(s, 1.0);
    for (double d = 1.3; d <= 1.0 + pocket - 0.1; d += 0.3) {
      const Vector3 p = over.translation() - d * r.AxisW();
      EXPECT_EQ(locator.Locate(pose(p)).site, i)
          << where << ": N then " << d << " mm down";
    }
    if (s.site != 0) continue;                // the ring once a tooth
    for (int deg = 1; deg < 360; deg += 2) {  // (the zones' bounds lie between)
      const double phi = deg * std::numbers::pi / 180;
      const int k = r.SegmentAt(phi);
      const double pk = r.margin_z[static_cast<std::size_t>(k)] -
                        r.floor_z[static_cast<std::size_t>(k)];
      for (const double d : {0.3, 0.5 * pk, pk - 0.1}) {
        const Vector3 q = r.PointAt(phi, d);
        // Past a cut between shares the neighbour's gingiva begins: its own
        // sulcus there, or tissue below its (shallower) floor.
        bool beyond = false;
        for (int c = 0; c < r.num_cuts; ++c)
          beyond = beyond || (q - r.cut_q_W[static_cast<std::size_t>(c)])
                                     .dot(r.cut_n_W[static_cast<std::size_t>(c)]) > 0;
        if (beyond) {
          ++past_cut;
          continue;
        }
        const TipLocation at = locator.Locate(pose(q));
        ++points;
        if (at.site < 0) {
          ++nowhere;
          ADD_FAILURE() << s.fdi << " at " << deg << " degrees, " << d
                        << " mm deep: in no site";
          continue;
        }
        const ProbingSite& got = sites[static_cast<std::size_t>(at.site)];
        if (got.fdi != s.fdi) {
          ++neighbour;
          // Only under a contact, never across a mid site.
          EXPECT_TRUE(got.site != 1 && got.site != 4)
              << s.fdi << " at " << deg << " degrees: in " << got.fdi << " " << got.site;
        } else {
          EXPECT_EQ(got.site, r.ZoneAt(phi)) << s.fdi << " at " << deg << " degrees";
        }
      }
    }
    // The line angles: between each interdental site's line and the bound of
    // its zone toward the mid site (three fifths of the way), at half the
    // pocket: still the interdental site; just past the bound: the mid site.
    for (const int site : {0, 2, 3, 5}) {
      const ProbingSite& d = sites[static_cast<std::size_t>(i + site)];
      const Vector3 p = r.ToRing(d.margin_W);
      const double phi = std::atan2(p.y(), p.x());
      const double bound = site == 0   ? r.facial_from
                           : site == 2 ? r.facial_to
                           : site == 3 ? r.oral_to - 2 * std::numbers::pi
                                       : r.oral_from;
      const double toward = std::remainder(bound - phi, 2 * std::numbers::pi);
      auto half = [&](double a) {  // half the pocket's depth there
        const int k = r.SegmentAt(a);
        return 0.5 * (r.margin_z[static_cast<std::size_t>(k)] -
                      r.floor_z[static_cast<std::size_t>(k)]);
      };
      const double in = phi + 0.6 * toward;
      EXPECT_EQ(locator.Locate(pose(r.PointAt(in, half(in)))).site, i + site)
          << s.fdi << " site " << site << ": at its line angle";
      const int mid = site < 3 ? 1 : 4;
      const double past = phi + toward + (toward > 0 ? 0.02 : -0.02);
      EXPECT_EQ(locator.Locate(pose(r.PointAt(past, half(past)))).site, i + mid)
          << s.fdi << " site " << site << ": just past its zone's bound";
      if (d.line_moved_deg > 0) {
        if (std::string(scene_file) == "periodontal_probing.yaml")
          std::printf("figure: %d site %d: its line moved %.1f degrees off the cut\n",
                      d.fdi, site, d.line_moved_deg);
        ++moved;
        most_moved = std::max(most_moved, d.line_moved_deg);
      }
      if (r.num_cuts > 0) {
        const double to = r.ToContactMm(phi, site);
        nearest_col = std::min(nearest_col, to);
        col_sum += to;
        ++col_n;
      }
    }
  }
  std::printf(
      "figure: %s: %d points of the sulci, %d in no site, %d in a neighbour's "
      "(under a contact); %d past a cut into the neighbour's share; %d points "
      "on the sites' own lines; %d interdental lines moved off the cut (at most "
      "%.1f degrees)\n",
      scene_file, points, nowhere, neighbour, past_cut, lines, moved, most_moved);
  std::printf(
      "figure: %s: an interdental site's line is %.2f mm (mean) and at least "
      "%.2f mm from its col's midline along the sulcus\n",
      scene_file, col_n ? col_sum / col_n : 0.0, nearest_col);
}

TEST(Zones, EveryPointOfEachSulcusIsInASiteOnTheSextant) {
  CheckZones("periodontal_probing.yaml");
}

TEST(Zones, EveryPointOfEachSulcusIsInASiteInTheWholeMouth) {
  CheckZones("periodontal_examination.yaml");
}

}  // namespace
}  // namespace sulcus
