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
#include "tests/core/scene/probing_common.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

using probing_test::Cache;
using probing_test::PlayOffline;

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

using probing_test::ExactScene;
using probing_test::FreeEnd;

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
