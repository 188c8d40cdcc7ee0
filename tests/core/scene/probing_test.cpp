// End to end on the shipped probing scene: the scripted probe goes down the
// buccal sulcus of tooth 46 through the soft gingiva to the pocket floor, and
// the probing_depth effect reads the scene's depth. Also: an effect the scene
// does not name is not in the loop at all.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/haptics/effects.h"
#include "core/haptics/scripted_device.h"
#include "core/scene/scene.h"
#include "core/session/session.h"
#include "tests/common/alloc_guard.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

fs::path Cache() { return fs::path(SULCUS_TEST_OUTPUT) / "probing-cache"; }

TEST(Probing, InsertReadsThePocketDepthAtTooth46Buccal) {
  const SceneSpec spec = LoadSceneSpec(fs::path(SULCUS_SOURCE_DIR) / "scenes" / "periodontal_probing.yaml");
  const auto scene = CompileScene(spec, Cache());
  const ScriptTarget target = FindScriptTarget(*scene, "insert");
  ASSERT_GE(target.object, 0);
  EXPECT_EQ(scene->spec.objects[target.object].fdi, 46) << "the deepest buccal pocket";
  DeviceSpec d;
  d.device = std::make_unique<ScriptedDevice>(MakeScript("insert", target, 4.0));
  SessionOptions so;
  so.max_ticks = 4000;
  Session session(*scene, std::move(d), so);
  ASSERT_EQ(session.effects().size(), 3u);  // compliance, depth + bleeding, damage
  // The test is one more consumer of the tick stream.
  struct Readings final : TickConsumer {
    void OnTick(const TickRecord& r) override {
      max_force = std::max(max_force, r.force_W.norm());
      for (int i = 0; i < r.num_events; ++i)
        if (r.events[i].kind == EventKind::kProbeReading) events.push_back(r.events[i]);
    }
    std::vector<HapticEvent> events;
    double max_force = 0;
  } consumer;
  session.AddConsumer(&consumer);
  session.RunOffline();
  std::vector<double> readings;
  for (const HapticEvent& e : consumer.events) {
    EXPECT_EQ(e.object, target.object);
    EXPECT_EQ(e.payload.reading.fdi, 46);
    EXPECT_EQ(e.payload.reading.site, 1) << "site B";
    EXPECT_GT(e.payload.reading.peak_force_n, 0.1) << "pressed at the floor";
    EXPECT_LT(e.payload.reading.axis_angle_deg, 15.0) << "the insert tilts 8.5 degrees buccally";
    EXPECT_LE(e.payload.reading.entered_tick, e.payload.reading.deepest_tick);
    EXPECT_LE(e.payload.reading.deepest_tick, e.tick);
    readings.push_back(e.payload.reading.depth_mm);
  }
  const double max_force = consumer.max_force;
  HapticLoop& loop = session.loop();
  ASSERT_EQ(readings.size(), 1u) << "one insertion, one reading";
  const double truth = scene->spec.objects[target.object].pocket_mm[1];
  EXPECT_NEAR(readings[0], truth, 0.3) << "the tip reaches the pocket floor";
  EXPECT_LT(max_force, 1.0) << "through the sulcus, not through the gingiva";
  EXPECT_EQ(loop.faults().total(), 0u);

  // The loop with effects allocates nothing per tick.
  test::AllocationGuard guard;
  for (int i = 0; i < 500; ++i) loop.Tick(false);
  EXPECT_EQ(guard.allocations(), 0u);
}

TEST(Probing, AnEffectNotNamedIsNotInTheLoop) {
  EffectsModel m;  // contact only
  EXPECT_TRUE(MakeEffects(m).empty());
  m.on.tissue_damage = true;
  m.damage_limit_n = {1.0};
  const auto one = MakeEffects(m);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_STREQ(one[0]->name(), "tissue_damage");
  m.on = {};
  m.on.probing_depth = true;  // no sites (no gingiva): nothing to measure, nothing runs
  EXPECT_TRUE(MakeEffects(m).empty());
}

}  // namespace
}  // namespace sulcus
