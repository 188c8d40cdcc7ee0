#pragma once
// Effects on demand (docs/architecture.md, "One haptic frame", step 6): a scene lists the
// effects it needs, and the loop's list holds exactly those, so an effect the scene does
// not name is not in the loop at all (no call, no branch). Each effect reads the engine's
// data after the step, may add to the output force, and emits typed events
// (kProbeReading, kBleeding, kTissueDamage, kSoftContact; haptic_loop.h).
//
//   gingiva_compliance  soft tissue the probe displaces: its objects are not
//                       constraints of the engine but springs (soft walls, a firm
//                       pocket floor), so the probe can enter the sulcus.
//   probing_depth       a reading per visit of the tip to a site's sulcus: its
//                       deepest dwell (probe_reading.h), where the tip locator
//                       (tip_locator.h) puts the tip.
//   bleeding_on_probing a bleeding site bleeds when probed to its floor.
//   tissue_damage       the force the working end puts on an object above its
//                       tissue's damage limit (the shank resting on a lip or a
//                       cheek holds it aside, as a clinician's instrument does).
//   caries_catch        a carious lesion is softer than enamel (the normal force
//                       there is scaled down) and catches a tip pressed into it
//                       (a tangential spring to where it caught, slipping past a
//                       cap), with an event when it catches.
//   calculus            a calculus deposit (a hard object of the scene, standing
//                       proud of the tooth: felt as a raised edge) announces
//                       itself when the working end meets it, with its share
//                       of the contact force (kCalculusTouched).
//   surface_texture     enamel, root cementum and calculus feel different
//                       under a sliding tip: a small force along the contact
//                       normal, periodic in the distance slid.

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/haptics/haptic_loop.h"
#include "core/haptics/probe_reading.h"
#include "core/haptics/tip_locator.h"

namespace sulcus {

/// Which of the effects this layer implements the scene named (friction is
/// the engine's, EngineModel::friction).
struct EffectsOn {
  bool gingiva_compliance = false, probing_depth = false, bleeding_on_probing = false,
       tissue_damage = false;
  bool caries_catch = false, surface_texture = false, calculus = false;
};

/// surface_texture: what a sliding tip feels of each surface, a force along
/// the contact normal that varies with the distance slid (so the same at any
/// haptic rate): amplitude (N, at 0.5 N of contact force and in proportion
/// below) and spatial period (mm).
struct Texture {
  double amplitude_n = 0, period_mm = 1;
};
/// What an object's surface is for the texture: none, or a tooth (enamel above
/// its CEJ, root cementum below), or calculus.
enum class TextureKind : std::uint8_t { kNone, kTooth, kCalculus };
struct TextureFeel {
  Texture enamel{0.015, 0.25}, root{0.04, 0.15}, calculus{0.10, 0.30};
};

/// A carious lesion in the world: on object `tooth`, a disc of `radius_mm`
/// about `centre_W` on the surface whose outward normal there is `normal_W`.
struct CariesLesion {
  int tooth = -1;
  Vector3 centre_W = Vector3::Zero(), normal_W = Vector3::UnitZ();
  double radius_mm = 0;
  int surface = 0;  // ToothSurface: mesial, distal, buccal, lingual, occlusal
};

/// caries_catch's feel: the share of the normal force a lesion's centre keeps
/// (softer than enamel), the normal force at which a tip catches, the catch's
/// tangential stiffness and how much of the normal force it can hold.
struct CariesFeel {
  double softness = 0.6;  // normal force scaled to this at the centre, to 1 at the rim
  double catch_force_n = 0.3;
  double catch_k_n_per_mm = 0.8;
  double catch_ratio = 0.8;
};

/// What the effects need from the scene, immutable after compile.
struct EffectsModel {
  EffectsOn on;
  std::vector<double> damage_limit_n;  // per object
  // tissue_damage: per node of the tool's tree, 1 for the working end's leaves
  // (within kWorkingEndMm of the tip); empty: every leaf counts.
  std::vector<std::uint8_t> tool_working_end;
  static constexpr double kWorkingEndMm = 4.0;
  std::vector<ProbingSite> sites;
  // gingiva_compliance: the soft objects, their own collision world (object i of
  // it is scene object soft_first + i), and per leaf node a stiffness (N/mm).
  std::unique_ptr<CollisionWorld> soft_world;
  int soft_first = 0;
  std::vector<std::vector<float>> soft_leaf_stiffness;
  // calculus: per object, the deposit's tooth and site (fdi 0: not a deposit)
  struct Deposit {
    int fdi = 0, site = 0;
  };
  std::vector<Deposit> deposits;
  // caries_catch
  std::vector<CariesLesion> lesions;
  CariesFeel caries;
  // surface_texture: per hard object its kind and its frame's inverse (for a
  // tooth, the tip's height above the CEJ in the tooth frame).
  std::vector<TextureKind> texture_kind;
  std::vector<RigidTransform> X_OW;
  TextureFeel texture;
};

/// The effects that are on, in a fixed order, ready for HapticLoop. An effect
/// with nothing to act on (compliance without soft objects, depth without
/// sites) is left out. `rate_hz`: the loop's (a reading's visit ends after a
/// time away, counted in ticks).
std::vector<std::unique_ptr<LoopEffect>> MakeEffects(const EffectsModel& model,
                                                     double rate_hz = 1000);

/// Raw pointers for HapticLoop's span.
std::vector<LoopEffect*> EffectPointers(
    const std::vector<std::unique_ptr<LoopEffect>>& effects);

}  // namespace sulcus
