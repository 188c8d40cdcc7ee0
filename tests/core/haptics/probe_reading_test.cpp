// The reading rule (core/haptics/probe_reading.h) on synthetic strokes: the
// sites are two straight lines 2 mm apart, the hand's path is written out tick
// by tick, so each case's expected reading follows from the rule by hand.
#include "core/haptics/probe_reading.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "core/haptics/tip_locator.h"

namespace sulcus {
namespace {

constexpr double kRate = 1000;

// Two sites of one tooth, their lines vertical, 5 mm pockets, 2 mm apart in x.
std::vector<ProbingSite> TwoSites() {
  std::vector<ProbingSite> v(2);
  for (int i = 0; i < 2; ++i) {
    ProbingSite& s = v[static_cast<std::size_t>(i)];
    s.fdi = 46;
    s.site = i;
    s.margin_W = Vector3(2.0 * i, 0, 0);
    s.floor_W = Vector3(2.0 * i, 0, -5);
    s.axis_W = Vector3::UnitZ();
    s.origin_W = Vector3(1.0, -3.0, -10);  // the tooth's axis behind the lines
    s.sulcus_r_mm = (s.margin_W - s.origin_W).head<2>().norm();
    s.pocket_mm = 5;
  }
  return v;
}

RigidTransform Tip(const Vector3& p) {
  return RigidTransform(Quaternion::Identity(), p);  // the probe's axis up (+z)
}

struct Fed {
  std::vector<ProbeReading> readings;
};

// Feeds (position, force along the probe) per tick; completes at the end.
Fed Feed(const std::vector<std::pair<Vector3, double>>& path, bool complete = true) {
  static const std::vector<ProbingSite> sites = TwoSites();
  const TipLocator locator(sites);
  ProbeReadingTracker tracker(kRate);
  Fed out;
  std::uint64_t tick = 1;
  for (const auto& [p, f] : path) {
    const TipLocation at = locator.Locate(Tip(p), tracker.site());
    ProbeReading r;
    if (tracker.Update(tick, at, f, &r)) out.readings.push_back(r);
    ++tick;
  }
  ProbeReading r;
  if (complete && tracker.Complete(tick - 1, &r)) out.readings.push_back(r);
  return out;
}

// A careful stroke at site x: down at `speed` mm/s to `depth`, a rest of
// `rest_s` pressing `force` N, then out; `tremor_mm` at 10 Hz along the probe
// and a drift of `drift_mm_s` while resting; `overshoot_mm` past the floor
// (pressing 2 N/mm harder) for 0.15 s before the rest.
struct Stroke {
  double x = 0, depth = 4.0, speed = 12, rest_s = 0.5, force = 0.22;
  double tremor_mm = 0, drift_mm_s = 0, overshoot_mm = 0;
};
void Add(const Stroke& s, std::vector<std::pair<Vector3, double>>* path) {
  const double dt = 1.0 / kRate;
  for (double z = -1.0; z < s.depth; z += s.speed * dt)
    path->push_back({Vector3(s.x, 0, -z),
                     z > s.depth - 0.1 ? s.force * (z - s.depth + 0.1) / 0.1 : 0});
  for (double t = 0; t < 0.15 && s.overshoot_mm > 0; t += dt)
    path->push_back(
        {Vector3(s.x, 0, -(s.depth + s.overshoot_mm)), s.force + 2.0 * s.overshoot_mm});
  for (double t = 0; t < s.rest_s; t += dt) {
    const double w = s.tremor_mm * std::sin(2 * std::numbers::pi * 10.0 * t);
    const double d = s.depth + w + s.drift_mm_s * t;
    path->push_back(
        {Vector3(s.x, 0, -d), std::max(0.0, s.force + 2.0 * (w + s.drift_mm_s * t))});
  }
  for (double z = s.depth; z > -1.0; z -= 20 * dt)
    path->push_back({Vector3(s.x, 0, -z), 0});
}

TEST(ProbeReading, OneStrokeIsOneReadingWithTheForceHeld) {
  std::vector<std::pair<Vector3, double>> path;
  Add(Stroke{}, &path);
  const Fed r = Feed(path);
  ASSERT_EQ(r.readings.size(), 1u);
  EXPECT_EQ(r.readings[0].site, 0);
  EXPECT_NEAR(r.readings[0].depth_mm, 4.0, 0.02);
  EXPECT_NEAR(r.readings[0].held_force_n, 0.22, 0.01);
  EXPECT_NEAR(r.readings[0].peak_force_n, 0.22, 1e-9);
  EXPECT_FALSE(r.readings[0].update);
}

TEST(ProbeReading, TremorNeitherMultipliesReadingsNorMovesTheHeldForceOutOfTheBand) {
  for (const double tremor : {0.05, 0.10, 0.15}) {
    std::vector<std::pair<Vector3, double>> path;
    Stroke s;
    s.tremor_mm = tremor;
    s.rest_s = 2.0;
    Add(s, &path);
    const Fed r = Feed(path);
    ASSERT_EQ(r.readings.size(), 1u) << tremor << " mm: one dwell, one reading";
    // The highest tick swings with the tremor (2 N/mm against the floor); the
    // force held is the hand's.
    EXPECT_NEAR(r.readings[0].peak_force_n, 0.22 + 2 * tremor, 0.01) << tremor;
    EXPECT_GE(r.readings[0].held_force_n, 0.15) << tremor;
    EXPECT_LE(r.readings[0].held_force_n, 0.30) << tremor;
    EXPECT_NEAR(r.readings[0].depth_mm, 4.0 + tremor, 0.02) << tremor;
  }
}

TEST(ProbeReading, AnOvershootAndBackOffHoldsTheRestsForceAndKeepsThePeak) {
  std::vector<std::pair<Vector3, double>> path;
  Stroke s;
  s.overshoot_mm = 0.15;  // 0.52 N for 0.15 s, then a rest of 0.5 s at 0.22 N
  Add(s, &path);
  const Fed r = Feed(path);
  ASSERT_EQ(r.readings.size(), 1u);
  EXPECT_NEAR(r.readings[0].depth_mm, 4.15, 0.02);
  EXPECT_NEAR(r.readings[0].peak_force_n, 0.52, 0.01);
  EXPECT_LT(r.readings[0].held_force_n, 0.30);
}

TEST(ProbeReading, AWalkAlongTheSulcusReadsEachSitePassedAtItsDeepest) {
  // Down at site 0 to 3 mm, then along the sulcus to site 1 at 3 to 4 mm deep
  // (short up-and-down strokes), resting at site 1's floor.
  std::vector<std::pair<Vector3, double>> path;
  for (double z = -1; z < 3; z += 0.012) path.push_back({Vector3(0, 0, -z), 0});
  for (int i = 0; i <= 2000; ++i) {
    const double x = 2.0 * i / 2000, z = 3.5 + 0.5 * std::sin(i * 0.02);
    path.push_back({Vector3(x, 0, -z), 0.1});
  }
  for (int i = 0; i < 300; ++i) path.push_back({Vector3(2, 0, -4.2), 0.22});
  const Fed r = Feed(path);
  ASSERT_EQ(r.readings.size(), 2u);
  EXPECT_EQ(r.readings[0].site, 0);
  EXPECT_EQ(r.readings[1].site, 1);
  EXPECT_NEAR(r.readings[1].depth_mm, 4.2, 1e-9) << "completed with the tip still in";
  EXPECT_NEAR(r.readings[1].held_force_n, 0.22, 0.01);
  EXPECT_LE(r.readings[0].depth_mm, 4.0 + 1e-9);
  EXPECT_GT(r.readings[0].depth_mm, 3.0);
}

TEST(ProbeReading, ATremorAcrossTheLineBetweenTwoSitesDoesNotEndTheVisit) {
  // Resting at the boundary's near side of site 0 (x = 0.95), trembling 0.1 mm
  // across to site 1's side for 40 ms in every 100 ms (a visit ends after 100 ms away).
  std::vector<std::pair<Vector3, double>> path;
  for (double z = -1; z < 3; z += 0.012) path.push_back({Vector3(0.9, 0, -z), 0});
  for (int i = 0; i < 2000; ++i) {
    const bool across = i % 100 < 40;
    path.push_back({Vector3(across ? 1.1 : 0.9, 0, -3), 0.2});
  }
  for (double z = 3; z > -1; z -= 0.02) path.push_back({Vector3(0.9, 0, -z), 0});
  const Fed r = Feed(path);
  ASSERT_EQ(r.readings.size(), 1u);
  EXPECT_EQ(r.readings[0].site, 0);
}

TEST(ProbeReading, SlowWorkAndAShallowVisit) {
  std::vector<std::pair<Vector3, double>> path;
  Stroke slow;
  slow.speed = 1.0;
  slow.rest_s = 0.3;
  Add(slow, &path);
  const Fed r = Feed(path);
  ASSERT_EQ(r.readings.size(), 1u);
  EXPECT_NEAR(r.readings[0].held_force_n, 0.22, 0.03)
      << "the way down at 1 mm/s is not the stay at the floor";
  // 0.4 mm deep: no reading.
  std::vector<std::pair<Vector3, double>> shallow;
  Stroke s;
  s.depth = 0.4;
  Add(s, &shallow);
  EXPECT_TRUE(Feed(shallow).readings.empty());
}

// Charting a site completes its reading: a deeper dwell later in the same
// visit is not its reading (the student charted what the probe showed then);
// leaving the site and entering it again is a re-probe, a reading of its own.
TEST(ProbeReading, ChartingSealsTheVisitAndOnlyANewEntryReadsAgain) {
  const std::vector<ProbingSite> sites = TwoSites();
  const TipLocator locator(sites);
  ProbeReadingTracker tracker(kRate);
  ProbeReading r;
  std::uint64_t t = 1;
  auto at = [&](double z) {
    return locator.Locate(Tip(Vector3(0, 0, -z)), tracker.site());
  };
  for (int i = 0; i < 100; ++i) EXPECT_FALSE(tracker.Update(t++, at(3.0), 0.2, &r));
  ASSERT_TRUE(tracker.Complete(t, &r));
  EXPECT_FALSE(r.update);
  EXPECT_NEAR(r.depth_mm, 3.0, 1e-9);
  EXPECT_FALSE(tracker.Complete(t, &r)) << "nothing new";
  // Deeper with more force, the same visit: nothing read, now or when it ends.
  for (int i = 0; i < 100; ++i) EXPECT_FALSE(tracker.Update(t++, at(3.6), 0.31, &r));
  EXPECT_FALSE(tracker.Complete(t, &r));
  // Out of the sulcus (above the margin) for 0.2 s: the visit ends, unread.
  for (int i = 0; i < 200; ++i)
    EXPECT_FALSE(tracker.Update(t++, locator.Locate(Tip(Vector3(0, 0, 2))), 0, &r));
  // In again: a new visit, read on its own.
  for (int i = 0; i < 100; ++i) EXPECT_FALSE(tracker.Update(t++, at(3.4), 0.25, &r));
  ASSERT_TRUE(tracker.Complete(t, &r));
  EXPECT_FALSE(r.update) << "a new insertion";
  EXPECT_NEAR(r.depth_mm, 3.4, 1e-9);
  EXPECT_NEAR(r.held_force_n, 0.25, ProbeReadingTracker::kBinN);
}

TEST(TipLocator, TheNearerLineWinsAndFarFromEveryLineIsNowhere) {
  const std::vector<ProbingSite> sites = TwoSites();
  const TipLocator locator(sites);
  EXPECT_EQ(locator.Locate(Tip(Vector3(0.3, 0, -2))).site, 0);
  EXPECT_EQ(locator.Locate(Tip(Vector3(1.7, 0, -2))).site, 1);
  EXPECT_NEAR(locator.Locate(Tip(Vector3(0.3, 0, -2))).depth_mm, 2.0, 1e-12);
  EXPECT_EQ(locator.Locate(Tip(Vector3(5, 0, -2))).site, -1) << "beyond 1.2 mm";
  EXPECT_EQ(locator.Locate(Tip(Vector3(0, 0, 1))).site, -1) << "1 mm above the margin";
  EXPECT_EQ(locator.Locate(Tip(Vector3(0, 0, -6))).site, -1) << "1 mm past the floor";
  EXPECT_EQ(locator.Locate(Tip(Vector3(0, 0, -6)), 0).site, 0)
      << "pushed on through the floor it stays with its site";
  EXPECT_TRUE(locator.Near(Tip(Vector3(1.1, 0, -2)), 0));
  EXPECT_NEAR(TipLocator::ProbingForce(Vector3(0, 0, 0.3), Tip(Vector3::Zero())), 0.3,
              1e-12);
  EXPECT_EQ(TipLocator::ProbingForce(Vector3(0, 0, -0.3), Tip(Vector3::Zero())), 0.0);
}

}  // namespace
}  // namespace sulcus
