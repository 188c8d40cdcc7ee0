#include "core/scene/scene_settings.h"

#include <gtest/gtest.h>

#include "core/scene/scene.h"
#include "tests/core/scene/scene_file_errors.h"

namespace sulcus {
namespace {

using test::Errors;
using test::Lines;
using test::Write;

TEST(SceneSettings, HapticsKeysAreCheckedAndRead) {
  EXPECT_EQ(Errors("haptics:\n  wobble: 3\nobjects: []\n"),
            (Lines{"2:3: unknown key 'wobble' in 'haptics' (expected one of: "
                   "k_t_n_per_mm, k_r_nmm_per_rad, "
                   "max_force_n, max_torque_nmm, rate_hz, surface, solve_pairs, "
                   "slip_mm_per_s)"}));
  EXPECT_EQ(Errors("haptics:\n  surface: smooth\nobjects: []\n"),
            (Lines{"2:12: 'surface' must be 'planes' (leaf spheres clipped by planes "
                   "fitted to the mesh, the default) "
                   "or 'spheres' (the leaf spheres alone)"}));
  EXPECT_EQ(Errors("haptics:\n  solve_pairs: 8\nobjects: []\n"),
            (Lines{"2:16: 'solve_pairs' must be 0 (no limit) or at least 16 (a probe "
                   "resting on a tooth alone meets "
                   "a dozen pairs)"}));
  EXPECT_EQ(Errors("haptics:\n  solve_pairs: 100000\nobjects: []\n"),
            (Lines{"2:16: 'solve_pairs' is 100000, expected 0 to 16384"}));
  EXPECT_EQ(LoadSceneSpec(
                Write("solve_pairs.yaml", "haptics:\n  solve_pairs: 0\nobjects: []\n"))
                .haptics.solve_pairs,
            0);
  EXPECT_EQ(LoadSceneSpec(Write("solve_pairs_64.yaml",
                                "haptics:\n  solve_pairs: 64\nobjects: []\n"))
                .haptics.solve_pairs,
            64);
  EXPECT_EQ(Errors("haptics:\n  k_t_n_per_mm: stiff\nobjects: []\n"),
            (Lines{"2:17: 'k_t_n_per_mm' must be a number (N/mm), found 'stiff'"}));
}

// A slip is eased at 50 mm/s by default, whatever the rate; 0 turns the easing
// off; the step a frame is that speed over the rate.
TEST(SceneSettings, TheSlipSpeedIsReadAsAStepAFrame) {
  EXPECT_DOUBLE_EQ(
      LoadSceneSpec(Write("slip_default.yaml", "objects: []\n")).haptics.slip_step_mm,
      0.05);
  EXPECT_DOUBLE_EQ(
      LoadSceneSpec(Write("slip_off.yaml", "haptics: {slip_mm_per_s: 0}\nobjects: []\n"))
          .haptics.slip_step_mm,
      0.0);
  EXPECT_DOUBLE_EQ(
      LoadSceneSpec(Write("slip_fast.yaml",
                          "haptics: {slip_mm_per_s: 100, rate_hz: 2000}\nobjects: []\n"))
          .haptics.slip_step_mm,
      0.05);
  EXPECT_EQ(Errors("haptics:\n  slip_mm_per_s: -1\nobjects: []\n"),
            (Lines{"2:18: 'slip_mm_per_s' is -1 mm/s, expected 0 to 1000"}));
}

TEST(SceneSettings, EffectsAreValidatedEvenBeforeTheyExist) {
  EXPECT_EQ(
      Errors("effects: [contact, probing_dept]\nobjects: []\n"),
      (Lines{"1:20: unknown effect 'probing_dept'; did you mean 'probing_depth'?"}));
  EXPECT_EQ(Errors("effects: contact\nobjects: []\n"),
            (Lines{"1:10: 'effects' must be a list, e.g. [contact, probing_depth]"}));
  const SceneSpec s = LoadSceneSpec(
      Write("effects_twice.yaml", "effects: [friction, friction]\nobjects: []\n"));
  EXPECT_EQ(s.effects, (std::vector<Effect>{Effect::kContact, Effect::kFriction}));
  EXPECT_STREQ(ToString(Effect::kFriction), "friction");
}

}  // namespace
}  // namespace sulcus
