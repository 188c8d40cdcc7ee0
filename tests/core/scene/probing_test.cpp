// End to end on the shipped probing scene: the scripted probe goes down the
// buccal sulcus of tooth 46 through the soft gingiva to the pocket floor, and
// the probing_depth effect reads the scene's depth. Also: an effect the scene
// does not name is not in the loop at all.
#include <gtest/gtest.h>

#include <filesystem>
#include <optional>

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

// Friction on a tooth: the probe pressed 1 mm into the crown of the scene's
// first tooth along its surface normal, then the device moved sideways. With
// friction named (coefficient 0.3 on every object), a sideways offset of a fifth
// of the push leaves the tool where it touched and one of twice the push makes
// it slide; without friction the same small offset already moves it. And a
// scene that does not name friction has none in its model.
TEST(Probing, FrictionHoldsAProbeOnAToothBelowItsConeAndLetsItSlideAbove) {
  SceneSpec spec = LoadSceneSpec(fs::path(SULCUS_SOURCE_DIR) / "scenes" / "periodontal_probing.yaml");
  ASSERT_FALSE(spec.HasEffect(Effect::kFriction));
  EXPECT_TRUE(CompileScene(spec, Cache())->model->friction.empty()) << "not named: no friction in the model";
  auto run = [&](bool friction, double offset_mm) {
    SceneSpec s = spec;
    if (friction) s.effects.push_back(Effect::kFriction);
    for (ObjectSpec& o : s.objects) o.material.friction = 0.3;
    const auto scene = CompileScene(s, Cache());
    EXPECT_EQ(scene->model->friction.empty(), !friction);
    const ScriptTarget target = FindScriptTarget(*scene, "poke");
    const Vector3 n = target.n_W;
    const Vector3 t = n.unitOrthogonal();
    const Matrix3 R = Quaternion::FromTwoVectors(Vector3::UnitZ(), n).toRotationMatrix();
    EngineData d(*scene->model);
    ResetTool(RigidTransform(R, target.p_W + 2 * n), &d);
    std::optional<Vector3> touched;
    for (int i = 0; i < 3000; ++i) {
      const double down = std::min(3.0, 0.01 * i);  // to 1 mm below the surface point
      const double side = i < 1000 ? 0 : std::min(offset_mm, 0.001 * (i - 1000));
      Step(*scene->model, RigidTransform(R, target.p_W + (2 - down) * n + side * t), &d);
      if (!touched && d.active_contacts > 0) touched = d.X_WG.translation();
      if (i == 999) touched = d.X_WG.translation();  // where it rests before the sideways move
    }
    EXPECT_EQ(d.faults.total(), 0u);
    return touched ? ((d.X_WG.translation() - *touched) - (d.X_WG.translation() - *touched).dot(n) * n).norm() : -1.0;
  };
  EXPECT_LT(run(true, 0.2), 0.02) << "stuck: the tool stays where it touched";
  EXPECT_GT(run(true, 2.0), 0.5) << "slides once the spring leans past the cone";
  EXPECT_GT(run(false, 0.2), 0.1) << "without friction the small offset already moves it";
}

}  // namespace
}  // namespace sulcus
