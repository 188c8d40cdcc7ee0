#include "core/haptics/engine.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>

namespace sulcus {
namespace {

using Clock = std::chrono::steady_clock;

double Micros(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::micro>(b - a).count();
}

bool Finite(const RigidTransform& X) {
  return X.rotation().allFinite() && X.translation().allFinite();
}

// Removes the drift of many products of rotations.
RigidTransform Orthonormalised(const RigidTransform& X) {
  return RigidTransform(Quaternion(X.rotation()).normalized().toRotationMatrix(),
                        X.translation());
}

// A solve whose pose can be used: optimal, or the least violation of an
// infeasible set.
bool Usable(QpStatus s) {
  return s == QpStatus::kSolved || s == QpStatus::kInfeasibleRelaxed;
}

Vector3 Clamp(const Vector3& v, double limit, bool* clamped) {
  const double n = v.norm();
  if (n > limit) {
    *clamped = true;
    return v * (limit / n);
  }
  return v;
}

// How far a tool point moves at most for a configuration step (dp, dtheta).
double MoveBound(const Vector6& dq, double reach) {
  return dq.head<3>().norm() + dq.tail<3>().norm() * reach;
}

// The spring between the tools (paper eq. 6) as force and torque, saturated.
void SpringWrench(const EngineParams& p, const RigidTransform& X_WH, EngineData* d) {
  d->force_saturated = false;
  d->force_W = Clamp(p.k_t * (d->X_WG.translation() - X_WH.translation()), p.max_force_n,
                     &d->force_saturated);
  d->torque_W = Clamp(p.k_r * LogMap(d->X_WG.rotation() * X_WH.rotation().transpose()),
                      p.max_torque_nmm, &d->force_saturated);
}

// Candidate poses for a tool found inside an object: the device pose, then the
// device pose moved along 26 directions of the tool frame (its axis first) by
// growing distances, nearest first.
constexpr double kFreeSearchMm[] = {0.25, 0.5, 1, 1.5, 2, 3, 4, 6, 8, 12, 16, 24};
constexpr int kFreeSearchDirections = 26;
constexpr int kFreeSearchCandidates =
    1 + kFreeSearchDirections * static_cast<int>(std::size(kFreeSearchMm));

// The tool's axis (+z, -z) first, then its other faces, edges and corners; made
// at load, so the haptic thread never meets a first-call initialisation.
const std::array<Vector3, kFreeSearchDirections> kFreeSearchDirection = [] {
  std::array<Vector3, kFreeSearchDirections> t;
  int n = 0;
  t[n++] = Vector3(0, 0, 1);
  t[n++] = Vector3(0, 0, -1);
  for (int pass = 1; pass <= 3; ++pass)
    for (int x = -1; x <= 1; ++x)
      for (int y = -1; y <= 1; ++y)
        for (int z = -1; z <= 1; ++z) {
          const int nonzero = (x != 0) + (y != 0) + (z != 0);
          if (nonzero != pass || (pass == 1 && x == 0 && y == 0)) continue;
          t[n++] = Vector3(x, y, z).normalized();
        }
  return t;
}();

RigidTransform FreeSearchCandidate(const RigidTransform& X_WH, int k) {
  if (k == 0) return X_WH;
  const int d = (k - 1) / kFreeSearchDirections, dir = (k - 1) % kFreeSearchDirections;
  return RigidTransform(
      X_WH.rotation(),
      X_WH.translation() +
          kFreeSearchMm[d] *
              (X_WH.rotation() * kFreeSearchDirection[static_cast<std::size_t>(dir)]));
}

// A frame inside an object: the rendered tool is at the device (no force) while
// candidate poses are tried within the frame's budget of sphere tests; the
// first free one becomes the rendered tool, outside, and the spring (ramped in
// by the loop, which sees the fault) pulls the hand out from there.
void FindFreeSpace(const EngineModel& model, const RigidTransform& X_WH, EngineData* d) {
  const EngineParams& p = model.params;
  int budget = std::max(1, p.free_search_node_tests);
  for (int tried = 0; tried < kFreeSearchCandidates && budget > 0; ++tried) {
    if (d->free_search_next > 0 &&
        kFreeSearchMm[(d->free_search_next - 1) / kFreeSearchDirections] >
            p.free_search_max_mm) {
      d->free_search_next = 0;  // none near enough: the device's own pose again
      break;
    }
    const RigidTransform X = FreeSearchCandidate(X_WH, d->free_search_next);
    // An overlap test: the first pair in overlap stops it.
    const CollisionStats cs = FindContacts(model.world, X, 0.0, &d->scratch,
                                           d->pairs.data(), 0, QueryLimits{true, budget});
    budget -= cs.node_tests;
    if (cs.cut_short && !cs.overflow)
      break;  // out of budget: this candidate again next frame
    if (!cs.overflow && !cs.stack_overflow) {
      const bool apart = d->free_search_next > 0;
      d->inside = false;
      d->free_search_next = 0;
      ++d->faults.inside;
      ResetTool(X, d);
      d->X_WH = X_WH;
      d->placed_apart = apart;
      return;
    }
    d->free_search_next = (d->free_search_next + 1) % kFreeSearchCandidates;
  }
  d->X_WG = X_WH;
  d->num_pairs = 0;
  d->active_contacts = 0;
  d->num_active_keys = 0;
  d->last_move_mm = 0;
}

// Largest penetration of this frame's pairs with the tool at X.
double WorstPenetration(const CollisionWorld& world, const RigidTransform& X,
                        const EngineData& d) {
  double worst = 0;
  for (int i = 0; i < d.num_pairs; ++i)
    worst = std::max(worst, -world.PairGap(X, d.pairs[i]));
  return worst;
}

// Coulomb friction on the rendered tool, in the god-object manner (Zilles and
// Salisbury; Harwin and Melder). The contact normal n is the mean direction of
// the pairs touching where the tool was; with the tool kept there, the spring
// from the device has a normal part (the normal force / k_t) and a tangential
// part. The tool sticks there while the tangential part stays inside the static
// cone (mu_s times the normal part); beyond it, it slides, placed on the
// kinetic cone's edge between where it was and the device's foot on the
// surface, and sticks again only when the device stops leading it: a steady
// drag slides steadily, without alternating stick and slip (no buzz), whatever
// the sphere bumps do to n. Translation only: a stuck tool may
// still turn about its tip (the tool frame's origin). A sliding pose is lifted
// out of the sphere bumps it would enter; a pose that still penetrates is not
// taken (the frictionless one is).
void ApplyFriction(const EngineModel& model, const RigidTransform& X_WH,
                   const QpSolution& sol, RigidTransform* X, EngineData* d) {
  const EngineParams& p = model.params;
  const EngineData::Friction before = d->friction;
  auto done = [&](EngineData::Friction now) {
    if (before != now) ++d->friction_transitions;
    d->friction = now;
  };
  if (sol.num_active == 0 || d->active_contacts == 0) {
    d->friction_device_W = X_WH.translation();
    return done(EngineData::Friction::kNone);
  }
  // The normal where the tool was (a curved crown turns it between there and
  // the frictionless pose): the mean direction of the pairs touching there
  // (this frame's pairs were found at that pose).
  const Vector3 p_H = X_WH.translation(), p_last = d->X_WG.translation();
  const RigidTransform X_last(X->rotation(), p_last);
  constexpr double kTouching = 1e-3,
                   kNear = 0.05;  // mm: touching the nearest; near enough to touch at all
  double nearest = kNear;
  for (int i = 0; i < d->num_pairs; ++i)
    nearest = std::min(nearest, model.world.PairGap(X_last, d->pairs[i]));
  Vector3 n = Vector3::Zero();
  double mu = 0, weight = 0;
  for (int i = 0; i < d->num_pairs && nearest < kNear; ++i) {
    const ContactPair& c = d->pairs[i];
    Vector3 away;
    const double gap = model.world.PairGap(X_last, c, &away);
    if (away.squaredNorm() == 0 || gap > nearest + kTouching) continue;
    n += away;
    mu += model.friction[c.object];
    weight += 1;
  }
  if (weight <= 0 || n.norm() < 1e-12) return done(EngineData::Friction::kNone);
  n.normalize();
  mu /= weight;
  const Vector3 r = p_last - p_H;
  const double normal =
      r.dot(n);  // the normal force / k_t with the tool kept where it was
  if (mu <= 0 || normal <= 0) return done(EngineData::Friction::kNone);
  const Vector3 t = r - normal * n;
  const double tangential = t.norm();
  const double mu_s = mu, mu_k = EngineModel::kKineticShare * mu;
  // Sliding, it goes on sliding while the device keeps leading it (its step
  // this frame along the tangential lead is more than 0.1 um), and sticks when
  // the device stops or turns back: the bumps between spheres, which turn n a
  // little from frame to frame, then cannot flip it back and forth.
  const Vector3 device_step = p_H - d->friction_device_W;
  d->friction_device_W = p_H;
  const bool leading = tangential > 1e-12 && device_step.dot(-t / tangential) > 1e-4;
  const bool stick = before == EngineData::Friction::kSlip
                         ? !leading && tangential <= mu_s * normal
                         : tangential <= mu_s * normal;
  RigidTransform candidate(X->rotation(), p_last);
  if (!stick) {
    // From the frictionless pose (on the surface, at the device's foot or short
    // of it), back toward where the tool was until the spring leans on the
    // kinetic cone's edge.
    const Vector3 p_X = X->translation(), x = p_X - p_H;
    const double x_normal = std::max(x.dot(n), 0.0);
    const double x_tangential = (x - x.dot(n) * n).norm();
    Vector3 back = p_last - p_X;
    back -= back.dot(n) * n;
    const double room = back.norm();
    const double lag = std::clamp(mu_k * x_normal - x_tangential, 0.0, room);
    candidate = RigidTransform(X->rotation(),
                               room > 1e-12 ? Vector3(p_X + (lag / room) * back) : p_X);
  }
  // A sliding pose is lifted out of the bumps between spheres that the tangent plane
  // cuts.
  double worst = WorstPenetration(model.world, candidate, *d);
  for (int i = 0; !stick && i < 3 && worst > p.penetration_tolerance_mm; ++i) {
    candidate = RigidTransform(candidate.rotation(),
                               candidate.translation() + (worst + 1e-6) * n);
    worst = WorstPenetration(model.world, candidate, *d);
  }
  if (worst <= p.penetration_tolerance_mm) {
    *X = candidate;
    return done(stick ? EngineData::Friction::kStick : EngineData::Friction::kSlip);
  }
  if (stick) {
    // Turning about the tip would enter the object: stuck whole.
    const RigidTransform last(d->X_WG.rotation(), p_last);
    if (WorstPenetration(model.world, last, *d) <= p.penetration_tolerance_mm) {
      *X = last;
      return done(EngineData::Friction::kStick);
    }
  }
  done(EngineData::Friction::kNone);
}

// The directions an eased slip's move is bounded along: the three axes and the
// cube's four diagonals for the translation (their polyhedron reaches at most
// kTrustSpread times its half-width, along a face's diagonal), then the three
// axes of the turn.
constexpr int kTrustDirections = 10;
constexpr double kTrustSpread = 1.2248;  // 3 / sqrt(6)
const std::array<Vector6, kTrustDirections> kTrustDirection = [] {
  std::array<Vector6, kTrustDirections> t;
  for (auto& u : t) u.setZero();
  for (int k = 0; k < 3; ++k) t[static_cast<std::size_t>(k)][k] = 1;
  const double c = 1 / std::sqrt(3.0);
  t[3].head<3>() = Vector3(c, c, c);
  t[4].head<3>() = Vector3(c, c, -c);
  t[5].head<3>() = Vector3(c, -c, c);
  t[6].head<3>() = Vector3(-c, c, c);
  for (int k = 0; k < 3; ++k) t[static_cast<std::size_t>(7 + k)][3 + k] = 1;
  return t;
}();

// How far the rendered tool may move this frame (EngineParams::slip_step_mm):
// as far as the device moved, plus the slip step; a tool farther from the
// device than the force limit's stretch of the spring closes on it to there
// unhindered (the force does not change).
double SlipAllowance(const EngineParams& p, const RigidTransform& X_WH,
                     const EngineData& d) {
  const double saturated =
      (d.X_WG.translation() - X_WH.translation()).norm() - p.max_force_n / p.k_t;
  return d.device_move_mm + p.slip_step_mm + std::max(0.0, saturated);
}

// Shortens a move longer than `allowed` along the straight way from the last
// pose, if that pose overlaps the frame's pairs no more than the whole one.
bool EaseAlongTheWay(const EngineModel& model, double allowed, EngineData* d,
                     RigidTransform* X, double* move) {
  if (*move <= allowed) return false;
  const double s = allowed / *move;
  const Vector6 dq = d->X_WG.DifferenceTo(*X);
  const RigidTransform X_s =
      Orthonormalised(d->X_WG.Perturbed(s * dq.head<3>(), s * dq.tail<3>()));
  const double worst = WorstPenetration(model.world, X_s, *d);
  if (worst > std::max(model.params.penetration_tolerance_mm, d->max_penetration_mm))
    return false;
  *X = X_s;
  *move = MoveBound(d->X_WG.DifferenceTo(X_s), model.world.tool_reach());
  return true;
}

// A frame inside an object: the search for free space, and no force.
void InsideFrame(const EngineModel& model, const RigidTransform& X_WH,
                 Clock::time_point t0, EngineData* d) {
  FindFreeSpace(model, X_WH, d);
  d->force_W.setZero();
  d->torque_W.setZero();
  d->force_saturated = false;
  d->timings.total_us = Micros(t0, Clock::now());
}

void EnterInside(EngineData* d) {
  d->inside = true;
  d->free_search_next = 0;
}

}  // namespace

EngineModel::EngineModel(const SphereTree& tool,
                         const std::vector<CollisionWorld::Object>& objects,
                         const EngineParams& p)
    : world(tool, objects), params(p) {}

EngineData::EngineData(const EngineModel& model)
    : pairs(model.params.max_pairs),
      A(static_cast<std::size_t>(model.params.max_pairs) * 6),
      b(model.params.max_pairs),
      active_keys(kQpMaxActive),
      warm_rows(kQpMaxActive),
      qp(model.params.max_pairs) {}

void ResetTool(const RigidTransform& X_WG, EngineData* d) {
  d->margin_cap_mm = EngineData::kMarginCapMaxMm;
  d->X_WG = X_WG;
  d->eased_held = false;
  d->X_WH = X_WG;
  d->num_pairs = 0;
  d->num_active_keys = 0;
  d->last_move_mm = 0;
  d->force_W.setZero();
  d->torque_W.setZero();
  d->initialized = true;
  d->inside = false;
  d->free_search_next = 0;
  d->held_frames = 0;
  d->placed_apart = false;
}

void Step(const EngineModel& model, const RigidTransform& X_WH, EngineData* d) noexcept {
  const auto t0 = Clock::now();
  const EngineParams& p = model.params;
  const CollisionWorld& world = model.world;
  const SphereTree& tool = world.tool();
  ++d->frames;
  d->timings = {};
  if (!Finite(X_WH)) {
    // Hold the graphic pose, send nothing: the thread ramps back in after faults.
    ++d->faults.nonfinite_device;
    d->force_W.setZero();
    d->torque_W.setZero();
    d->timings.total_us = Micros(t0, Clock::now());
    return;
  }
  d->device_step = d->initialized ? d->X_WH.DifferenceTo(X_WH) : Vector6(Vector6::Zero());
  d->device_move_mm = MoveBound(d->device_step, world.tool_reach());
  d->X_WH = X_WH;
  if (!d->initialized) ResetTool(X_WH, d);
  if (d->inside) return InsideFrame(model, X_WH, t0, d);
  if (d->placed_apart) {
    // Placed apart from the device by a deep start: met (within 0.5 mm), or
    // rejoined where the device comes out in free space (an overlap test of its
    // pose within the frame's budget; a budget cut short counts as not free).
    constexpr double kMetMm = 0.5;
    if ((d->X_WG.translation() - X_WH.translation()).norm() < kMetMm) {
      d->placed_apart = false;
    } else {
      const CollisionStats cs =
          FindContacts(world, X_WH, 0.0, &d->scratch, d->pairs.data(), 0,
                       QueryLimits{true, std::max(1, p.free_search_node_tests)});
      if (!cs.overflow && !cs.stack_overflow && !cs.cut_short) {
        ++d->faults.rejoined;
        ResetTool(X_WH, d);
        d->timings.total_us = Micros(t0, Clock::now());
        return;
      }
    }
  }

  // The query margin must cover how far any tool point moves this frame, so that
  // no pair outside it can be reached (no pop-through). Guess from the last
  // frame's move; if the solved pose moved further, query again with a margin
  // that covers the actual move and solve again (at most a few times).
  const Vector6 g = (Vector6() << p.k_t, p.k_t, p.k_t, p.k_r, p.k_r, p.k_r).finished();
  const double reach = world.tool_reach();
  // A crowded place (more than solve_pairs within the margin) caps the margin,
  // and with it the step, for this frame and the next ones (margin_cap_mm).
  const double lowest_cap = p.base_margin_mm + 1.25 * p.min_crowded_step_mm;
  double cap = std::max(d->margin_cap_mm, lowest_cap);
  double margin = std::min(p.base_margin_mm + 2.0 * d->last_move_mm, cap);
  RigidTransform X = d->X_WG;
  const QpSolution* sol = nullptr;
  d->linearizations = 0;
  double move = 0;
  // The graphic tool moves at most max_step_mm a frame toward the device, which
  // bounds the margin (and the pairs) however fast the device jumps.
  const Vector6 to_device = d->X_WG.DifferenceTo(X_WH);
  const double device_move = MoveBound(to_device, reach);
  double step_scale = device_move > p.max_step_mm ? p.max_step_mm / device_move : 1.0;
  // A step is kept within what the cap covers (a move of (cap - base) / 1.25).
  bool capped = false;  // this frame's step was shortened to fit the cap
  const auto fit_step = [&] {
    const double allowed = (cap - p.base_margin_mm) / 1.25;
    if (step_scale * device_move > allowed) {
      step_scale = allowed / device_move;
      capped = true;
    }
  };
  fit_step();
  d->node_tests = 0;
  d->node_budget_hit = false;
  bool crowded_frame = false;  // a query of this frame met more than solve_pairs
  bool accepted = false, deep = false;
  bool eased = false;                  // this frame's move was shortened to ease a slip
  double trust_mm = 0, trust_rad = 0;  // the box it was kept in, then
  double eased_allowed = 0;            // and the move it was allowed
  bool reuse_pairs = false;            // the next try solves with this try's pairs
  double overlap = 0;  // deepest overlap of the rendered tool at the frame's start
  d->sweeps = 0;
  for (int sweep = 0; sweep < EngineData::kMaxSweeps; ++sweep) {
    d->sweeps = sweep + 1;
    d->sweep_margin_mm[sweep] = margin;
    d->sweep_move_mm[sweep] = -1;
    const RigidTransform X_target =
        step_scale < 1.0 ? d->X_WG.Perturbed(step_scale * to_device.head<3>(),
                                             step_scale * to_device.tail<3>())
                         : X_WH;
    // An eased slip is solved again with the pairs it has (the same pose, the
    // same margin).
    if (!reuse_pairs) {
      const auto t_collide = Clock::now();
      // Past the capacity the set is not used: the query stops there. Every try
      // but the last keeps to solve_pairs.
      const bool whole_set = p.solve_pairs <= 0 || sweep == EngineData::kMaxSweeps - 1 ||
                             margin <= lowest_cap || margin > cap;
      const int capacity = whole_set ? p.max_pairs : std::min(p.max_pairs, p.solve_pairs);
      const CollisionStats cs =
          FindContacts(world, d->X_WG, margin, &d->scratch, d->pairs.data(), capacity,
                       QueryLimits{true, p.max_node_tests});
      d->num_pairs = cs.pairs;
      d->node_tests += cs.node_tests;
      d->timings.collide_us += Micros(t_collide, Clock::now());
      const bool over_budget = cs.cut_short && !cs.overflow;
      const bool crowded =
          cs.overflow && capacity < p.max_pairs;  // past solve_pairs only
      d->node_budget_hit = d->node_budget_hit || over_budget;
      d->pair_overflow = (cs.overflow && !crowded) || cs.stack_overflow || over_budget;
      crowded_frame = crowded_frame || crowded;
      if (sweep == 0 && !d->pair_overflow && !crowded)
        for (int i = 0; i < cs.pairs; ++i) overlap = std::max(overlap, -d->pairs[i].gap);
      if (crowded) {
        // More pairs than a frame solves with: a smaller margin (the cap, from
        // now on) and a step within it.
        cap = std::max(lowest_cap, p.base_margin_mm + 0.5 * (margin - p.base_margin_mm));
        margin = cap;
        fit_step();
        continue;
      }
      if (d->pair_overflow) {
        // Too many pairs to trust the set: try a shorter step with a smaller margin.
        step_scale *= 0.5;
        margin = p.base_margin_mm + 1.25 * step_scale * device_move;
        continue;
      }
    }
    reuse_pairs = false;

    // Warm start: last frame's active pairs (at most 8 keys), found by key.
    int num_warm = 0;
    for (int r = 0; r < d->num_pairs && num_warm < d->num_active_keys; ++r) {
      const std::uint64_t key = d->pairs[r].key();
      for (int i = 0; i < d->num_active_keys; ++i) {
        if (d->active_keys[i] == key) {
          d->warm_rows[num_warm++] = r;
          break;
        }
      }
    }
    X = d->X_WG;
    d->max_penetration_mm = 0;
    const int m = d->num_pairs;
    for (int pass = 0; pass < std::max(1, p.max_linearizations); ++pass) {
      const auto t_build = Clock::now();
      // Constraint i: n^T dp + ((c_T - p) x n)^T dtheta >= -gap, the distance
      // form linearised at X (docs/architecture.md step 3); n is the direction
      // from the object sphere's centre, or a clipped leaf's plane normal when
      // the plane decides the gap.
      for (int i = 0; i < m; ++i) {
        const ContactPair& c = d->pairs[i];
        const Vector3 cT = X * tool.center(c.tool_leaf);
        Vector3 n;
        const double gap =
            world.LeafGap(c.object, c.object_leaf, cT, tool.r[c.tool_leaf], &n, c.piece);
        if (n.squaredNorm() == 0) {
          // Coincident centres: no direction is defined; push along the line from
          // the object sphere to the tool origin (or +z when that too is degenerate).
          n = X.translation() - world.ObjectCenter(c.object, c.object_leaf);
          n = n.norm() > 1e-9 ? Vector3(n.normalized()) : Vector3::UnitZ();
        }
        const Vector3 lever = cT - X.translation();
        double* row = d->A.data() + 6 * i;
        Eigen::Map<Vector3> normal_part(row), moment_part(row + 3);
        normal_part = n;
        moment_part = lever.cross(n);
        d->b[i] = -gap;
      }
      // Easing a slip: rows after the pairs' keep the frame's whole move
      // (from the last frame's pose), along each axis, between staying and
      // the device's own step, widened by trust_mm (the turn by trust_rad).
      int rows = m;
      if (eased) {
        const Vector6 o = d->X_WG.DifferenceTo(X);
        for (int k = 0; k < kTrustDirections; ++k) {
          const Vector6& u = kTrustDirection[static_cast<std::size_t>(k)];
          const double h = u.dot(d->device_step), at = u.dot(o),
                       a = k < kTrustDirections - 3 ? trust_mm : trust_rad;
          for (const double sign : {1.0, -1.0}) {
            Eigen::Map<Vector6> row(d->A.data() + kQpVars * rows);
            row = sign * u;
            // sign u.(o + q) >= -(a + max(0, -sign u.h))
            d->b[rows++] = -(a + std::max(0.0, -sign * h)) - sign * at;
          }
        }
      }
      const Vector6 target = X.DifferenceTo(X_target);
      const auto t_solve = Clock::now();
      sol = &d->qp.Solve(d->A.data(), d->b.data(), rows, g, target, d->warm_rows.data(),
                         num_warm);
      const auto t_solved = Clock::now();
      d->timings.constraints_us += Micros(t_build, t_solve);
      d->timings.solve_us += Micros(t_solve, t_solved);
      ++d->linearizations;
      if (!Usable(sol->status)) break;
      const RigidTransform X_pass = X;
      X = Orthonormalised(X.Perturbed(sol->q.head<3>(), sol->q.tail<3>()));
      // Exact re-check at the new pose: no penetration, and the active constraints
      // tight (a linearisation is conservative on curved spheres: when it stopped
      // the tool short, solve again from the new pose, like an SQP step). A
      // pair's gap shrinks by at most the move of its tool sphere (each gap is
      // a distance, or at least the sphere distance where it is measured so),
      // so a pair further than this pass's move cannot penetrate: skipped.
      const double pass_move = MoveBound(X_pass.DifferenceTo(X), reach);
      double worst = 0;
      for (int i = 0; i < m; ++i)
        if (-d->b[i] <= pass_move)
          worst = std::max(worst, -world.PairGap(X, d->pairs[i]));
      double slack = 0;
      for (int i = 0; i < sol->num_active; ++i)
        if (sol->active[i] < m)
          slack = std::max(slack, world.PairGap(X, d->pairs[sol->active[i]]));
      d->max_penetration_mm = worst;
      if (sol->status == QpStatus::kInfeasibleRelaxed) break;
      // A tool that stopped short of a long move by a hundredth of it (a tool
      // sliding fast round a curved or edged surface) is not held back for that:
      // another linearisation would cost more than the hand can feel.
      const double slack_allowed = std::max(
          p.penetration_tolerance_mm, 0.01 * MoveBound(d->X_WG.DifferenceTo(X), reach));
      if (worst <= p.penetration_tolerance_mm && slack <= slack_allowed) break;
      // Re-linearise from the new pose, keeping this pass's active set as the guess.
      num_warm = 0;
      for (int i = 0; i < sol->num_active; ++i) d->warm_rows[num_warm++] = sol->active[i];
    }
    if (!Usable(sol->status)) break;
    if (sol->status == QpStatus::kInfeasibleRelaxed &&
        d->max_penetration_mm > p.inside_mm) {
      // No pose near this one is out of the object: the rendered tool is inside it.
      deep = true;
      break;
    }
    move = MoveBound(d->X_WG.DifferenceTo(X), reach);
    d->sweep_move_mm[sweep] = move;
    // Every pair left out had gap >= margin, so a shorter move cannot reach it.
    if (move < margin) {
      // A slip (the tool moving further than the device did plus slip_step_mm:
      // off an edge, over a bump, a contact ending) is solved again, with the
      // same pairs, within a box of that size round the last pose: the tool
      // closes on the device round the surface over a few frames. A tool the
      // box held in a valley between sphere bumps (its last eased frame moved
      // it less than a quarter of its allowance) takes its whole move once.
      const double allowed = SlipAllowance(p, X_WH, *d);
      if (p.slip_step_mm > 0 && model.friction.empty() && !eased && !d->eased_held &&
          move > allowed && overlap <= 10 * p.penetration_tolerance_mm &&
          m + 2 * kTrustDirections <= p.max_pairs && sweep < EngineData::kMaxSweeps - 1) {
        eased = true;
        reuse_pairs = true;
        eased_allowed = allowed;
        // A polyhedron round the last pose (a cube cut by the planes across its
        // corners) that reaches at most the slip step (and what saturation
        // frees) beyond the device's own step, in any direction.
        trust_mm = (allowed - d->device_move_mm) / kTrustSpread;
        trust_rad = 0.5 * trust_mm / reach;
        continue;
      }
      accepted = true;
      break;
    }
    // Cover the actual move, with headroom; within the cap, a shorter step. A
    // move well beyond the step (the tool pushed out of an overlap, as when a
    // session starts with the device in tissue) is not shortened by a shorter
    // step: its margin is not capped, and its set is solved whole.
    const double wanted = p.base_margin_mm + 1.25 * move;
    if (wanted > cap && move < 2.0 * step_scale * device_move) {
      if (margin >= cap)
        step_scale *= 0.5;  // the set at the cap did not hold the move: shorter
      margin = cap;
      fit_step();
    } else {
      margin = wanted;
    }
  }
  d->margin_mm = margin;
  // The cap grows back where the margin it allowed found few pairs.
  // With no pair at all, it is lifted.
  if (accepted && d->num_pairs == 0) cap = EngineData::kMarginCapMaxMm;
  if (accepted && margin >= 0.8 * cap && d->num_pairs < p.solve_pairs / 4)
    cap = p.base_margin_mm + 1.25 * (cap - p.base_margin_mm);
  d->margin_cap_mm = std::min(cap, EngineData::kMarginCapMaxMm);
  if (crowded_frame) ++d->shortened_frames;
  if (capped) ++d->capped_frames;
  if (eased && accepted) ++d->eased_frames;
  d->eased_held = eased && accepted && move < 0.25 * eased_allowed;
  if (deep || (!accepted && ((d->pair_overflow && sol == nullptr) ||
                             overlap > 10 * p.penetration_tolerance_mm))) {
    // Inside an object, overlapping it by more pairs than a set holds even at
    // the shortest step, or overlapping it in a frame that could not move (the
    // next frame would be the same: a frozen tool): follow the device with no
    // force until free space next to it is found, starting this frame.
    EnterInside(d);
    return InsideFrame(model, X_WH, t0, d);
  }
  if (d->pair_overflow) ++d->faults.pair_overflow;
  if (sol != nullptr) {
    d->qp_status = sol->status;
    d->qp_iterations = sol->iterations;
    d->kkt_residual = sol->kkt_residual;
  }
  if (accepted) {
    d->held_frames = 0;
    // The accepted sweep's pairs and solution belong together: commit both.
    if (!model.friction.empty()) {
      ApplyFriction(model, X_WH, *sol, &X, d);
      move = MoveBound(d->X_WG.DifferenceTo(X),
                       reach);  // a stuck tool did not move: the next margin is small
      // With friction the slip is eased after it (a tool let go by the cone):
      // along the straight way to the friction's pose, checked exactly.
      if (p.slip_step_mm > 0 && overlap <= 10 * p.penetration_tolerance_mm &&
          EaseAlongTheWay(model, SlipAllowance(p, X_WH, *d), d, &X, &move))
        ++d->eased_frames;
    }
    d->X_WG = X;
    d->last_move_mm = move;
    d->active_contacts = 0;
    d->num_active_keys = 0;
    double total = 0;
    for (int i = 0; i < sol->num_active; ++i) {
      const int row = sol->active[i];
      if (row >= d->num_pairs) continue;  // a row of the slip's box, not a pair
      ++d->active_contacts;
      d->active_keys[d->num_active_keys] = d->pairs[row].key();
      // The row's share of the contact force: its multiplier times the
      // translational part of its normal.
      const double* a = &d->A[static_cast<std::size_t>(row) * kQpVars];
      const double w = std::max(0.0, sol->lambda[i]) *
                       std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
      d->active_share[d->num_active_keys++] = w;
      total += w;
    }
    for (int i = 0; i < d->num_active_keys; ++i)
      d->active_share[i] =
          total > 0 ? d->active_share[i] / total : 1.0 / d->num_active_keys;
    if (d->max_penetration_mm > p.penetration_tolerance_mm &&
        sol->status == QpStatus::kSolved) {
      ++d->faults.penetration;
    }
  } else {
    // A failed solve, or a move no query covered: hold the graphic pose.
    ++(sol != nullptr && !Usable(sol->status) ? d->faults.solver : d->faults.sweep);
    d->last_move_mm = 0;
    d->active_contacts = 0;
    d->num_active_keys = 0;
    if (++d->held_frames > p.max_held_frames) {
      // Held frame after frame: the next would meet the same wall. Free space
      // next to the device instead of a frozen tool.
      ++d->faults.held;
      d->held_frames = 0;
      EnterInside(d);
      return InsideFrame(model, X_WH, t0, d);
    }
  }
  SpringWrench(p, X_WH, d);
  d->timings.total_us = Micros(t0, Clock::now());
}

}  // namespace sulcus
