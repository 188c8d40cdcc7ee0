// End to end on the shipped probing scene: the scripted probe goes down the
// buccal sulcus of tooth 46 through the soft gingiva to the pocket floor, and
// the probing_depth effect reads the scene's depth. Also: an effect the scene
// does not name is not in the loop at all.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <numbers>
#include <optional>

#include "core/anatomy/soft_tissue.h"
#include "core/haptics/effects.h"
#include "core/haptics/probe_keys.h"
#include "core/haptics/scripted_device.h"
#include "core/haptics/tip_locator.h"
#include "core/scene/scene.h"
#include "core/session/session.h"
#include "core/spheretree/cache.h"
#include "tests/common/alloc_guard.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

fs::path Cache() { return fs::path(SULCUS_TEST_OUTPUT) / "probing-cache"; }

// Plays `keys` on `scene` offline for `ticks` ticks; `consumer`, if given, sees
// every tick. The session is returned for its loop's state after the run.
std::unique_ptr<Session> PlayOffline(const CompiledScene& scene,
                                     std::vector<Keyframe> keys, std::uint64_t ticks,
                                     const std::string& name,
                                     TickConsumer* consumer = nullptr) {
  DeviceSpec d;
  d.device = std::make_unique<ScriptedDevice>(Trajectory(std::move(keys)), name);
  SessionOptions so;
  so.max_ticks = ticks;
  auto session = std::make_unique<Session>(scene, std::move(d), so);
  if (consumer) session->AddConsumer(consumer);
  session->RunOffline();
  return session;
}

TEST(Probing, InsertReadsThePocketDepthAtTooth46Buccal) {
  const SceneSpec spec =
      LoadSceneSpec(fs::path(SULCUS_SOURCE_DIR) / "scenes" / "periodontal_probing.yaml");
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
    EXPECT_LT(e.payload.reading.axis_angle_deg, 15.0)
        << "the insert tilts 8.5 degrees buccally";
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
  SceneSpec spec =
      LoadSceneSpec(fs::path(SULCUS_SOURCE_DIR) / "scenes" / "periodontal_probing.yaml");
  ASSERT_FALSE(spec.HasEffect(Effect::kFriction));
  EXPECT_TRUE(CompileScene(spec, Cache())->model->friction.empty())
      << "not named: no friction in the model";
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
      if (i == 999)
        touched = d.X_WG.translation();  // where it rests before the sideways move
    }
    EXPECT_EQ(d.faults.total(), 0u);
    return touched ? ((d.X_WG.translation() - *touched) -
                      (d.X_WG.translation() - *touched).dot(n) * n)
                         .norm()
                   : -1.0;
  };
  EXPECT_LT(run(true, 0.2), 0.02) << "stuck: the tool stays where it touched";
  EXPECT_GT(run(true, 2.0), 0.5) << "slides once the spring leans past the cone";
  EXPECT_GT(run(false, 0.2), 0.1) << "without friction the small offset already moves it";
}

}  // namespace
}  // namespace sulcus

#include "core/anatomy/arch.h"
#include "core/anatomy/gingiva.h"

namespace sulcus {
namespace {

// Interproximal probing: the probe, tilted buccally as a clinician tilts it to
// reach under the contact, goes down between 45 and 46 at 46's mesial surface
// (the point under the contact, where the col is) and reaches that point's
// pocket floor, pressing it; through the soft gingiva of both teeth, past 45's
// crown, with no engine fault.
TEST(Probing, UnderTheContactBetween45And46TheTipReachesTheFloor) {
  const SceneSpec spec =
      LoadSceneSpec(fs::path(SULCUS_SOURCE_DIR) / "scenes" / "periodontal_probing.yaml");
  const auto scene = CompileScene(spec, Cache());
  const ObjectSpec* tooth = nullptr;
  for (const ObjectSpec& o : scene->spec.objects)
    if (o.kind == ObjectSpec::Kind::kTooth && o.fdi == 46) tooth = &o;
  ASSERT_NE(tooth, nullptr);
  GingivaParams gp;
  gp.pocket_mm = tooth->pocket_mm;
  gp.recession_mm = tooth->recession_mm;
  const GingivaModel g = GenerateGingiva(GenerateTooth(46), gp);
  // In 46's frame (+x mesial, toward 45; +y buccal; +z occlusal): the sulcus'
  // middle at the mesial point, and its floor there.
  const double floor_z = g.FloorAt(0), r = g.sulcus_r[0];
  ASSERT_LT(floor_z, g.margin_z[0] - 4.0)
      << "a deep interproximal pocket (5 and 5 mm at MB and ML)";
  auto world = [&](const Vector3& p_T) {
    return Vector3(tooth->X_WO * ArchMirror(tooth->mirrored, p_T));
  };
  const Matrix3 R = tooth->X_WO.rotation() *
                    (tooth->mirrored ? Vector3(-1, 1, 1) : Vector3(1, 1, 1)).asDiagonal();
  const double tilt = 20 * std::numbers::pi / 180;
  const Vector3 up_T(0, std::sin(tilt),
                     std::cos(tilt));        // the working end toward the shank
  const Vector3 end_T(r, 0, floor_z - 0.3);  // 0.3 mm past the floor: pressing it
  const Quaternion q =
      Quaternion::FromTwoVectors(Vector3::UnitZ(), (R * up_T).normalized());
  std::vector<Keyframe> keys;
  const double travel = 9.0, speed = 4.0;  // mm, mm/s
  const int ticks = static_cast<int>(travel / speed * 1000);
  for (int i = 0; i <= ticks; i += 10)
    keys.push_back({i * 0.001, world(end_T + (travel - speed * i * 0.001) * up_T), q, 0});
  struct Deepest final : TickConsumer {
    void OnTick(const TickRecord& rec) override { last = rec; }
    TickRecord last;
  } consumer;
  const auto session =
      PlayOffline(*scene, std::move(keys), static_cast<std::uint64_t>(ticks + 400),
                  "interproximal", &consumer);
  // Where the rendered tip ended, in 46's frame.
  const Vector3 tip_T = ArchMirror(
      tooth->mirrored, tooth->X_WO.inverse() * consumer.last.X_WG.translation());
  std::printf("tip %.2f %.2f %.2f, floor %.2f at r %.2f, margin %.2f, force %.3f N\n",
              tip_T.x(), tip_T.y(), tip_T.z(), floor_z, r, g.margin_z[0],
              consumer.last.force_W.norm());
  EXPECT_LE(tip_T.z(), floor_z + 0.2) << "the tip reached the floor under the contact";
  EXPECT_GE(tip_T.z(), floor_z - 0.8) << "and pressed it, not through it";
  EXPECT_NEAR(tip_T.x(), r, 0.8) << "in the sulcus, not pushed out of it";
  EXPECT_LT(std::abs(tip_T.y()), 1.0) << "under the contact, between buccal and lingual";
  EXPECT_GT(consumer.last.force_W.norm(), 0.1) << "pressing the floor";
  EXPECT_LT(consumer.last.force_W.norm(), 1.5);
  EXPECT_EQ(session->loop().faults().total(), 0u);
}

}  // namespace
}  // namespace sulcus

namespace sulcus {
namespace {

// The scripted insert in the full mouth: the shank leans over the crown, not out
// through the cheek or lip, so the probe goes down the sulcus of the tooth it
// was aimed at from a free start: no engine fault, no saturated force.
TEST(Probing, TheScriptedInsertInTheFullMouthKeepsItsShankOutOfTheCheek) {
  const SceneSpec spec =
      LoadSceneSpec(fs::path(SULCUS_SOURCE_DIR) / "scenes" / "oral_inspection.yaml");
  // The user's cache, as the window uses it: the full mouth is built once for both.
  const auto scene = CompileScene(spec, DefaultCacheDir());
  const ScriptTarget target = FindScriptTarget(*scene, "insert");
  EXPECT_EQ(scene->spec.objects[target.object].fdi, 46)
      << "the lower tooth with the deepest buccal pocket";
  EXPECT_GT(ScriptOrientation(target).toRotationMatrix().col(0).dot(target.n_W), 0.9)
      << "the tool's +x buccal: its shank (-x) leans lingually";
  DeviceSpec d;
  d.device = std::make_unique<ScriptedDevice>(MakeScript("insert", target, 4.0));
  SessionOptions so;
  so.max_ticks = 4000;
  Session session(*scene, std::move(d), so);
  struct Force final : TickConsumer {
    void OnTick(const TickRecord& r) override {
      max_force = std::max(max_force, r.force_W.norm());
    }
    double max_force = 0;
  } consumer;
  session.AddConsumer(&consumer);
  session.RunOffline();
  EXPECT_EQ(session.loop().faults().total(), 0u);
  EXPECT_GT(consumer.max_force, 0.1) << "it touched the pocket floor";
  EXPECT_LT(consumer.max_force, 1.0) << "and nothing it should not";
}

}  // namespace
}  // namespace sulcus

namespace sulcus {
namespace {

// Pockets changed after loading (as a generated case changes them) get the bone
// that goes with them: the jaw's crest is set when the scene is compiled, so the
// probe reaches a 6 mm pocket at 44 B instead of stopping on the bone 1.5 mm
// below the CEJ.
TEST(Probing, ADeepenedPocketHasItsBoneLoweredToo) {
  SceneSpec spec =
      LoadSceneSpec(fs::path(SULCUS_SOURCE_DIR) / "scenes" / "periodontal_probing.yaml");
  for (ObjectSpec& o : spec.objects)
    if ((o.kind == ObjectSpec::Kind::kTooth || o.kind == ObjectSpec::Kind::kGingiva) &&
        o.fdi == 44)
      o.pocket_mm[1] = 6;
  const auto scene = CompileScene(spec, Cache());
  for (const ObjectSpec& o : scene->spec.objects)
    if (o.kind == ObjectSpec::Kind::kAnatomy && o.anatomy == "jaw_lower") {
      EXPECT_EQ(o.crest_drop_mm.at(44), 5.5);
    }
  const ScriptTarget target = FindScriptTarget(*scene, "insert");
  ASSERT_EQ(scene->spec.objects[target.object].fdi, 44);
  DeviceSpec d;
  d.device = std::make_unique<ScriptedDevice>(MakeScript("insert", target, 4.0));
  SessionOptions so;
  so.max_ticks = 4000;
  Session session(*scene, std::move(d), so);
  struct Readings final : TickConsumer {
    void OnTick(const TickRecord& r) override {
      for (int i = 0; i < r.num_events; ++i)
        if (r.events[i].kind == EventKind::kProbeReading)
          depth.push_back(r.events[i].payload.reading.depth_mm);
    }
    std::vector<double> depth;
  } consumer;
  session.AddConsumer(&consumer);
  session.RunOffline();
  ASSERT_EQ(consumer.depth.size(), 1u);
  EXPECT_NEAR(consumer.depth[0], 6.0, 0.4);
}

}  // namespace
}  // namespace sulcus

#include "core/anatomy/mesh_contact.h"
#include "core/anatomy/probe.h"
#include "core/geometry/mesh_io.h"
#include "core/haptics/engine.h"
#include "core/spheretree/metrics.h"

namespace sulcus {
namespace {

// A compiled scene's objects as their exact meshes, placed in the world (those
// `keep` accepts; every one by default), and the probe's exact mesh at a pose:
// what the engine's felt surface is measured against.
struct ExactScene {
  explicit ExactScene(const CompiledScene& scene,
                      const std::function<bool(const ObjectSpec&)>& keep = {})
      : tool(scene.tool_mesh) {
    for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
      const ObjectSpec& o = scene.spec.objects[i];
      if (keep && !keep(o)) continue;
      TriangleMesh m = scene.meshes[i];
      m.Transform(o.X_WO.rotation(), o.X_WO.translation());
      objects.push_back(std::move(m));
    }
  }
  TriangleMesh Probe(const RigidTransform& X) const {
    TriangleMesh probe = tool;
    probe.Transform(X.rotation(), X.translation());
    return probe;
  }
  // Whether the probe at X meets none of the objects (exact triangle tests).
  bool ProbeFree(const RigidTransform& X) const {
    const TriangleMesh probe = Probe(X);
    for (const TriangleMesh& m : objects)
      if (MeshesIntersect(probe, m)) return false;
    return true;
  }
  std::vector<TriangleMesh> objects;
  const TriangleMesh& tool;
};

// Bisection between a value where `free_at` is false and one where it is true,
// to within `tolerance`: the free end.
double FreeEnd(const std::function<bool(double)>& free_at, double touching, double free,
               double tolerance) {
  while (std::abs(free - touching) > tolerance) {
    const double mid = 0.5 * (touching + free);
    (free_at(mid) ? free : touching) = mid;
  }
  return free;
}

// The narrow slot (0.7 mm between two walls; the probe's tip 0.5 mm, its working
// end widening to 1 mm over 13 mm): how far down the tip can go is set by where
// the working end wedges between the walls' top edges. Its taper is shallow
// (0.019 mm of radius per mm), so every 0.01 mm the spheres stand out of the
// walls or the probe lifts the wedge by 0.5 mm: a fit error e costs e / taper
// of depth. Measured: felt as plain spheres (`surface: spheres`), the default
// 512-leaf walls stop the tip 4.9 mm short of where the exact meshes let it go;
// walls fitted to 0.05 mm (6 levels) let it down to within what the measured
// protrusions of walls and probe allow. Felt as the default clipped leaves, the
// walls' faces and top edges are their true planes: the same 512-leaf walls let
// it down to within the probe's own protrusion. Never below the true limit.
TEST(Probing, TheTipGoesDownTheNarrowSlotAsFarAsTheTrueGeometryAllows) {
  SceneSpec spec =
      LoadSceneSpec(fs::path(SULCUS_SOURCE_DIR) / "tests/scenes/hard/narrow_slot.yaml");
  auto depth_reached = [&](const CompiledScene& scene) {
    EngineData d(*scene.model);
    ResetTool(RigidTransform(Matrix3::Identity(), Vector3(0, 0, 8)), &d);
    for (int i = 0; i <= 1200; ++i)
      Step(*scene.model, RigidTransform(Matrix3::Identity(), Vector3(0, 0, 8 - 0.01 * i)),
           &d);
    EXPECT_EQ(d.faults.total(), 0u);
    return d.X_WG.translation().z();
  };
  spec.leaf_planes = false;
  const auto coarse = CompileScene(spec, Cache());
  // The true limit: the lowest tip height at which the probe's exact mesh meets
  // neither wall (bisection on exact triangle intersection).
  const ExactScene walls(*coarse, [](const ObjectSpec& o) {
    return o.name.find("wall") != std::string::npos;
  });
  ASSERT_EQ(walls.objects.size(), 2u);
  auto free_at = [&](double z) {
    return walls.ProbeFree(RigidTransform(Matrix3::Identity(), Vector3(0, 0, z)));
  };
  const double lo = -4.0, hi = 8.0;  // touching at lo (or the floor), free at hi
  ASSERT_TRUE(free_at(hi));
  ASSERT_FALSE(free_at(lo));
  const double truth = FreeEnd(free_at, lo, hi, 0.005);
  const double with_512 = depth_reached(*coarse);
  for (ObjectSpec& o : spec.objects) {
    if (o.name.find("wall") == std::string::npos) continue;
    o.trees.levels = 6;
    o.trees.target_error_mm = 0.05;
  }
  const double fitted =
      depth_reached(*CompileScene(spec, Cache()));  // built here, then from the cache
  SceneSpec clipped_spec =
      LoadSceneSpec(fs::path(SULCUS_SOURCE_DIR) / "tests/scenes/hard/narrow_slot.yaml");
  ASSERT_TRUE(clipped_spec.leaf_planes) << "the default";
  const double clipped = depth_reached(*CompileScene(clipped_spec, Cache()));
  // What the fits allow: the worst protrusion of the fitted walls and of the
  // probe, over the working end's taper.
  const auto fine = CompileScene(spec, Cache());
  EvalParams quick;
  quick.surface_samples = 20000;
  quick.points_per_sphere = 96;
  quick.volume_samples_per_sphere = 0;
  double wall_err = 0;
  for (std::size_t i = 0; i < fine->meshes.size(); ++i)
    if (fine->spec.objects[i].name.find("wall") != std::string::npos)
      wall_err =
          std::max(wall_err, EvaluateSphereTree(fine->meshes[i], fine->trees[i], quick)
                                 .leaves()
                                 .protrusion_max_mm);
  const double tool_err = EvaluateSphereTree(fine->tool_mesh, fine->tool_tree, quick)
                              .leaves()
                              .protrusion_max_mm;
  const ProbeModel probe = MakeProbe(spec.probe);
  const double taper = (0.5 - probe.tip_radius_mm) / probe.working_length_mm;
  const double allowed = (wall_err + tool_err) / taper;
  std::printf(
      "narrow slot: the exact meshes let the tip down to z = %.2f mm; 512-leaf walls as "
      "spheres stop it at "
      "%.2f; walls fitted to 0.05 mm (worst %.3f mm, probe %.3f mm: %.2f mm of depth) at "
      "%.2f; 512-leaf "
      "walls as clipped leaves (the default) at %.2f (the probe's own protrusion: %.2f "
      "mm of depth)\n",
      truth, with_512, wall_err, tool_err, allowed, fitted, clipped, tool_err / taper);
  EXPECT_LT(clipped, with_512 - 3.0) << "clipped leaves open the slot at the default fit";
  EXPECT_LT(clipped, truth + tool_err / taper + 0.05)
      << "as far down as the probe's own tree allows";
  EXPECT_GT(clipped, truth - 0.01) << "and never below the true limit";
  EXPECT_GT(with_512, truth + 3.0) << "the default fit closes the slot";
  EXPECT_LT(fitted, with_512 - 2.0) << "the fine fit opens it";
  EXPECT_LE(wall_err, 0.05 + 1e-6) << "the fit asked for";
  EXPECT_LT(fitted, truth + allowed) << "as far down as the spheres' geometry allows";
  EXPECT_GT(fitted, truth - 0.15) << "and never below the true limit (through the walls)";
}

// The wedge: two slabs leaning 35 degrees, their top faces meeting in a V.
// The probe, upright and tilted across and along the crease, is pushed 0.5 mm
// past where its exact mesh meets the slabs, then slid along the crease. Every
// 20 frames, for each slab the engine holds the tool against (an active pair),
// the exact distance between the probe's mesh there and the slab's: the air
// gap a hand feels. The slabs' leaves are clipped by planes, so both faces,
// and the crease where they meet, are felt where they are.
struct CreaseGaps {
  double tip = 0;               // the largest air gap felt with the tip in the crease
  double lying = 0;             // with the working end lying in it
  double face = 0;              // with the working end lying on one face, for comparison
  double probe_protrusion = 0;  // the probe tree's worst leaf (the tool is spheres)
};

// `half_length`: how far the crease runs either way from y = 0.
CreaseGaps FeltInTheCrease(const std::string& file, double half_length) {
  const SceneSpec spec =
      LoadSceneSpec(fs::path(SULCUS_SOURCE_DIR) / "tests/scenes/hard" / file);
  const auto scene = CompileScene(spec, Cache());
  const ExactScene exact(*scene);
  const double deg = std::numbers::pi / 180;
  // Upright or tilted, the tip at the crease's middle slides 2 mm either way
  // along it; lying in it, the working end along the crease from the tip 1 mm
  // from its end (the shank rising clear of the faces), 0.5 mm. Each is pushed along -up
  // from `at`. For comparison, the probe lying on one face, away from the crease.
  struct Tilt {
    const char* name;
    Matrix3 R;
    Vector3 at = Vector3::Zero();
    double slide = 2;
    Vector3 up = Vector3::UnitZ();
  };
  const Matrix3 lying(Eigen::AngleAxisd(-90 * deg, Vector3::UnitX()));
  auto rolled = [&](double a) {
    return Matrix3(lying * Eigen::AngleAxisd(a * deg, Vector3::UnitZ()));
  };
  const Vector3 in_crease(0, 1 - half_length, 0);
  const double t = 35 * deg;
  const Tilt tilts[] = {
      {"upright", Matrix3::Identity()},
      {"20 deg across", Matrix3(Eigen::AngleAxisd(20 * deg, Vector3::UnitY()))},
      {"20 deg across, the other way",
       Matrix3(Eigen::AngleAxisd(-20 * deg, Vector3::UnitY()))},
      {"30 deg along", Matrix3(Eigen::AngleAxisd(30 * deg, Vector3::UnitX()))},
      {"20 along, 15 across", Matrix3(Eigen::AngleAxisd(20 * deg, Vector3::UnitX()) *
                                      Eigen::AngleAxisd(15 * deg, Vector3::UnitY()))},
      {"lying in the crease, its shank rising", rolled(90), in_crease, 0.5},
      {"lying on the left face", Matrix3(Eigen::AngleAxisd(t, Vector3::UnitY()) * lying),
       Vector3(-2.5, 1 - half_length, 0.11 + 2.5 * std::tan(t)), 0.5,
       Vector3(std::sin(t), 0, std::cos(t))},
  };
  CreaseGaps out;
  for (const Tilt& tilt : tilts) {
    auto pose = [&](double s, double y) {
      return RigidTransform(tilt.R, tilt.at + Vector3(0, y, 0) + s * tilt.up);
    };
    auto free_at = [&](double s) { return exact.ProbeFree(pose(s, 0)); };
    const double lo = -0.6, start = 5.0;  // in both slabs at lo
    EXPECT_TRUE(free_at(start)) << tilt.name;
    EXPECT_FALSE(free_at(lo)) << tilt.name;
    const double hi = FreeEnd(free_at, lo, start, 0.001);
    EngineData d(*scene->model);
    const auto device = [&](int i) {
      return pose(std::max(hi - 0.5, 5 - 0.01 * i),
                  i < 700 ? 0 : tilt.slide * std::sin((i - 700) * 0.004));
    };
    ResetTool(device(0), &d);
    double gap_max = 0;
    int samples = 0;
    for (int i = 0; i <= 2300; ++i) {
      Step(*scene->model, device(i), &d);
      if (i < 600 || i % 20 != 0) continue;
      const TriangleMesh probe = exact.Probe(d.X_WG);
      std::vector<char> touching(exact.objects.size(), 0);
      for (int k = 0; k < d.num_active_keys; ++k)
        touching[static_cast<std::size_t>(ContactPair::ObjectOfKey(d.active_keys[k]))] =
            1;
      for (std::size_t o = 0; o < exact.objects.size(); ++o) {
        if (!touching[o]) continue;
        const MeshContact c = MeasureContact(probe, exact.objects[o]);
        EXPECT_FALSE(c.intersect) << tilt.name << " frame " << i << " slab " << o;
        gap_max = std::max(gap_max, c.gap_mm);
        ++samples;
      }
    }
    EXPECT_EQ(d.faults.total(), 0u) << tilt.name;
    EXPECT_GT(samples, 50) << tilt.name << ": held against the slabs";
    std::printf(
        "%s, probe %s: the exact meshes meet at %.3f mm; air gap felt "
        "at most %.4f mm over %d contacts\n",
        file.c_str(), tilt.name, hi, gap_max, samples);
    const std::string name = tilt.name;
    double& kind = name.starts_with("lying in")   ? out.lying
                   : name.starts_with("lying on") ? out.face
                                                  : out.tip;
    kind = std::max(kind, gap_max);
  }
  EvalParams quick;
  quick.surface_samples = 20000;
  quick.points_per_sphere = 96;
  quick.volume_samples_per_sphere = 0;
  out.probe_protrusion = EvaluateSphereTree(scene->tool_mesh, scene->tool_tree, quick)
                             .leaves()
                             .protrusion_max_mm;
  std::printf("%s: the probe's tree protrudes at most %.4f mm\n", file.c_str(),
              out.probe_protrusion);
  return out;
}

TEST(Probing, TheTipRestsInTheWedgesCreaseWhereTheTrueGeometryStopsIt) {
  const CreaseGaps g = FeltInTheCrease("wedge.yaml", 5);
  EXPECT_LE(g.tip, 0.02) << "mm";
  EXPECT_LE(g.lying, g.probe_protrusion) << "mm";
  EXPECT_LE(g.face, g.probe_protrusion) << "mm";
}

TEST(Probing, AConcaveCreaseInOneMeshIsFeltWhereItIs) {
  const CreaseGaps g = FeltInTheCrease("v_groove.yaml", 12);
  EXPECT_LE(g.tip, 0.02) << "mm";
  EXPECT_LE(g.lying, g.probe_protrusion) << "mm";
  EXPECT_LE(g.face, g.probe_protrusion) << "mm";
}

}  // namespace
}  // namespace sulcus

#include <fstream>

#include "core/anatomy/findings.h"
#include "core/anatomy/tooth.h"
#include "tests/common/output.h"

namespace sulcus {
namespace {

// caries_catch: an explorer pressed into 36's occlusal lesion and then drawn
// 1 mm sideways feels a softer surface and a catch that holds it back; the same
// press and draw on the same tooth without the lesion feels neither (and has no
// caries_catch in its loop at all).
TEST(Probing, ACariousLesionFeelsSofterAndCatchesTheExplorer) {
  const fs::path dir = test::FreshOutputPath("caries", "catch");
  auto write =
      [&](const std::string& name, bool carious) {
        std::ofstream(dir / name)
            << "tool:\n  probe: explorer23\neffects: [contact, caries_catch]\nobjects:\n"
            << "  - tooth: 36\n"
            << (carious ? "    caries_mm: {occlusal: 2.5}\n" : "");
        return dir / name;
      };
  const auto carious = CompileScene(LoadSceneSpec(write("carious.yaml", true)), Cache());
  const auto sound = CompileScene(LoadSceneSpec(write("sound.yaml", false)), Cache());
  ASSERT_EQ(carious->effects.lesions.size(), 1u);
  EXPECT_TRUE(sound->effects.lesions.empty());
  EXPECT_TRUE(MakeEffects(sound->effects).empty()) << "no lesion: nothing in the loop";
  const CariesLesion lesion = carious->effects.lesions[0];
  const Vector3 n = lesion.normal_W, t = n.unitOrthogonal();
  const Quaternion q = Quaternion::FromTwoVectors(Vector3::UnitZ(), n);
  // Down onto the lesion's centre to 0.5 mm past the surface in 0.5 s, held
  // 0.3 s, drawn 1 mm along t in 0.5 s, held 0.2 s.
  std::vector<Keyframe> keys;
  for (int i = 0; i <= 1500; i += 10) {
    const double s = i * 0.001;
    const double depth = s < 0.5 ? -3.0 + 3.5 * s / 0.5 : 0.5;
    const double along = s < 0.8 ? 0.0 : std::min(1.0, (s - 0.8) / 0.5);
    keys.push_back({s, Vector3(lesion.centre_W - depth * n + along * t), q, 0});
  }
  struct Run {
    double normal_held = 0, tangential_drawn = 0;
    int catches = 0;
  };
  auto run = [&](const CompiledScene& scene) {
    struct Probe final : TickConsumer {
      Vector3 n, t;
      Run out;
      void OnTick(const TickRecord& r) override {
        if (r.tick == 790) out.normal_held = r.force_W.dot(n);
        if (r.tick == 1490)
          out.tangential_drawn = -r.force_W.dot(t);  // holding back the draw
        for (int i = 0; i < r.num_events; ++i)
          out.catches += r.events[i].kind == EventKind::kCariesCatch;
      }
    } probe;
    probe.n = n;
    probe.t = t;
    EXPECT_EQ(
        PlayOffline(scene, keys, 1500, "press and draw", &probe)->loop().faults().total(),
        0u);
    return probe.out;
  };
  const Run on = run(*carious), off = run(*sound);
  std::printf(
      "lesion: normal %.3f N held, %.3f N holding back the draw, %d catch; sound: %.3f "
      "N, %.3f N, %d\n",
      on.normal_held, on.tangential_drawn, on.catches, off.normal_held,
      off.tangential_drawn, off.catches);
  EXPECT_GT(off.normal_held, 0.3) << "pressed";
  EXPECT_LT(on.normal_held, 0.8 * off.normal_held) << "softer than enamel";
  EXPECT_GT(on.tangential_drawn, off.tangential_drawn + 0.15)
      << "the catch holds the tip back";
  EXPECT_EQ(on.catches, 1);
  EXPECT_EQ(off.catches, 0);
}

}  // namespace
}  // namespace sulcus

namespace sulcus {
namespace {

// A cavitated lesion (cavity_mm) is a pit in the tooth's mesh: its floor 1 mm
// below the intact surface at the centre. An explorer pressed down the lesion's
// normal at its centre stops on the intact surface of a lesion that is not
// cavitated, and goes down into the cavity of one that is.
TEST(Probing, ACavitatedLesionIsAPitTheExplorerGoesInto) {
  const fs::path dir = test::FreshOutputPath("caries", "cavity");
  auto compile =
      [&](const std::string& name, bool cavity) {
        std::ofstream(dir / name)
            << "tool:\n  probe: explorer23\neffects: [contact]\nobjects:\n"
            << "  - tooth: 36\n    caries_mm: {occlusal: 2.5}\n"
            << (cavity ? "    cavity_mm: {occlusal: 1.0}\n" : "");
        return CompileScene(LoadSceneSpec(dir / name), Cache());
      };
  const auto pit = compile("cavitated.yaml", true),
             intact = compile("intact.yaml", false);
  ASSERT_EQ(intact->effects.lesions.size(), 0u);  // (no caries_catch named)
  const SurfacePoint spot = CariesSpot(
      GenerateTooth(36), ToothSurface::kOcclusal);  // the tooth frame is the world here
  // The mesh: still a valid solid, its surface at the centre 1 mm in, unchanged outside
  // the lesion.
  const MeshReport report = pit->meshes[0].Check();
  EXPECT_TRUE(report.IsSolid());
  double deepest = 0;
  std::size_t moved_outside = 0;
  for (std::size_t i = 0; i < pit->meshes[0].num_vertices(); ++i) {
    const Vector3 v = pit->meshes[0].vertices()[i], was = intact->meshes[0].vertices()[i];
    if ((was - spot.point).norm() >= 2.5) moved_outside += (v - was).norm() > 0;
    deepest = std::max(deepest, (was - v).dot(spot.normal));
  }
  EXPECT_NEAR(deepest, 1.0, 1e-9);
  EXPECT_EQ(moved_outside, 0u);
  // Down the normal at the centre to 2 mm past the intact surface in 0.6 s, held 0.4 s.
  const Quaternion q = Quaternion::FromTwoVectors(Vector3::UnitZ(), spot.normal);
  std::vector<Keyframe> keys;
  for (int i = 0; i <= 1000; i += 10) {
    const double s = i * 0.001, depth = s < 0.6 ? -3.0 + 5.0 * s / 0.6 : 2.0;
    keys.push_back({s, Vector3(spot.point - depth * spot.normal), q, 0});
  }
  auto rest = [&](const CompiledScene& scene) {
    const auto session = PlayOffline(scene, keys, 1000, "press");
    EXPECT_EQ(session->loop().faults().total(), 0u);
    // How far below the intact surface the tip rests.
    return (spot.point - session->loop().data().X_WG.translation()).dot(spot.normal);
  };
  const double in_pit = rest(*pit), on_intact = rest(*intact);
  std::printf(
      "the explorer's tip rests %.2f mm below the intact surface in the cavity, %.2f mm "
      "on the intact lesion\n",
      in_pit, on_intact);
  EXPECT_LT(on_intact, 0.2);
  EXPECT_GT(in_pit, on_intact + 0.5) << "into the pit";
}

// surface_texture: the same slide along tooth 46's buccal surface with and
// without the effect; the difference is the texture's force, along the contact
// normal, periodic in the distance slid: enamel's on the crown, root
// cementum's (larger, finer) below the CEJ.
TEST(Probing, EnamelAndRootFeelDifferentUnderASlidingTip) {
  const fs::path dir = test::FreshOutputPath("texture", "slide");
  auto compile = [&](bool texture) {
    const fs::path file = dir / (texture ? "on.yaml" : "off.yaml");
    std::ofstream(file) << "tool:\n  probe: who\neffects: [contact"
                        << (texture ? ", surface_texture" : "")
                        << "]\nobjects:\n  - tooth: 46\n";
    return CompileScene(LoadSceneSpec(file), Cache());
  };
  const auto on = compile(true), off = compile(false);
  ASSERT_EQ(MakeEffects(on->effects).size(), 1u);
  ASSERT_TRUE(MakeEffects(off->effects).empty());
  const TriangleMesh& tooth = on->meshes[0];  // the tooth frame is the world here
  for (const double z : {3.0, -3.0}) {
    // The buccal surface at this height, and a slide 0.4 mm inside it from x = -2 to 2
    // mm.
    double y_surface = 0;
    for (const Vector3& v : tooth.vertices())
      if (std::abs(v.z() - z) < 0.4 && std::abs(v.x()) < 0.5)
        y_surface = std::max(y_surface, v.y());
    const Quaternion q =
        Quaternion::FromTwoVectors(Vector3::UnitZ(), Vector3(0, 1, 1).normalized());
    std::vector<Keyframe> keys;
    for (int i = 0; i <= 1200; i += 10) {
      const double s = std::clamp((i - 200) / 1000.0, 0.0, 1.0);
      keys.push_back({i * 0.001, Vector3(-2 + 4 * s, y_surface - 0.4, z), q, 0});
    }
    auto forces = [&](const CompiledScene& scene) {
      struct Trace final : TickConsumer {
        std::vector<Vector3> f;
        void OnTick(const TickRecord& r) override { f.push_back(r.force_W); }
      } trace;
      PlayOffline(scene, keys, 1200, "slide", &trace);
      return trace.f;
    };
    const std::vector<Vector3> with = forces(*on), without = forces(*off);
    ASSERT_EQ(with.size(), without.size());
    // The texture's force over the slide (ticks 300 to 1100, pressing).
    double biggest = 0, allowed = 0;
    int sign_changes = 0, last_sign = 0;
    for (std::size_t t = 300; t < 1100; ++t) {
      const double f = without[t].norm();
      if (f < 0.05) continue;
      const double d = (with[t] - without[t]).dot(without[t] / f);
      EXPECT_LT((with[t] - without[t] - d * without[t] / f).norm(), 1e-9)
          << "along the normal only";
      const Texture& expect =
          z > 0 ? on->effects.texture.enamel : on->effects.texture.root;
      allowed = std::max(allowed, std::min(1.0, f / 0.5) * expect.amplitude_n);
      biggest = std::max(biggest, std::abs(d));
      const int sign = d > 1e-6 ? 1 : d < -1e-6 ? -1 : 0;
      if (sign != 0 && last_sign != 0 && sign != last_sign) ++sign_changes;
      if (sign != 0) last_sign = sign;
    }
    std::printf(
        "slide at z = %+.0f mm: texture force up to %.4f N (allowed %.4f), %d sign "
        "changes\n",
        z, biggest, allowed, sign_changes);
    EXPECT_GT(biggest, 0.5 * allowed) << z;
    EXPECT_LE(biggest, allowed + 1e-9) << z;
    // 3.2 mm slid in those ticks: about 2 * 3.2 / period sign changes (the tip slides a
    // little less than the device, and on the root a little more along the surface:
    // a slip over one of its leaf spheres' bumps is eased, EngineParams::slip_step_mm,
    // so the tip goes over the bump where it jumped across it).
    const double period =
        z > 0 ? on->effects.texture.enamel.period_mm : on->effects.texture.root.period_mm;
    EXPECT_GT(sign_changes, 2 * 1.5 / period) << z;
    EXPECT_LT(sign_changes, 2 * 4.5 / period) << z;
  }
}

}  // namespace
}  // namespace sulcus

namespace sulcus {
namespace {

// calculus: the working end drawn against a supragingival deposit on 46 B
// announces it (tooth, site, force) once per contact; the same scene without
// the effect has nothing in its loop for it and no such event.
TEST(Probing, ACalculusDepositIsAnnouncedOnlyWhenTheSceneNamesIt) {
  const fs::path dir = test::FreshOutputPath("calculus", "touch");
  auto write = [&](const std::string& name, bool effect) {
    std::ofstream(dir / name) << "tool:\n  probe: who\ngingiva: true\neffects: [contact"
                              << (effect ? ", calculus" : "") << "]\nobjects:\n"
                              << "  - tooth: 46\n    calculus: {supra: [B]}\n";
    return dir / name;
  };
  const auto with = CompileScene(LoadSceneSpec(write("with.yaml", true)), Cache());
  const auto without = CompileScene(LoadSceneSpec(write("without.yaml", false)), Cache());
  int deposit = -1, tooth = -1;
  for (int i = 0; i < static_cast<int>(with->spec.objects.size()); ++i) {
    if (with->spec.objects[i].kind == ObjectSpec::Kind::kCalculus) deposit = i;
    if (with->spec.objects[i].kind == ObjectSpec::Kind::kTooth) tooth = i;
  }
  ASSERT_GE(deposit, 0);
  for (const auto& e : MakeEffects(without->effects))
    EXPECT_STRNE(e->name(), "calculus") << "not named: not in the loop";
  // The deposit's centre in the world, and the way out from the tooth's axis there.
  Aabb b;
  for (const Vector3& v : with->meshes[deposit].vertices())
    b.Extend(with->spec.objects[deposit].X_WO * v);
  const Vector3 c = 0.5 * (b.min + b.max);
  const RigidTransform& X_WT = with->spec.objects[tooth].X_WO;
  const Vector3 up = X_WT.rotation().col(2);
  Vector3 out = c - X_WT.translation();
  out -= out.dot(up) * up;
  out.normalize();
  const Quaternion q =
      Quaternion::FromTwoVectors(Vector3::UnitZ(), (up + 0.2 * out).normalized());
  // From 3 mm out to 0.3 mm into the deposit in 0.6 s, held, back out, and in again.
  std::vector<Keyframe> keys;
  for (int i = 0; i <= 2000; i += 10) {
    const double s = i * 0.001, phase = std::fmod(s, 1.0);
    const double gap = phase < 0.6   ? 3.0 - 3.3 * phase / 0.6
                       : phase < 0.8 ? -0.3
                                     : -0.3 + 3.3 * (phase - 0.8) / 0.2;
    keys.push_back({s, Vector3(c + (gap + 0.6) * out), q, 0});
  }
  auto run = [&](const CompiledScene& scene) {
    struct Count final : TickConsumer {
      std::vector<CalculusPayload> met;
      void OnTick(const TickRecord& r) override {
        for (int i = 0; i < r.num_events; ++i)
          if (r.events[i].kind == EventKind::kCalculusTouched)
            met.push_back(r.events[i].payload.calculus);
      }
    } count;
    PlayOffline(scene, keys, 2000, "to the deposit and back, twice", &count);
    return count.met;
  };
  const auto met = run(*with), none = run(*without);
  ASSERT_EQ(met.size(), 2u) << "once per contact, two contacts";
  EXPECT_EQ(met[0].fdi, 46);
  EXPECT_EQ(met[0].site, 1) << "B";
  EXPECT_GT(met[0].force_n, 0.0);
  EXPECT_TRUE(none.empty());
}

// Tissue damage is counted once per press: the probe rests on the tongue's
// dorsum about its 0.5 N limit, the force rippling across the limit again and
// again, then lifts off and presses once more. Two presses, two damage events;
// an episode ends only when the force falls well below the limit or the tongue
// is left.
TEST(Probing, APressHoveringAboutTheDamageLimitIsOneDamageEpisode) {
  const SceneSpec spec =
      LoadSceneSpec(fs::path(SULCUS_SOURCE_DIR) / "scenes" / "oral_inspection.yaml");
  ASSERT_TRUE(spec.HasEffect(Effect::kTissueDamage));
  const auto scene = CompileScene(spec, DefaultCacheDir());
  int tongue = -1;
  for (std::size_t i = 0; i < scene->spec.objects.size(); ++i)
    if (scene->spec.objects[i].anatomy == "tongue") tongue = static_cast<int>(i);
  ASSERT_GE(tongue, 0);
  const ObjectSpec& o = scene->spec.objects[static_cast<std::size_t>(tongue)];
  const SurfacePoint sp =
      RegionSpot("tongue", "dorsum", scene->meshes[static_cast<std::size_t>(tongue)]);
  const Vector3 p = o.X_WO * sp.point, n = (o.X_WO.rotation() * sp.normal).normalized();
  ScriptTarget st;
  st.n_W = n;
  st.tool_axis_W = (n + 0.5 * Vector3::UnitY()).normalized();
  st.shank_W = Vector3::UnitY();
  const Quaternion q = ScriptOrientation(st);
  // First where the force reaches the limit: the device lowered slowly (1 mm/s).
  struct Force final : TickConsumer {
    void OnTick(const TickRecord& r) override {
      if (!at_limit && r.force_W.norm() > 0.5) at_limit = r.tick;
    }
    std::optional<std::uint64_t> at_limit;
  } probe;
  std::vector<Keyframe> down;
  for (double t = 0; t <= 8.0 + 1e-9; t += 0.005)
    down.push_back({t, p - (-6.0 + t) * n, q, 0});
  PlayOffline(*scene, std::move(down), 8000, "tongue probe", &probe);
  ASSERT_TRUE(probe.at_limit) << "the probe never pressed the tongue at 0.5 N";
  const double d0 = -6.0 + static_cast<double>(*probe.at_limit) / 1000.0;
  // Then the presses: device depth below the surface point over time.
  auto depth = [d0](double t) {
    if (t < 1.0) return -6.0 + (d0 + 5.0) * t;  // down to 1 mm above the press
    if (t < 2.0) return d0 - 1.0 + (t - 1.0);   // into the press
    if (t < 4.0)
      return d0 + 0.09 * std::sin(2 * std::numbers::pi * 5 *
                                  (t - 2.0));        // hovering about the limit
    if (t < 4.5) return d0 - 5.0 * (t - 4.0);        // lifted 2.5 mm off
    if (t < 5.5) return d0 - 2.5 + 2.7 * (t - 4.5);  // pressed again, a little harder
    if (t < 6.5) return d0 + 0.2;
    return d0 + 0.2 - 5.0 * (t - 6.5);
  };
  std::vector<Keyframe> keys;
  for (double t = 0; t <= 7.0 + 1e-9; t += 0.005)
    keys.push_back({t, p - depth(t) * n, q, 0});
  struct Damage final : TickConsumer {
    explicit Damage(int object) : object(object) {}
    void OnTick(const TickRecord& r) override {
      for (int i = 0; i < r.num_events; ++i)
        if (r.events[i].kind == EventKind::kTissueDamage && r.events[i].object == object)
          ticks.push_back(r.tick);
      // Crossings of the limit by the whole force while hovering (the tongue bears it
      // all).
      const bool above = r.force_W.norm() > 0.5;
      if (r.tick > 2000 && r.tick < 4000 && above != was_above) ++crossings;
      if (r.tick > 2000 && r.tick < 4000) {
        lo = std::min(lo, r.force_W.norm());
        hi = std::max(hi, r.force_W.norm());
      }
      was_above = above;
    }
    int object;
    std::vector<std::uint64_t> ticks;
    int crossings = 0;
    bool was_above = false;
    double lo = 1e9, hi = 0;
  } consumer(tongue);
  const auto session =
      PlayOffline(*scene, std::move(keys), 7600, "tongue press", &consumer);
  std::printf(
      "force while hovering %.3f to %.3f N, %d crossings of the limit; damage events at",
      consumer.lo, consumer.hi, consumer.crossings);
  for (std::uint64_t t : consumer.ticks)
    std::printf(" %llu", static_cast<unsigned long long>(t));
  std::printf("\n");
  EXPECT_GE(consumer.crossings, 6)
      << "the hovering press crosses the limit again and again";
  ASSERT_EQ(consumer.ticks.size(), 2u) << "one damage episode per press";
  EXPECT_GT(consumer.ticks[0], 1000u);
  EXPECT_LT(consumer.ticks[0], 4000u);
  EXPECT_GT(consumer.ticks[1], 4500u)
      << "the second press, after the tip left the tongue";
  EXPECT_EQ(session->loop().faults().total(), 0u);
}

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
