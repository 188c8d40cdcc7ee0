// The effects a scene names, each on its own over a block the probe presses:
// made only when named and given something to act on; the damage limit, the
// calculus deposit and the carious lesion each do what the scene file promises.
#include "core/haptics/effects.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "tests/core/haptics/test_scenes.h"

namespace sulcus {
namespace {

using test::At;

// A probe over two blocks whose tops are at z = 0: object 0 at the origin,
// object 1 at x = 20.
struct Rig {
  explicit Rig(EffectsModel m) : effects_model(std::move(m)) {
    scene.tool = std::make_unique<SphereTree>(test::MakeProbe());
    scene.Add(test::MakeBlock(3, 3, -1.5, -0.5, 0.5, 0.5), RigidTransform::Identity());
    scene.Add(test::MakeBlock(3, 3, -1.5, -0.5, 0.5, 0.5), At(20, 0, 0));
    model = scene.Model();
    effects = MakeEffects(effects_model);
    pointers = EffectPointers(effects);
    loop = std::make_unique<HapticLoop>(*model, &device, LoopOptions{}, pointers);
    loop->Reset(At(0, 0, 2));
  }
  // `n` ticks with the device at `pose`; keeps the events of `kind`.
  void Hold(const RigidTransform& pose, int n, EventKind kind) {
    device.pose = pose;
    for (int i = 0; i < n; ++i) {
      loop->Tick(false);
      const TickRecord& r = loop->last_record();
      for (int e = 0; e < r.num_events; ++e)
        if (r.events[e].kind == kind) events.push_back(r.events[e]);
    }
  }
  EffectsModel effects_model;
  test::Scene scene;
  std::unique_ptr<EngineModel> model;
  test::PuppetDevice device;
  std::vector<std::unique_ptr<LoopEffect>> effects;
  std::vector<LoopEffect*> pointers;
  std::unique_ptr<HapticLoop> loop;
  std::vector<HapticEvent> events;
};

std::vector<std::string> Names(const EffectsModel& m) {
  std::vector<std::string> names;
  for (const auto& e : MakeEffects(m)) names.push_back(e->name());
  return names;
}

// An effect is in the loop only when the scene names it and it has something to
// act on: named without its data (a lesion, a deposit, a site) it is left out.
TEST(Effects, EachIsMadeOnlyWhenNamedAndGivenSomethingToActOn) {
  EffectsModel m;
  EXPECT_TRUE(Names(m).empty());
  m.on.caries_catch = m.on.calculus = m.on.probing_depth = true;
  EXPECT_TRUE(Names(m).empty()) << "named, but no lesion, deposit or site";
  m.lesions.push_back({0, Vector3::Zero(), Vector3::UnitZ(), 1.0, 4});
  m.deposits = {{0, 0}, {46, 2}};
  EXPECT_EQ(Names(m), (std::vector<std::string>{"caries_catch", "calculus"}));
  m.on = {};
  m.on.tissue_damage = true;
  m.damage_limit_n = {1.0, 1.0};
  EXPECT_EQ(Names(m), (std::vector<std::string>{"tissue_damage"}));
}

// A press above an object's limit is one damage event naming the object and the
// force; pressing on while it stays above adds none; a new press after letting
// go is a new event. Under the limit, none.
EffectsModel Damage(double limit_n) {
  EffectsModel m;
  m.on.tissue_damage = true;
  m.damage_limit_n = {limit_n, limit_n};
  return m;
}

EffectsModel Calculus() {
  EffectsModel m;
  m.on.calculus = true;
  m.deposits = {{0, 0}, {46, 2}};
  return m;
}

EffectsModel Caries() {
  EffectsModel m;
  m.on.caries_catch = true;
  m.lesions.push_back({0, Vector3::Zero(), Vector3::UnitZ(), 1.0, 4});
  return m;
}

TEST(Effects, TissueDamageIsOneEventPerPressAboveTheLimit) {
  Rig rig(Damage(0.5));
  rig.Hold(At(0, 0, -0.5), 600, EventKind::kTissueDamage);  // about 0.75 N
  ASSERT_EQ(rig.events.size(), 1u);
  EXPECT_EQ(rig.events[0].object, 0);
  EXPECT_GT(rig.events[0].payload.damage.force_n, 0.5);
  EXPECT_EQ(rig.events[0].payload.damage.limit_n, 0.5);
  rig.Hold(At(0, 0, 3), 300, EventKind::kTissueDamage);
  rig.Hold(At(0, 0, -0.5), 600, EventKind::kTissueDamage);
  EXPECT_EQ(rig.events.size(), 2u) << "a second press is a second episode";

  Rig gentle(Damage(5.0));
  gentle.Hold(At(0, 0, -0.5), 600, EventKind::kTissueDamage);
  EXPECT_TRUE(gentle.events.empty());
}

// A deposit announces itself once per contact with its tooth and site; the
// block that is not a deposit never does.
TEST(Effects, ACalculusDepositIsAnnouncedOncePerContact) {
  Rig rig(Calculus());
  rig.Hold(At(0, 0, -0.2), 400, EventKind::kCalculusTouched);
  EXPECT_TRUE(rig.events.empty()) << "object 0 is not a deposit";
  rig.Hold(At(20, 0, -0.2), 400, EventKind::kCalculusTouched);
  ASSERT_EQ(rig.events.size(), 1u);
  EXPECT_EQ(rig.events[0].object, 1);
  EXPECT_EQ(rig.events[0].payload.calculus.fdi, 46);
  EXPECT_EQ(rig.events[0].payload.calculus.site, 2);
  rig.Hold(At(20, 0, 3), 300, EventKind::kCalculusTouched);
  rig.Hold(At(20, 0, -0.2), 400, EventKind::kCalculusTouched);
  EXPECT_EQ(rig.events.size(), 2u);
}

// A carious lesion is softer than enamel: pressed at its centre the same press
// pushes back with the lesion's share of the force, and a firm press catches.
TEST(Effects, ACariousLesionIsSofterAndCatchesAFirmPress) {
  Rig lesion(Caries());
  lesion.Hold(At(0, 0, -0.5), 600, EventKind::kCariesCatch);
  Rig sound(Caries());
  // Over the sound enamel first, then down onto it (a diagonal press would
  // rest in a valley between the block's spheres, with another force).
  sound.Hold(At(2.5, 0, 2), 100, EventKind::kCariesCatch);
  sound.Hold(At(2.5, 0, -0.5), 600, EventKind::kCariesCatch);
  const double soft = lesion.loop->last_record().force_W.z();
  const double firm = sound.loop->last_record().force_W.z();
  ASSERT_GT(firm, 0.5);
  // At the centre the force keeps `softness` of itself, at the rim (the radius
  // and the tip's reach, 0.3 mm) all of it; the tip's centre stands over the
  // surface by its radius.
  const double d = lesion.loop->last_record().X_WG.translation().norm();
  const double weight = 1 - d / (1.0 + 0.3);
  EXPECT_NEAR(soft / firm, 1 - (1 - CariesFeel{}.softness) * weight, 0.03);
  EXPECT_LT(soft / firm, 0.8);
  EXPECT_EQ(lesion.events.size(), 1u) << "the press above the catch force caught";
  EXPECT_TRUE(sound.events.empty());
}

}  // namespace
}  // namespace sulcus
