#include "core/scene/scene.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>

#include "core/anatomy/arch.h"
#include "core/anatomy/findings.h"
#include "core/anatomy/gingiva.h"
#include "core/anatomy/soft_tissue.h"
#include "core/anatomy/tooth.h"
#include "core/base/files.h"
#include "core/base/text.h"
#include "core/base/yaml_reader.h"
#include "core/scene/mesh_paths.h"
#include "core/scene/object_gingiva.h"
#include "core/scene/scene_settings.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

struct TissueName {
  const char* name;
  Tissue tissue;
};
constexpr TissueName kTissues[] = {
    {"enamel", Tissue::kEnamel},    {"root", Tissue::kRoot},
    {"gingiva", Tissue::kGingiva},  {"bone", Tissue::kBone},
    {"tongue", Tissue::kTongue},    {"cheek", Tissue::kCheek},
    {"palate", Tissue::kPalate},    {"lip", Tissue::kLip},
    {"mucosa", Tissue::kMucosa},    {"metal", Tissue::kMetal},
    {"calculus", Tissue::kCalculus}};
const std::vector<std::string> kProbes = {"williams", "unc15", "who", "explorer23",
                                          "explorer1112"};

using Reader = YamlReader;

// A pose given as `at_key: [x, y, z]` (mm) and `turn_key: [rx, ry, rz]`
// (degrees about x, y, z), each optional.
RigidTransform ReadPose(Reader& r, const YAML::Node& map, const char* at_key,
                        const char* turn_key) {
  double at[3] = {0, 0, 0}, turn[3] = {0, 0, 0};
  if (map[at_key])
    r.Numbers(map[at_key], at_key, 3, -1000, 1000, at, "mm", "x, y, z in mm");
  if (map[turn_key])
    r.Numbers(map[turn_key], turn_key, 3, -360, 360, turn, "degrees",
              "turns about x, y, z in degrees");
  constexpr double kDeg = std::numbers::pi / 180;
  Vector6 q;
  q << at[0], at[1], at[2], turn[0] * kDeg, turn[1] * kDeg, turn[2] * kDeg;
  return RigidTransform::FromConfiguration(q);
}

std::vector<std::string> Names(const auto& table) {
  std::vector<std::string> v;
  for (const auto& t : table) v.push_back(t.name);
  return v;
}

// A map from tooth surfaces to values (`caries_mm: {occlusal: 2.0}`): calls
// each(surface index, key, value) for every known surface; a node that is not
// a map gets `not_a_map`, an unknown surface an error with a suggestion.
template <class Each>
void ForEachSurface(Reader& r, const YAML::Node& c, const std::string& not_a_map,
                    Each each) {
  if (!c) return;
  if (!c.IsMap()) {
    r.Error(c, not_a_map);
    return;
  }
  const std::vector<std::string> surfaces(kSurfaces.begin(), kSurfaces.end());
  for (auto it = c.begin(); it != c.end(); ++it) {
    const std::string surface = it->first.Scalar();
    const auto at = std::find(surfaces.begin(), surfaces.end(), surface);
    if (at == surfaces.end()) {
      r.Error(it->first, "unknown surface '" + surface + "'" +
                             Suggest(surface, surfaces) + " (" + Join(surfaces) + ")");
      continue;
    }
    each(static_cast<std::size_t>(at - surfaces.begin()), it->first, it->second);
  }
}

// A `spheretree` map over the values in *p (the scene's, for an object's own).
// `gingiva` (the collars' sub-map) is read by the caller where it is allowed.
void ReadTreeParams(Reader& r, const YAML::Node& t, const std::string& where,
                    bool gingiva_allowed, SphereTreeParams* p) {
  if (!r.IsMap(t, where)) return;
  std::vector<std::string> keys = {"levels",          "branch", "leaves",
                                   "target_error_mm", "spend",  "tighten_passes"};
  if (gingiva_allowed) keys.push_back("gingiva");
  r.CheckKeys(t, keys, where);
  if (t["levels"]) p->levels = r.Integer(t["levels"], "levels", 1, 8, p->levels);
  if (t["branch"]) p->branching = r.Integer(t["branch"], "branch", 2, 32, p->branching);
  if (t["leaves"]) p->leaves = r.Integer(t["leaves"], "leaves", 1, kMaxLeaves, p->leaves);
  if (t["target_error_mm"])
    p->target_error_mm =
        r.Number(t["target_error_mm"], "target_error_mm", kMinTargetErrorMm, 10, 0, "mm");
  if (t["spend"]) {
    const std::string spend = r.Text(t["spend"], "spend");
    if (const auto parsed = ParseSpend(spend)) {
      p->spend = *parsed;
    } else if (t["spend"].IsScalar()) {  // (else Text has said what is wrong)
      r.Error(t["spend"],
              "in " + where + ": 'spend' is '" + spend + "' (expected mean or worst)");
    }
  }
  if (t["tighten_passes"])
    p->tighten_passes =
        r.Integer(t["tighten_passes"], "tighten_passes", 1, 8, p->tighten_passes);
  const std::size_t capacity = LeafCapacity(p->levels, p->branching);
  if (p->target_error_mm == 0 && static_cast<std::size_t>(p->leaves) > capacity) {
    r.Error(t, "in " + where + ": " + std::to_string(p->leaves) +
                   " leaves do not fit in " + std::to_string(p->levels) + " levels of " +
                   std::to_string(p->branching) + " (at most " +
                   std::to_string(capacity) + "); raise 'levels'");
  }
}

void ReadObject(Reader& r, const YAML::Node& n, const fs::path& folder, int index,
                SceneSpec* spec, std::set<std::string>* names) {
  ObjectSpec o;
  o.file_index = index;
  o.line = n.Mark().line + 1;
  o.column = n.Mark().column + 1;
  o.mouth_open_mm = spec->mouth_open_mm;
  o.trees = spec->trees;
  if (!r.IsMap(n, "an object")) return;
  r.CheckKeys(n, {"name",     "tooth",          "mesh",       "box",
                  "sphere",   "cylinder",       "anatomy",    "height_mm",
                  "at",       "turn_deg",       "tissue",     "stiffness_n_per_mm",
                  "friction", "damage_limit_n", "pockets_mm", "recession_mm",
                  "bleeding", "inflamed",       "caries_mm",  "cavity_mm",
                  "calculus", "furcation",      "lesion",     "spheretree",
                  "mobility"},
              "an object");
  if (n["spheretree"]) {
    ReadTreeParams(r, n["spheretree"], "an object's 'spheretree'", false, &o.trees);
    o.own_trees = true;
  }
  std::vector<std::string> kinds;
  for (const char* k : {"tooth", "mesh", "box", "sphere", "cylinder", "anatomy"}) {
    if (n[k]) kinds.push_back(k);
  }
  if (kinds.size() != 1) {
    r.Error(n, kinds.empty()
                   ? "an object needs one of: tooth, mesh, box, sphere, cylinder, anatomy"
                   : "an object has exactly one of tooth, mesh, box, sphere, cylinder, "
                     "anatomy; found " +
                         Join(kinds));
    return;
  }
  const std::string kind = kinds[0];
  double root_length = 0;
  if (kind == "tooth") {
    o.kind = ObjectSpec::Kind::kTooth;
    o.fdi = r.Integer(n["tooth"], "tooth", -1000000, 1000000, 0);
    try {
      const FdiTooth t = FdiTooth::Parse(o.fdi);
      root_length = Dimensions(t).longest_root();
    } catch (const std::invalid_argument& e) {
      r.Error(n["tooth"], e.what());
    }
    o.name = "tooth " + std::to_string(o.fdi);
    o.tissue = Tissue::kEnamel;
  } else if (kind == "mesh") {
    o.kind = ObjectSpec::Kind::kMesh;
    const std::string rel = r.Text(n["mesh"], "mesh");
    const fs::path full = (folder / rel).lexically_normal();
    if (const std::string why = MeshPathProblem(rel, folder); !why.empty())
      r.Error(n["mesh"], why);
    o.mesh = full;
    o.name = fs::path(rel).stem().string();
  } else if (kind == "anatomy") {
    o.kind = ObjectSpec::Kind::kAnatomy;
    o.anatomy = r.Text(n["anatomy"], "anatomy");
    const auto& known = SoftTissueNames();
    if (std::find(known.begin(), known.end(), o.anatomy) == known.end()) {
      r.Error(n["anatomy"], "unknown anatomy '" + o.anatomy + "'" +
                                Suggest(o.anatomy, known) + " (known: " + Join(known) +
                                ")");
    }
    o.name = o.anatomy;
    std::replace(o.name.begin(), o.name.end(), '_', ' ');
    o.tissue = o.anatomy == "tongue"                                 ? Tissue::kTongue
               : o.anatomy == "palate" || o.anatomy == "soft_palate" ? Tissue::kPalate
               : o.anatomy.rfind("cheek", 0) == 0                    ? Tissue::kCheek
               : o.anatomy.rfind("lip", 0) == 0                      ? Tissue::kLip
               : o.anatomy == "floor_of_mouth"                       ? Tissue::kMucosa
                                                                     : Tissue::kBone;
  } else if (kind == "box") {
    o.kind = ObjectSpec::Kind::kBox;
    double s[3] = {1, 1, 1};
    r.Numbers(n["box"], "box", 3, 1e-3, 200, s, "mm", "sizes along x, y, z in mm");
    o.size = Vector3(s[0], s[1], s[2]);
    o.name = "box " + std::to_string(index + 1);
  } else {
    o.kind = kind == "sphere" ? ObjectSpec::Kind::kSphere : ObjectSpec::Kind::kCylinder;
    o.radius_mm =
        r.Number(n[kind], kind, 1e-3, 100, 1, "mm (a mouth is about 60 mm across)");
    if (kind == "cylinder") {
      if (n["height_mm"]) {
        o.height_mm = r.Number(n["height_mm"], "height_mm", 1e-3, 200, 1, "mm");
      } else {
        r.Error(n, "a cylinder needs 'height_mm'");
      }
    }
    o.name = kind + " " + std::to_string(index + 1);
  }
  if (kind != "cylinder" && n["height_mm"])
    r.Error(n["height_mm"], "'height_mm' is for cylinders only");
  if (n["name"]) o.name = r.Text(n["name"], "name");
  if (!names->insert(o.name).second)
    r.Error(n["name"] ? n["name"] : n, "two objects are named '" + o.name + "'");
  o.X_WO = ReadPose(r, n, "at", "turn_deg");
  // An upper tooth placed by hand stands crown down, as in the mouth (its frame
  // turned half a turn about y: occlusal down, buccal still +y), unless the
  // scene turns it itself.
  if (kind == "tooth" && !n["turn_deg"] && o.fdi > 0 && !(spec->arch && !n["at"])) {
    try {
      if (FdiTooth::Parse(o.fdi).upper())
        o.X_WO =
            o.X_WO *
            RigidTransform(
                Eigen::AngleAxisd(std::numbers::pi, Vector3::UnitY()).toRotationMatrix(),
                Vector3::Zero());
    } catch (const std::invalid_argument&) {
      // reported with the tooth
    }
  }
  if (kind == "tooth" && spec->arch && !n["at"] && !n["turn_deg"] && o.fdi > 0) {
    try {
      const FdiTooth t = FdiTooth::Parse(o.fdi);
      for (const PlacedTooth& p :
           PlaceArch(t.upper(), ArchParams{.upper_lift_mm = spec->mouth_open_mm,
                                .third_molars = t.position == 8})) {
        if (p.tooth.fdi == o.fdi) {
          o.X_WO = p.X_WT;
          o.mirrored = p.mirrored;
        }
      }
    } catch (const std::invalid_argument&) {
      // reported above
    }
  }
  if (n["tissue"]) {
    const std::string t = r.Text(n["tissue"], "tissue");
    bool found = false;
    for (const auto& tn : kTissues) {
      if (t == tn.name) {
        o.tissue = tn.tissue;
        found = true;
      }
    }
    if (!found)
      r.Error(n["tissue"], "unknown tissue '" + t + "'" + Suggest(t, Names(kTissues)));
  } else if (kind != "tooth" && kind != "anatomy") {
    r.Error(n, "'" + o.name + "' needs a 'tissue' (" + Join(Names(kTissues)) + ")");
  }
  o.material = DefaultMaterial(o.tissue);
  // Keys of the design that this version does not use: refused, never ignored.
  if (n["stiffness_n_per_mm"])
    r.Error(
        n["stiffness_n_per_mm"],
        "'stiffness_n_per_mm' is not used by this version of Sulcus (hard objects are "
        "rigid; gingiva_compliance sets the gingiva's own); remove it");
  if (n["friction"])
    o.material.friction =
        r.Number(n["friction"], "friction", 0, 2, o.material.friction, "");
  if (n["damage_limit_n"])
    o.material.damage_limit_n =
        r.Number(n["damage_limit_n"], "damage_limit_n", 0, 1e9, 1, "N");

  if (const YAML::Node& l = n["lesion"]) {
    // lesion: {kind: ulcer, region: lateral_border_left, size_mm: 3}
    if (kind != "anatomy") {
      r.Error(l,
              "'lesion' is for soft tissue ('anatomy' objects); a tooth's findings are "
              "caries_mm and calculus");
    } else if (!l.IsMap()) {
      r.Error(l,
              "'lesion' must be a map, e.g. {kind: ulcer, region: lateral_border_left, "
              "size_mm: 3}");
    } else {
      r.CheckKeys(l, {"kind", "region", "size_mm"}, "'lesion'");
      const auto regions = LesionRegions(o.anatomy);
      if (regions.empty())
        r.Error(l, "no lesion on '" + o.anatomy +
                       "': it is bone; lesions are for soft tissue");
      if (!l["kind"]) {
        r.Error(l, "a lesion needs 'kind' (" + Join(LesionKinds()) + ")");
      } else {
        o.lesion_kind = r.Text(l["kind"], "kind");
        if (std::find(LesionKinds().begin(), LesionKinds().end(), o.lesion_kind) ==
            LesionKinds().end())
          r.Error(l["kind"], "unknown lesion '" + o.lesion_kind + "'" +
                                 Suggest(o.lesion_kind, LesionKinds()));
      }
      if (l["region"]) {
        o.lesion_region = r.Text(l["region"], "region");
        if (!regions.empty() &&
            std::find(regions.begin(), regions.end(), o.lesion_region) == regions.end())
          r.Error(l["region"], "'" + o.anatomy + "' has no region '" + o.lesion_region +
                                   "'" + Suggest(o.lesion_region, regions));
      } else if (regions.size() > 1) {
        r.Error(l, "a lesion on the " + o.anatomy + " needs 'region' (" + Join(regions) +
                       ")");
      } else if (!regions.empty()) {
        o.lesion_region = regions[0];
      }
      o.lesion_mm = l["size_mm"] ? r.Number(l["size_mm"], "size_mm", 0.5, 15, 2,
                                            "mm (the lesion's radius)")
                                 : 2.0;
    }
  }
  if (const YAML::Node& f = n["furcation"]; f && kind == "tooth" && o.fdi > 0) {
    // furcation: {B: 2, L: 1}
    std::vector<std::string> entrances;
    try {
      entrances = FurcationEntrances(o.fdi);
    } catch (const std::invalid_argument&) {
      // reported with the tooth
    }
    if (!f.IsMap()) {
      r.Error(f,
              "'furcation' must map entrances to Hamp classes 0 to 3, e.g. {B: 2, L: 1}");
    } else if (entrances.empty()) {
      r.Error(f, "tooth " + std::to_string(o.fdi) + " has one root: no furcation");
    } else {
      for (auto it = f.begin(); it != f.end(); ++it) {
        const std::string e = it->first.Scalar();
        if (std::find(entrances.begin(), entrances.end(), e) == entrances.end()) {
          r.Error(it->first, "tooth " + std::to_string(o.fdi) +
                                 " has no furcation entrance '" + e +
                                 "' (its entrances: " + Join(entrances) + ")");
        } else {
          o.furcation[e] = r.Integer(it->second, "furcation class", 0, 3, 0);
        }
      }
    }
  }
  if (n["mobility"] && kind == "tooth")
    o.mobility = r.Integer(n["mobility"], "mobility (Miller 0 to 3)", 0, 3, 0);
  for (const char* key :
       {"pockets_mm", "recession_mm", "bleeding", "inflamed", "caries_mm", "cavity_mm",
        "calculus", "furcation", "mobility"}) {
    if (n[key] && kind != "tooth")
      r.Error(n[key], std::string("'") + key + "' is for teeth only");
  }
  if (kind == "tooth") {
    if (n["pockets_mm"]) {
      o.has_sites = true;
      if (r.Numbers(n["pockets_mm"], "pockets_mm", 6, 0, 15, o.pocket_mm.data(), "mm",
                    "depths at MB, B, DB, ML, L, DL in mm") &&
          root_length > 0) {
        for (int i = 0; i < 6; ++i) {
          if (o.pocket_mm[i] >= root_length) {
            std::ostringstream s;
            s << "pocket of " << o.pocket_mm[i] << " mm at site " << kSiteCodes[i]
              << " is deeper than the root of tooth " << o.fdi << " (" << root_length
              << " mm)";
            r.Error(n["pockets_mm"][i], s.str());
          }
        }
      }
    }
    if (n["recession_mm"]) {
      r.Numbers(n["recession_mm"], "recession_mm", 6, -5, 10, o.recession_mm.data(), "mm",
                "recession at MB, B, DB, ML, L, DL in mm; negative for enlarged gingiva");
    }
    for (const char* key : {"bleeding", "inflamed"}) {
      const YAML::Node& b = n[key];
      if (!b) continue;
      std::array<bool, 6>& flags =
          std::string(key) == "bleeding" ? o.bleeding : o.inflamed;
      if (!b.IsSequence()) {
        r.Error(b, std::string("'") + key + "' must be a list of sites, e.g. [MB, DL]");
        continue;
      }
      for (const YAML::Node& site : b) {
        const std::string code = site.IsScalar() ? site.Scalar() : "";
        const auto it = std::find(kSiteCodes.begin(), kSiteCodes.end(), code);
        if (it == kSiteCodes.end()) {
          r.Error(site, "unknown site '" + code + "'" +
                            Suggest(code, std::vector<std::string>(kSiteCodes.begin(),
                                                                   kSiteCodes.end())));
        } else {
          flags[it - kSiteCodes.begin()] = true;
        }
      }
    }
    ForEachSurface(r, n["caries_mm"],
                   "'caries_mm' must map surfaces to lesion sizes, e.g. {occlusal: 2.0}",
                   [&](std::size_t s, const YAML::Node&, const YAML::Node& value) {
                     o.caries_mm[s] = r.Number(value, "caries_mm", 0.1, 8, 1, "mm");
                   });
    // cavity_mm: {occlusal: 0.8}: the lesion there is cavitated, this deep.
    ForEachSurface(
        r, n["cavity_mm"],
        "'cavity_mm' must map surfaces to cavity depths, e.g. {occlusal: 0.8}",
        [&](std::size_t s, const YAML::Node& key, const YAML::Node& value) {
          o.cavity_mm[s] = r.Number(value, "cavity_mm", 0.1, kMaxCavityMm, 0.5, "mm");
          if (o.caries_mm[s] <= 0) {
            r.Error(key, "a cavity is in a carious lesion: give 'caries_mm' a " +
                             key.Scalar() + " lesion first");
          } else if (o.cavity_mm[s] > o.caries_mm[s]) {
            char m[160];
            std::snprintf(m, sizeof m,
                          "a cavity %.1f mm deep in a lesion of %.1f mm: the depth is at "
                          "most the lesion's size",
                          o.cavity_mm[s], o.caries_mm[s]);
            r.Error(value, m);
          }
        });
    if (const YAML::Node& c = n["calculus"]) {
      // calculus: {supra: [L, DL], sub: [MB]}
      if (!c.IsMap()) {
        r.Error(c,
                "'calculus' must map 'supra' and 'sub' to lists of sites, e.g. {supra: "
                "[L], sub: [MB]}");
      } else {
        for (auto it = c.begin(); it != c.end(); ++it) {
          const std::string where = it->first.Scalar();
          if (where != "supra" && where != "sub") {
            r.Error(it->first,
                    "unknown calculus position '" + where + "'" +
                        Suggest(where, {"supra", "sub"}) +
                        " (supra: above the gingival margin, sub: in the sulcus)");
            continue;
          }
          if (!it->second.IsSequence()) {
            r.Error(it->second, "'" + where + "' must be a list of sites, e.g. [MB, DL]");
            continue;
          }
          const YAML::Node sites =
              it->second;  // a copy: the iterator's pair is a temporary
          for (const YAML::Node& site : sites) {
            const std::string code = site.IsScalar() ? site.Scalar() : "";
            const auto at = std::find(kSiteCodes.begin(), kSiteCodes.end(), code);
            if (at == kSiteCodes.end()) {
              r.Error(site, "unknown site '" + code + "'" +
                                Suggest(code, std::vector<std::string>(
                                                  kSiteCodes.begin(), kSiteCodes.end())));
            } else if (o.calculus[at - kSiteCodes.begin()] != 0) {
              r.Error(site, "site " + code + " has calculus named twice");
            } else {
              o.calculus[at - kSiteCodes.begin()] = where == "supra" ? 1 : 2;
            }
          }
        }
      }
    }
  }
  spec->objects.push_back(std::move(o));
}

}  // namespace

void LinkGingivaNeighbours(SceneSpec* spec) {
  auto adjacent = [](int a, int b) {
    const int qa = a / 10, pa = a % 10, qb = b / 10, pb = b % 10;
    if (qa == qb) return std::abs(pa - pb) == 1;
    const bool same_jaw =
        (qa <= 2) == (qb <= 2) && qa >= 1 && qa <= 4 && qb >= 1 && qb <= 4;
    return same_jaw && pa == 1 && pb == 1;
  };
  auto width = [](int fdi) {
    try {
      return Dimensions(FdiTooth::Parse(fdi)).md_crown;
    } catch (const std::invalid_argument&) {
      return 0.0;
    }
  };
  const std::map<int, double> drops = CrestDrops(*spec);
  auto crest = [&](int fdi) {
    const auto it = drops.find(fdi);
    return it == drops.end() ? CrestDropMm(0) : it->second;
  };
  for (ObjectSpec& g : spec->objects) {
    if (g.kind != ObjectSpec::Kind::kGingiva) continue;
    g.gingiva_neighbours.clear();
    g.share_crest_drop_mm = 0;
    if (!spec->gingiva_joined) continue;
    for (const ObjectSpec& n : spec->objects) {
      if (n.kind != ObjectSpec::Kind::kGingiva || !adjacent(g.fdi, n.fdi)) continue;
      const double apart = (n.X_WO.translation() - g.X_WO.translation()).norm();
      if (apart > 0.5 * (width(g.fdi) + width(n.fdi)) + 2.0) continue;
      g.gingiva_neighbours.push_back(
          {n.fdi, n.mirrored, n.X_WO, n.pocket_mm, n.recession_mm, crest(n.fdi)});
    }
    if (!g.gingiva_neighbours.empty()) g.share_crest_drop_mm = crest(g.fdi);
  }
  // Each share's lines, then copied into the links to it (its neighbours'
  // collars are built with the same lines as its own).
  std::map<int, std::array<double, 6>> lines;
  for (ObjectSpec& g : spec->objects)
    if (g.kind == ObjectSpec::Kind::kGingiva)
      lines[g.fdi] = g.site_angle = ShareLineAngles(g);
  for (ObjectSpec& g : spec->objects)
    for (GingivaNeighbourSpec& n : g.gingiva_neighbours) n.site_angle = lines.at(n.fdi);
}

const char* ToString(Tissue t) {
  for (const auto& tn : kTissues) {
    if (tn.tissue == t) return tn.name;
  }
  return "?";
}

Material DefaultMaterial(Tissue t) {
  // Stiffness: hard tissue rigid, soft tissue compliant (approx.); damage limits
  // as the clinical literature gives them (0.5 N tongue and cheek, 0.30 N gingiva).
  switch (t) {
    case Tissue::kGingiva:
      return {0.3, 0.3, 0.30};
    case Tissue::kTongue:
    case Tissue::kCheek:
    case Tissue::kLip:
    case Tissue::kMucosa:
      return {0.1, 0.4, 0.5};
    case Tissue::kPalate:
      return {1.0, 0.3, 1.0};
    case Tissue::kCalculus:
      return {1e9, 0.2, 1e9};  // hard and rough
    default:
      return {};
  }
}

const std::vector<std::string>& MissingReasons() {
  static const std::vector<std::string> reasons = {
      "periodontitis", "caries", "trauma", "orthodontic", "congenital", "unknown"};
  return reasons;
}

namespace {

// `missing: {36: periodontitis, 18: unknown}`: teeth that are gone. Each is an
// FDI number of the permanent dentition that no object of the scene is; the
// teeth lost to periodontitis are the patient's count (or at most it, when the
// patient gives a count that includes teeth lost before this dentition).
void ReadMissing(Reader& r, const YAML::Node& root, SceneSpec* spec) {
  const YAML::Node m = root["missing"];
  if (!m || !r.IsMap(m, "'missing' (e.g. {36: periodontitis, 18: unknown})")) return;
  r.CheckUnique(m, "'missing'");
  int periodontitis = 0;
  for (const auto& kv : m) {
    const YAML::Node key = kv.first;
    int fdi = 0;
    if (!key.IsScalar() || !YAML::convert<int>::decode(key, fdi) ||
        !FdiTooth::Valid(fdi)) {
      r.Error(key, "'missing': '" + (key.IsScalar() ? key.Scalar() : std::string("?")) +
                       "' is not a tooth of the permanent dentition (FDI 11 to 48)");
      continue;
    }
    for (const ObjectSpec& o : spec->objects)
      if (o.kind == ObjectSpec::Kind::kTooth && o.fdi == fdi)
        r.Error(key, "tooth " + std::to_string(fdi) +
                         " is listed as missing and is an object of the scene (line " +
                         std::to_string(o.line) + "); give it in one place");
    const std::string why = kv.second.IsScalar() ? kv.second.Scalar() : "";
    const auto& reasons = MissingReasons();
    if (std::find(reasons.begin(), reasons.end(), why) == reasons.end()) {
      r.Error(kv.second, "tooth " + std::to_string(fdi) + " missing: '" + why +
                             "' is not a reason; expected " + Join(reasons));
      continue;
    }
    periodontitis += why == "periodontitis";
    spec->missing[fdi] = {why, key.Mark().line + 1, key.Mark().column + 1};
  }
  PatientFacts& p = spec->patient;
  if (p.teeth_lost_to_periodontitis == 0) {
    p.teeth_lost_to_periodontitis = periodontitis;
  } else if (p.teeth_lost_to_periodontitis < periodontitis) {
    r.Error(root["patient"]["teeth_lost_to_periodontitis"],
            "'teeth_lost_to_periodontitis' is " +
                std::to_string(p.teeth_lost_to_periodontitis) + " but 'missing' (line " +
                std::to_string(m.Mark().line + 1) + ") lists " +
                std::to_string(periodontitis) + " teeth lost to periodontitis");
  }
}

}  // namespace

SceneSpec LoadSceneSpec(const fs::path& file) {
  Reader r(file, "scene file");
  SceneSpec spec;
  spec.file = file;
  const YAML::Node root = LoadYamlMap(r, "a scene is a map with at least 'objects:'");
  r.CheckKeys(root,
              {"name", "description", "tool", "haptics", "effects", "spheretree", "arch",
               "gingiva", "mouth_open_mm", "patient", "missing", "objects"},
              "the scene");
  if (const YAML::Node p = root["patient"]; p && r.IsMap(p, "'patient'")) {
    PatientFacts& f = spec.patient;
    f.given = true;
    r.CheckKeys(p,
                {"age", "cigarettes_per_day", "hba1c_pct", "teeth_lost_to_periodontitis",
                 "drifting_flaring", "bite_collapse", "opposing_pairs"},
                "'patient'");
    if (p["age"]) f.age_years = r.Integer(p["age"], "age", 1, 120, 40);
    if (p["cigarettes_per_day"])
      f.cigarettes_per_day =
          r.Integer(p["cigarettes_per_day"], "cigarettes_per_day", 0, 200, 0);
    if (p["hba1c_pct"])
      f.hba1c_pct = r.Number(p["hba1c_pct"], "hba1c_pct", 3, 20, 6, "%");
    if (p["teeth_lost_to_periodontitis"])
      f.teeth_lost_to_periodontitis = r.Integer(p["teeth_lost_to_periodontitis"],
                                                "teeth_lost_to_periodontitis", 0, 32, 0);
    if (p["drifting_flaring"])
      f.drifting_flaring = r.Bool(p["drifting_flaring"], "drifting_flaring", false);
    if (p["bite_collapse"])
      f.bite_collapse = r.Bool(p["bite_collapse"], "bite_collapse", false);
    if (p["opposing_pairs"])
      f.opposing_pairs = r.Integer(p["opposing_pairs"], "opposing_pairs", 0, 16, 14);
  }
  if (root["mouth_open_mm"])
    spec.mouth_open_mm = r.Number(root["mouth_open_mm"], "mouth_open_mm", 0, 50, 0, "mm");
  if (const YAML::Node b = root["arch"]) spec.arch = r.Bool(b, "arch", false);
  if (const YAML::Node g = root["gingiva"]) {
    bool v = false;
    if (g.IsScalar() && g.Scalar() == "arch") {
      spec.gingiva = spec.gingiva_joined = true;
    } else if (g.IsScalar() && YAML::convert<bool>::decode(g, v)) {
      spec.gingiva = v;
    } else {
      r.Error(g,
              "'gingiva' must be true (a collar around every tooth), arch (one gingiva "
              "per arch, joined "
              "between neighbouring teeth) or false");
    }
  }
  if (root["name"]) spec.name = r.Text(root["name"], "name");
  if (root["description"]) spec.description = r.Text(root["description"], "description");
  if (const YAML::Node tool = root["tool"]; tool && r.IsMap(tool, "'tool'")) {
    r.CheckKeys(tool, {"probe", "grip_at", "grip_turn_deg"}, "'tool'");
    if (tool["probe"]) {
      spec.probe = r.Text(tool["probe"], "probe");
      if (std::find(kProbes.begin(), kProbes.end(), spec.probe) == kProbes.end()) {
        r.Error(tool["probe"],
                "unknown probe '" + spec.probe + "'" + Suggest(spec.probe, kProbes));
      }
    }
    spec.X_TG = ReadPose(r, tool, "grip_at", "grip_turn_deg");
  }
  if (const YAML::Node h = root["haptics"]; h && r.IsMap(h, "'haptics'"))
    ReadHaptics(r, h, &spec);
  if (const YAML::Node e = root["effects"]) ReadEffects(r, e, &spec);
  const YAML::Node trees = root["spheretree"];
  if (trees) ReadTreeParams(r, trees, "'spheretree'", true, &spec.trees);
  // The collars': `spheretree: gingiva:` over the scene's.
  SphereTreeParams gingiva_trees = spec.trees;
  if (trees && trees.IsMap() && trees["gingiva"]) {
    ReadTreeParams(r, trees["gingiva"], "'spheretree: gingiva'", false, &gingiva_trees);
  }
  const YAML::Node objects = root["objects"];
  if (!objects) {
    r.Error(root, "a scene needs 'objects:', a list of teeth, meshes or solids");
  } else if (!objects.IsSequence()) {
    r.Error(objects, "'objects' must be a list");
  } else {
    std::set<std::string> names;
    const fs::path folder = file.has_parent_path() ? file.parent_path() : fs::path(".");
    for (std::size_t i = 0; i < objects.size(); ++i)
      ReadObject(r, objects[i], folder, static_cast<int>(i), &spec, &names);
  }
  ReadMissing(r, root, &spec);
  FollowAttachmentLoss(&spec);
  if (spec.gingiva) {
    // A collar around every tooth, carrying the tooth's site truth.
    const std::size_t teeth = spec.objects.size();
    for (std::size_t i = 0; i < teeth; ++i) {
      const ObjectSpec& t = spec.objects[i];
      if (t.kind != ObjectSpec::Kind::kTooth) continue;
      ObjectSpec g = t;
      g.kind = ObjectSpec::Kind::kGingiva;
      g.file_index = -1;
      g.name = "gingiva " + std::to_string(t.fdi);
      g.tissue = Tissue::kGingiva;
      g.material = DefaultMaterial(Tissue::kGingiva);
      g.trees = gingiva_trees;
      if (!t.has_sites) g.pocket_mm.fill(2.0);
      try {
        const ToothDimensions d = Dimensions(FdiTooth::Parse(t.fdi));
        for (int s = 0; s < 6; ++s) {
          // (a pocket deeper than the root is reported with the tooth already)
          if (g.pocket_mm[s] < d.longest_root() &&
              g.pocket_mm[s] + g.recession_mm[s] > MaxAttachmentLoss(d)) {
            r.Error(t.line, t.column,
                    "tooth " + std::to_string(t.fdi) +
                        ": pocket plus recession at site " + kSiteCodes[s] +
                        " leaves less than 1 mm of attached root for the gingiva");
          }
        }
      } catch (const std::invalid_argument&) {
        // reported with the tooth
      }
      spec.objects.push_back(std::move(g));
    }
    if (spec.gingiva_joined) LinkGingivaNeighbours(&spec);
  }
  // A deposit object per calculus site, on its tooth (sized in mm, so a few
  // levels of a small tree fit it).
  std::vector<ObjectSpec>
      deposits;  // appended after the loop: the tooth references stay valid
  for (const ObjectSpec& t : spec.objects) {
    if (t.kind != ObjectSpec::Kind::kTooth) continue;
    for (int s = 0; s < 6; ++s) {
      if (t.calculus[s] == 0) continue;
      ObjectSpec c = t;
      c.kind = ObjectSpec::Kind::kCalculus;
      c.file_index = -1;
      c.calculus_site = s;
      c.name = std::string("calculus ") + std::to_string(t.fdi) + " " + kSiteCodes[s];
      c.tissue = Tissue::kCalculus;
      c.material = DefaultMaterial(Tissue::kCalculus);
      c.with_gingiva = spec.gingiva;
      c.trees.levels = 3;
      c.trees.branching = 8;
      c.trees.leaves = 64;
      c.trees.target_error_mm = 0;
      if (!t.has_sites) c.pocket_mm.fill(2.0);
      deposits.push_back(std::move(c));
    }
  }
  for (ObjectSpec& c : deposits) spec.objects.push_back(std::move(c));
  r.ThrowIfErrors();
  return spec;
}

}  // namespace sulcus
