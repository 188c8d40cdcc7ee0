// Probing what the tooth holds: caries (softer, catching the explorer), a
// cavity, enamel against root, calculus, and a press about the damage limit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <optional>

#include "core/anatomy/findings.h"
#include "core/anatomy/soft_tissue.h"
#include "core/anatomy/tooth.h"
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
using probing_test::PlayOffline;
}  // namespace
}  // namespace sulcus

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
