#pragma once
// One haptic frame (docs/architecture.md, "One haptic frame"): collide the tool's
// sphere-tree against the scene at the graphic pose, linearise every pair
// constraint in the distance form with a local rotation increment, solve the QP
// that keeps the graphic tool out of every object while staying as close as
// possible to the device, re-check the exact constraints and re-linearise when
// needed, and turn the spring between the two tools into a force and torque.
//
// Model/Data split (MuJoCo): EngineModel is immutable after construction;
// EngineData holds everything that changes, sized once. Step() never allocates
// and never throws; faults are counted in EngineData.

#include <array>
#include <chrono>
#include <cstdint>
#include <vector>

#include "core/collision/collision.h"
#include "core/geometry/transform.h"
#include "core/solver/qp.h"

namespace sulcus {

struct EngineParams {
  double k_t = 1.0;               // N/mm, translational spring (paper)
  double k_r = 1000.0;            // N*mm/rad, rotational spring (paper: 1000 mN*m/rad)
  double max_force_n = 3.3;       // saturation (Geomagic Touch peak force)
  double max_torque_nmm = 515.0;  // saturation (Phantom Premium 6DOF peak torque)
  double base_margin_mm = 0.05;   // pairs closer than this are constraints even at rest
  double penetration_tolerance_mm =
      1e-4;  // re-linearise while the exact check exceeds it
  int max_linearizations = 4;
  double max_step_mm = 2.0;  // most a tool point moves per frame (2 m/s at 1 kHz)
  // Most a tool point of the rendered tool moves in a frame beyond what the
  // device itself moved in it (0.05 mm: 50 mm/s at 1 kHz; the scene sets it
  // from its rate). A tool slipping off an edge closes on the device over a few
  // frames instead of in one jump: the spring's force falls by at most k_t times
  // this a frame beyond the hand's move, a quick fall and not a click, and the
  // force sent is always the spring's (the loop limits rises only). A tool
  // sliding along a surface at the hand's speed is not slowed. 0: no bound.
  double slip_step_mm = 0.05;
  // Pairs a frame can hold. A probe laid along a finely fitted tooth meets about
  // 80 of its leaves per tool leaf within a fraction of a millimetre: 4,000 pairs
  // (the oral inspection at 10 kHz); the set holds four times that.
  int max_pairs = 16384;
  // Pairs a frame solves with when it can choose. A fast slide through a
  // crowded place (a probe between closed arches, lips and cheeks) with the
  // margin its move needs meets thousands of pairs, and the frame's cost grows
  // with them; past this many the frame takes a shorter step with a smaller
  // margin instead (the rendered tool lags the device a little for a tick or
  // two), and only its last try may use the whole set (max_pairs). 0: no
  // limit, every frame solves with all the pairs its move's margin holds.
  int solve_pairs = 512;
  // A crowded place never shortens a frame's step below this (0.1 mm: 100 mm/s
  // at 1 kHz, faster than a probe walks a pocket): at the margin this step
  // needs, the frame solves with every pair it finds, up to max_pairs.
  double min_crowded_step_mm = 0.1;
  // A rendered tool that the solve cannot take out of an object (its least
  // violation leaves it this far in), that overlaps it by more pairs than
  // max_pairs, or that overlaps it in a frame that could not move it is inside
  // it, as when a session starts with the device in tissue: it is brought to
  // free space next to the device (below), never left frozen there. Shallower
  // overlaps the QP pushes out by itself.
  double inside_mm = 0.1;
  // Most sphere tests a frame spends looking for that free space; the search
  // goes on next frame where it stopped.
  int free_search_node_tests = 40000;
  // The free space is looked for at most this far from the device: a pose
  // farther off can be on the far side of a thin wall (a cheek), where the
  // spring would push the hand through the wall toward it. Until one is found
  // the rendered tool follows the device with no force.
  double free_search_max_mm = 8;
  // Most sphere tests one contact query of a frame may make (0: no limit). A
  // query that would need more is treated as an overflow: a shorter step with a
  // smaller margin is tried, so a frame's collision work is bounded by
  // kMaxSweeps times this, whatever the pose.
  int max_node_tests = 20000;
  // A frame that cannot move the rendered tool (a failed solve, a move no query
  // covered, more pairs than a set holds at the shortest step) holds it where it
  // was. The next frame starts from the same pose and may meet the same wall:
  // after this many held frames in a row the tool is treated as inside (brought
  // to free space next to the device), never left frozen.
  int max_held_frames = 5;
};

/// The immutable engine model: the collision world and the parameters.
struct EngineModel {
  EngineModel(const SphereTree& tool, const std::vector<CollisionWorld::Object>& objects,
              const EngineParams& params);
  CollisionWorld world;
  EngineParams params;
  /// Coulomb friction (the scene's `friction` effect): per object, the static
  /// coefficient; kinetic is kKineticShare of it. Empty: no friction, and the
  /// frame does no friction work at all (one test of this vector's size).
  std::vector<double> friction;
  static constexpr double kKineticShare = 0.8;
};

/// Fault counters; a fault never throws, it is counted and the frame falls back.
struct EngineFaults {
  std::uint64_t nonfinite_device =
      0;  // a NaN or infinite device pose: pose held, zero force
  std::uint64_t pair_overflow = 0;  // more pairs than max_pairs: a shorter step is tried
  std::uint64_t solver = 0;         // QP status other than solved / relaxed
  std::uint64_t penetration = 0;  // exact penetration above tolerance after the last pass
  std::uint64_t sweep = 0;        // the frame's move could not be covered: pose held
  std::uint64_t held = 0;         // held max_held_frames in a row: treated as inside
  std::uint64_t inside = 0;       // the tool was found inside an object and brought out
  std::uint64_t rejoined = 0;  // placed apart by that, it rejoined the device once free
  std::uint64_t total() const {
    return nonfinite_device + pair_overflow + solver + penetration + sweep + held +
           inside + rejoined;
  }
};

/// Per-stage wall time of the last frame, microseconds.
struct StepTimings {
  double collide_us = 0, constraints_us = 0, solve_us = 0, total_us = 0;
};

struct EngineData {
  explicit EngineData(const EngineModel& model);

  // Inputs and outputs of the last frame.
  RigidTransform X_WH;                 // device ("haptic") tool
  RigidTransform X_WG;                 // rendered ("graphic") tool
  Vector3 force_W = Vector3::Zero();   // N, on the device: k_t (p_G - p_H), saturated
  Vector3 torque_W = Vector3::Zero();  // N*mm about the tool origin, saturated
  bool force_saturated = false;

  // Contacts: pairs within the margin at the graphic pose.
  std::vector<ContactPair> pairs;
  int num_pairs = 0;
  int active_contacts = 0;        // pairs with a positive multiplier
  double max_penetration_mm = 0;  // exact, over all pairs, after the frame (>= 0)
  double margin_mm = 0;           // query margin used (covers this frame's move)
  static constexpr int kMaxSweeps = 6;
  int sweeps = 0;      // queries this frame (a re-query when the move outgrew the margin)
  int node_tests = 0;  // sphere tests this frame, all its queries
  bool node_budget_hit = false;  // a query of this frame was cut short by max_node_tests
  double sweep_margin_mm[kMaxSweeps] = {};
  double sweep_move_mm[kMaxSweeps] = {};
  double last_move_mm = 0;  // how far a tool point moved last frame (margin guess)
  int held_frames = 0;  // frames in a row that held the rendered tool (could not move it)
  bool pair_overflow = false;
  static constexpr double kMarginCapMaxMm = 1e3;  // no cap: above any step's margin
  double margin_cap_mm = kMarginCapMaxMm;  // largest margin (and step) the last crowded
                                           // place allowed; grows back
  std::uint64_t shortened_frames =
      0;  // frames that took a shorter step for solve_pairs (all frames)
  std::uint64_t capped_frames =
      0;  // frames whose step the margin cap shortened (all frames)
  std::uint64_t eased_frames =
      0;  // frames whose move slip_step_mm shortened, a slip eased (all frames)
  double device_move_mm = 0;  // how far a tool point of the device moved this frame
  bool eased_held = false;    // this frame's eased move was under a quarter of its due
  Vector6 device_step = Vector6::Zero();  // the device's own step, (dp, dtheta)

  // Solver report of the last pass.
  QpStatus qp_status = QpStatus::kSolved;
  int qp_iterations = 0;
  int linearizations = 0;
  double kkt_residual = 0;

  // Friction (when the model has it): the rendered tool stuck where it touched,
  // or sliding on the edge of the kinetic friction cone.
  enum class Friction : std::uint8_t { kNone, kStick, kSlip };
  Friction friction = Friction::kNone;
  std::uint64_t friction_transitions = 0;  // stick <-> slip changes (all frames)
  Vector3 friction_device_W =
      Vector3::Zero();  // the device's position at the last friction frame

  // Inside an object: the rendered tool follows the device with no force while
  // poses around the device are tried, nearest first, for one that is free.
  bool inside = false;
  int free_search_next = 0;  // the next candidate pose to try
  // The free pose found was not the device's own: until the rendered tool has
  // met the device, a device that comes out in free space elsewhere (the other
  // side of a thin wall) is rejoined there, with no force, instead of being
  // pulled back through the wall to where the search put the tool.
  bool placed_apart = false;

  StepTimings timings;
  EngineFaults faults;
  std::uint64_t frames = 0;
  bool initialized = false;

  // Workspace (sized once).
  std::vector<double> A, b;
  std::vector<std::uint64_t> active_keys;  // last frame's active pairs
  int num_active_keys = 0;
  std::array<double, kQpMaxActive>
      active_share{};  // each active pair's share of the contact force (sums to 1)
  std::vector<std::int32_t> warm_rows;
  CollisionScratch scratch;
  QpSolver qp;
};

/// Puts the graphic tool at X_WG (and the device there too), clearing contacts
/// and the warm start; the next Step starts from it.
void ResetTool(const RigidTransform& X_WG, EngineData* data);

/// One frame with the device at X_WH. Never allocates, never throws.
void Step(const EngineModel& model, const RigidTransform& X_WH,
          EngineData* data) noexcept;

}  // namespace sulcus
