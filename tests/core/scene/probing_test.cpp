// End to end on the shipped probing scene: the scripted probe goes down the
// buccal sulcus of tooth 46 through the soft gingiva to the pocket floor, and
// the probing_depth effect reads the scene's depth. Also: an effect the scene
// does not name is not in the loop at all.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/haptics/effects.h"
#include "core/haptics/scripted_device.h"
#include "core/scene/scene.h"
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
  ScriptedDevice device(MakeScript("insert", target, 4.0));
  const auto effects = MakeEffects(scene->effects);
  const auto list = EffectPointers(effects);
  ASSERT_EQ(list.size(), 3u);  // compliance, depth + bleeding, damage
  HapticLoop loop(*scene->model, &device, {}, list);
  std::vector<double> readings;
  double max_force = 0;
  for (int i = 0; i < 4000; ++i) {
    loop.Tick(false);
    max_force = std::max(max_force, loop.last_record().force_W.norm());
    HapticEvent e;
    while (loop.PopEvent(&e))
      if (e.kind == EventKind::kEffect && e.detail == static_cast<std::uint8_t>(EffectEvent::kProbeReading)) {
        EXPECT_EQ(e.object, target.object);
        EXPECT_EQ(e.value2, 1.0) << "site B";
        readings.push_back(e.value);
      }
  }
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
