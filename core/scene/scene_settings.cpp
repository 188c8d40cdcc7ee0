#include "core/scene/scene_settings.h"

#include <algorithm>
#include <iterator>
#include <string>
#include <vector>

namespace sulcus {
namespace {

struct EffectName {
  const char* name;
  Effect effect;
};
constexpr EffectName kEffects[] = {{"contact", Effect::kContact},
                                   {"gingiva_compliance", Effect::kGingivaCompliance},
                                   {"friction", Effect::kFriction},
                                   {"surface_texture", Effect::kSurfaceTexture},
                                   {"probing_depth", Effect::kProbingDepth},
                                   {"bleeding_on_probing", Effect::kBleedingOnProbing},
                                   {"tissue_damage", Effect::kTissueDamage},
                                   {"caries_catch", Effect::kCariesCatch},
                                   {"calculus", Effect::kCalculus}};

}  // namespace

const char* ToString(Effect e) {
  for (const auto& en : kEffects) {
    if (en.effect == e) return en.name;
  }
  return "?";
}

void ReadHaptics(YamlReader& r, const YAML::Node& h, SceneSpec* spec) {
  r.CheckKeys(h,
              {"k_t_n_per_mm", "k_r_nmm_per_rad", "max_force_n", "max_torque_nmm",
               "rate_hz", "surface", "solve_pairs", "slip_mm_per_s"},
              "'haptics'");
  EngineParams& p = spec->haptics;
  if (h["k_t_n_per_mm"])
    p.k_t = r.Number(h["k_t_n_per_mm"], "k_t_n_per_mm", 1e-3, 100, p.k_t, "N/mm");
  if (h["k_r_nmm_per_rad"])
    p.k_r =
        r.Number(h["k_r_nmm_per_rad"], "k_r_nmm_per_rad", 1e-3, 1e6, p.k_r, "N*mm/rad");
  if (h["max_force_n"])
    p.max_force_n = r.Number(h["max_force_n"], "max_force_n", 0, 50, p.max_force_n, "N");
  if (h["max_torque_nmm"])
    p.max_torque_nmm = r.Number(h["max_torque_nmm"], "max_torque_nmm", 0, 5000,
                                p.max_torque_nmm, "N*mm");
  if (h["solve_pairs"]) {
    p.solve_pairs =
        r.Integer(h["solve_pairs"], "solve_pairs", 0, p.max_pairs, p.solve_pairs);
    if (p.solve_pairs > 0 && p.solve_pairs < 16) {
      r.Error(h["solve_pairs"],
              "'solve_pairs' must be 0 (no limit) or at least 16 (a probe resting on a "
              "tooth "
              "alone meets a dozen pairs)");
    }
  }
  if (h["rate_hz"])
    spec->rate_hz = r.Number(h["rate_hz"], "rate_hz", 100, 10000, spec->rate_hz, "Hz");
  // A slip eased at 50 mm/s whatever the rate (0.05 mm a frame at 1 kHz);
  // 0: not eased (a slip is felt in one tick, as a click).
  double slip_mm_per_s = 50.0;
  if (h["slip_mm_per_s"])
    slip_mm_per_s =
        r.Number(h["slip_mm_per_s"], "slip_mm_per_s", 0, 1000, slip_mm_per_s, "mm/s");
  p.slip_step_mm = slip_mm_per_s / spec->rate_hz;
  if (const YAML::Node s = h["surface"]) {
    const std::string v = s.IsScalar() ? s.Scalar() : "";
    if (v == "planes" || v == "spheres") {
      spec->leaf_planes = v == "planes";
    } else {
      r.Error(s,
              "'surface' must be 'planes' (leaf spheres clipped by planes fitted to "
              "the mesh, the default) or "
              "'spheres' (the leaf spheres alone)");
    }
  }
}

void ReadEffects(YamlReader& r, const YAML::Node& e, SceneSpec* spec) {
  if (!e.IsSequence()) {
    r.Error(e, "'effects' must be a list, e.g. [contact, probing_depth]");
    return;
  }
  for (const YAML::Node& item : e) {
    const std::string name = item.IsScalar() ? item.Scalar() : "";
    const auto* en = std::find_if(std::begin(kEffects), std::end(kEffects),
                                  [&](const EffectName& x) { return name == x.name; });
    if (en == std::end(kEffects)) {
      std::vector<std::string> names;
      for (const auto& x : kEffects) names.push_back(x.name);
      r.Error(item, "unknown effect '" + name + "'" + Suggest(name, names));
    } else if (!spec->HasEffect(en->effect)) {
      spec->effects.push_back(en->effect);
    }
  }
}

}  // namespace sulcus
