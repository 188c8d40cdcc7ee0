#pragma once
// Scene files: YAML an instructor writes by hand (schema in scenes/README.md).
// Loading parses and validates everything before anything is built, and reports
// every problem at once as `file:line:column: message`. A valid spec compiles into
// the engine's immutable model (meshes, sphere-trees, materials, parameters).

#include <algorithm>
#include <array>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/anatomy/gingiva.h"
#include "core/base/load_error.h"
#include "core/geometry/mesh.h"
#include "core/geometry/transform.h"
#include "core/haptics/effects.h"
#include "core/haptics/engine.h"
#include "core/haptics/scripted_device.h"
#include "core/scene/patient.h"
#include "core/spheretree/builder.h"

namespace sulcus {

enum class Tissue {
  kEnamel,
  kRoot,
  kGingiva,
  kBone,
  kTongue,
  kCheek,
  kPalate,
  kLip,
  kMucosa,
  kMetal,
  kCalculus
};
const char* ToString(Tissue t);

/// What the engine uses of a tissue. Defaults per tissue in DefaultMaterial.
struct Material {
  double stiffness_n_per_mm = 1e9;  // effectively rigid
  double friction = 0.1;
  double damage_limit_n = 1e9;  // contact force above which the tissue is hurt
};
Material DefaultMaterial(Tissue t);

/// The effects a scene may ask for (docs/architecture.md, "One haptic frame", step 6).
enum class Effect {
  kContact,
  kGingivaCompliance,
  kFriction,
  kSurfaceTexture,
  kProbingDepth,
  kBleedingOnProbing,
  kTissueDamage,
  kCariesCatch,
  kCalculus
};
const char* ToString(Effect e);

/// Probing sites in charting order.
inline constexpr std::array<const char*, 6> kSiteCodes = {"MB", "B", "DB",
                                                          "ML", "L", "DL"};
/// Tooth surfaces for caries.
inline constexpr std::array<const char*, 5> kSurfaces = {"mesial", "distal", "buccal",
                                                         "lingual", "occlusal"};

/// A gingiva's neighbour on the arch (LinkGingivaNeighbours): what its share
/// of the gingiva needs of the next tooth's.
struct GingivaNeighbourSpec {
  int fdi = 0;
  bool mirrored = false;
  RigidTransform X_WO;
  std::array<double, 6> pocket_mm{}, recession_mm{};
  double crest_drop_mm = 0;  // its bone crest below its CEJ (as its share's)
  std::array<double, 6> site_angle = kSiteAngles;  // its sites' lines (as its share's)
};

struct ObjectSpec {
  enum class Kind {
    kTooth,
    kMesh,
    kBox,
    kSphere,
    kCylinder,
    kGingiva,
    kAnatomy,
    kCalculus
  } kind = Kind::kTooth;
  std::string name;
  int fdi = 0;               // kTooth, kGingiva (the tooth it surrounds)
  bool mirrored = false;     // kTooth, kGingiva placed on the arch (arch.h)
  std::string anatomy;       // kAnatomy: tongue, palate, cheek_left, ... (soft_tissue.h)
  double mouth_open_mm = 0;  // the scene's: upper teeth and tissues raised by this
  std::map<int, double> crest_drop_mm;  // kAnatomy jaws: the bone crest below each
                                        // tooth's CEJ (soft_tissue.h)
  std::map<int, std::map<std::string, int>>
      furcation_of;  // kAnatomy jaws: each tooth's furcation classes (soft_tissue.h)
  std::filesystem::path mesh;           // kMesh, resolved against the scene's folder
  Vector3 size = Vector3::Zero();       // kBox, mm
  double radius_mm = 0, height_mm = 0;  // kSphere, kCylinder
  RigidTransform X_WO;
  SphereTreeParams trees;  // the scene's, or the object's own `spheretree`
  bool own_trees = false;  // the object named its own `spheretree`
  Tissue tissue = Tissue::kEnamel;
  Material material;
  // Clinical truth per site (teeth): pocket depth, recession, bleeding on probing.
  bool has_sites = false;
  std::array<double, 6> pocket_mm{};
  std::array<double, 6> recession_mm{};
  std::array<bool, 6> bleeding{};
  std::array<bool, 6> inflamed{};  // gingiva inflamed at the site
  // Caries by surface (mesial, distal, buccal, lingual, occlusal): lesion size in mm, 0
  // for none.
  std::array<double, 5> caries_mm{};
  // Cavitated lesions by surface: the cavity's depth in mm at its centre, 0 for
  // a lesion whose surface is intact (every cavity is in a lesion of caries_mm).
  std::array<double, 5> cavity_mm{};
  // Calculus by site: 0 none, 1 supragingival, 2 subgingival. The scene adds one
  // kCalculus object per deposit (its `calculus_site` the site, `fdi` the tooth).
  std::array<int, 6> calculus{};
  // Furcation involvement by entrance (Hamp class 0-3): lower molars B, L;
  // upper molars B, M, D; the upper first premolar M, D (FurcationEntrances).
  std::map<std::string, int> furcation;
  int mobility = 0;  // Miller 0 to 3 (what the examiner charts; not felt)
  // kGingiva: the neighbouring teeth's gingiva it joins (empty: a collar alone).
  std::vector<GingivaNeighbourSpec> gingiva_neighbours;
  // kGingiva shares (gingiva_neighbours not empty): the bone crest below the
  // tooth's CEJ, as the jaw has it; the share reaches 1 mm past it.
  double share_crest_drop_mm = 0;
  // kGingiva: its sites' lines in the tooth frame (GingivaParams::site_angle);
  // a share's interdental lines moved clear of its cuts (LinkGingivaNeighbours).
  std::array<double, 6> site_angle = kSiteAngles;
  int calculus_site = -1;
  bool with_gingiva = false;
  // kAnatomy: a soft-tissue lesion (soft_tissue.h), empty kind for none.
  std::string lesion_kind, lesion_region;
  double lesion_mm = 0;      // radius         // kCalculus: the scene has gingiva (the
                             // deposit sits by its margin)
  int line = 0, column = 0;  // where the object is declared
  // Its place in the file's `objects` list (0-based); -1 for what the scene adds
  // (the gingival collars, which carry their tooth's `fdi`). The compiled scene
  // reorders objects; events and reports name them by name, FDI or this.
  int file_index = -1;
};

struct SceneSpec {
  std::filesystem::path file;
  std::string name, description;
  std::string probe = "williams";
  RigidTransform X_TG;  // grip frame in the tool frame
  EngineParams haptics;
  double rate_hz = 1000;
  // The surface the tool feels: leaf spheres clipped by planes fitted to the
  // mesh (true), or the leaf spheres alone (`haptics: {surface: spheres}`).
  bool leaf_planes = true;
  std::vector<Effect> effects = {Effect::kContact};
  bool HasEffect(Effect e) const {
    return std::find(effects.begin(), effects.end(), e) != effects.end();
  }
  SphereTreeParams
      trees;          // the scene's `spheretree`: every object's unless it names its own
  bool arch = false;  // teeth without `at` stand on the dental arches
  bool gingiva = false;  // a gingival collar around every tooth, with its sites' truth
  // `gingiva: arch`: the collars joined into one gingiva per arch (papillae,
  // col; LinkGingivaNeighbours) instead of a collar each.
  bool gingiva_joined = false;
  double mouth_open_mm =
      0;  // raises the upper arch (and palate) so instruments fit between the arches
  PatientFacts patient;  // `patient:` (stage IV and the grade need it)
  // `missing:`: teeth of the dentition that are gone, each with why it was lost;
  // their place in the arch stays empty (the others keep theirs).
  std::map<int, MissingTooth> missing;
  std::vector<ObjectSpec> objects;
};

/// Why a tooth is missing, as a chart records it.
const std::vector<std::string>& MissingReasons();

/// Each tooth's bone crest below its CEJ (mm, along its axis) where the scene's
/// pockets, recession or furcation put it deeper than health (CrestDropMm, and
/// below the furcation by its class); teeth in health are not listed.
std::map<int, double> CrestDrops(const SceneSpec& spec);

/// Radiographic bone loss at a tooth, as a radiograph shows it: how far its
/// bone crest (CrestDrops) lies below a healthy crest, as a share of the root
/// below that crest, in % (0 in health, 100 at the apex); empty for a number
/// that is not a tooth of the scene.
std::optional<double> BoneLossPct(const SceneSpec& spec, int fdi);

/// The largest object a scene may hold, in mm (a mouth is about 60 mm across).
inline constexpr double kMaxSceneObjectMm = 300;

/// Parses and validates a scene file. Throws LoadError listing every error
/// (unknown keys with a suggestion, wrong types, out-of-range values, missing mesh
/// files, non-existent FDI numbers, paths leaving the scene's folder, unknown
/// effects, YAML syntax errors).
SceneSpec LoadSceneSpec(const std::filesystem::path& file);

/// The furcation entrances a tooth has: {"B", "L"} for lower molars, {"B", "M",
/// "D"} for upper molars, {"M", "D"} for the upper first premolar, none else.
std::vector<std::string> FurcationEntrances(int fdi);

/// Sets each jaw's bone crest (`crest_drop_mm`) from the teeth's pockets and
/// recession, as they are now, and below the furcation where a tooth's
/// furcation is involved (class 1: 0.5 mm below the entrance, 2: 1.5 mm,
/// 3: 3 mm), and gives each jaw the teeth's furcation classes
/// (`furcation_of`: the bone between the roots as each class leaves it,
/// MakeSoftTissue): LoadSceneSpec and CompileScene call it, so a
/// scene whose pockets were changed after loading (a generated case) gets the
/// bone that goes with them. A jaw whose crest has dropped below a tooth's
/// furcation (so that the bone between the roots is modelled, whole or with
/// its class's defect) and that has no `spheretree` of its own gets at least
/// kFurcationJawLeaves leaves (5 levels, spent on the min-max cover only and
/// tightened kFurcationJawTightenPasses times), so that a probe feels that
/// bone as it is.
void FollowAttachmentLoss(SceneSpec* spec);
inline constexpr int kFurcationJawLeaves = 2048;
inline constexpr int kFurcationJawTightenPasses = 1;

/// For a scene with `gingiva: arch` (none else), joins the gingiva of
/// neighbouring teeth into one per arch: each gingiva
/// object's `gingiva_neighbours` are the teeth next to it in the arch (same
/// quadrant and next position, or the two central incisors across the
/// midline) whose gingiva the scene has and that stand within 2 mm of touching
/// (a hand-placed row of teeth apart keeps a collar each), and each share's
/// bone crest (`share_crest_drop_mm`, the jaw's, from FollowAttachmentLoss's
/// rule), and each share's sites' lines (`site_angle`, from
/// LineAnglesClearOfCuts: an interdental line that the arch crowds past the
/// cut toward the neighbour is moved round toward its mid site), copied into
/// its neighbours' links. LoadSceneSpec and CompileScene call it, after
/// FollowAttachmentLoss.
void LinkGingivaNeighbours(SceneSpec* spec);

/// An object's mesh in its own frame (before X_WO): a generated tooth, gingiva
/// or soft tissue, the mesh file, or the solid. Throws MeshError for an
/// unreadable mesh file.
/// With `normals`, also the normals to draw it with, per vertex (a share of an
/// arch's gingiva has them: GingivaModel::normals; other objects none, and
/// `normals` is left empty).
/// `seen`: for a share of an arch's gingiva, the surface the eye sees instead
/// of the one the probe feels (GingivaSurface in core/anatomy/gingiva.h);
/// other objects are the same either way.
/// `caps`: for a share, per face 1 on its flat cap toward a neighbour
/// (GingivaModel::caps); empty otherwise.
TriangleMesh MakeObjectMesh(const ObjectSpec& object,
                            std::vector<Vector3>* normals = nullptr, bool seen = false,
                            std::vector<char>* caps = nullptr);

/// The same, with generated meshes cached in `cache_dir`/meshes keyed by a hash
/// of what generates them (a corrupt file is regenerated, never trusted).
TriangleMesh MakeObjectMeshCached(const ObjectSpec& object,
                                  const std::filesystem::path& cache_dir,
                                  std::vector<Vector3>* normals = nullptr,
                                  bool seen = false, std::vector<char>* caps = nullptr);

/// What the window draws for the shares of an arch's gingiva: per object of
/// the compiled scene, the seen gingiva's mesh and normals (the sulcus closed
/// round the tooth, the papillae full: GingivaSurface::kSeen), empty for every
/// other object, which is drawn as the engine has it. A share's mirrored twin
/// is its mesh mirrored, as in CompileScene.
struct SeenGingiva {
  std::vector<TriangleMesh> meshes;
  std::vector<std::vector<Vector3>> normals;
  // Per object, per face of its seen mesh: 1 for a face of the flat cap on
  // the cut toward a neighbour, where two shares meet face to face (drawn
  // only while the gingiva is opaque: through translucent gingiva the two
  // coinciding caps would show as a dark plane between the teeth).
  std::vector<std::vector<char>> caps;
};

/// A compiled scene: everything the engine needs, immutable after construction.
struct CompiledScene {
  SceneSpec spec;
  std::vector<TriangleMesh> meshes;  // per object, in the object frame
  // Per object: per vertex of its mesh, the normal to draw it with (object
  // frame; empty: from its faces). Shares of an arch's gingiva have them.
  std::vector<std::vector<Vector3>> normals;
  std::vector<SphereTree> trees;  // per object
  std::vector<LeafPlanes>
      planes;              // per object: its leaves' clipping planes (empty: spheres)
  TriangleMesh tool_mesh;  // the probe's collision part (anatomy/probe.h), tip frame
  SphereTree tool_tree;
  std::unique_ptr<EngineModel>
      model;             // the hard objects: spec.objects[0 .. effects.soft_first)
  EffectsModel effects;  // what the scene's effects need (soft objects last)
  // The gingiva as the window draws it, when CompileScene was asked for it
  // (CompileOptions::seen_gingiva); else empty.
  SeenGingiva seen;
  // Wall time of the two stages of CompileScene, each on all cores (cache hits
  // included); the trees' stage includes the seen gingiva when it was asked for.
  double mesh_seconds = 0, tree_seconds = 0;
  // Per object: whether its sphere-tree was built (not in the cache), and the
  // seconds it took (built or read).
  std::vector<double> object_tree_seconds;
  std::vector<char> tree_built;
};

/// Stiffness of soft gingiva and of the pocket floor under gingiva_compliance (N/mm).
inline constexpr double kGingivaWallStiffness = 0.05, kPocketFloorStiffness = 2.0;

struct CompileOptions {
  /// Also build CompiledScene::seen, in the same workers as the trees (after
  /// them, so that the shares' quick meshes fill the cores a long tree leaves
  /// idle): what the window draws.
  bool seen_gingiva = false;
};

/// Builds meshes and sphere-trees (through the cache in `cache_dir`) and the
/// engine model. Progress is reported per object.
std::unique_ptr<CompiledScene> CompileScene(const SceneSpec& spec,
                                            const std::filesystem::path& cache_dir,
                                            const BuildProgress& progress = {},
                                            const CompileOptions& options = {});

/// Where a named scripted trajectory works in a compiled scene: on object
/// `object` (-1: the first tooth, else the first object). For teeth, `insert`
/// starts at the buccal surface at the CEJ with the working end along the long
/// axis, and the others at the top of the crown; for other objects, their top.
ScriptTarget FindScriptTarget(const CompiledScene& scene, const std::string& script,
                              int object = -1);

/// The caries lesions of the scene's teeth in the world (object: the tooth's
/// index), where caries_catch feels them and lessons score pressing them.
std::vector<CariesLesion> SceneCariesLesions(const SceneSpec& spec);

/// An object's name, or "object N" for an index the scene does not have.
std::string ObjectName(const SceneSpec& spec, int object);

/// One line for a haptic event, in words a student reads, with the scene's
/// names: "touching tooth 46", "force above 1.01 N", "reading 3.8 mm at 46 B
/// (0.22 N, 4 deg)", "bleeding at 46 MB".
std::string DescribeEvent(const SceneSpec& spec, const HapticEvent& e);

/// FNV-1a of a file's bytes (recordings name the scene they were made on).
std::uint64_t HashFile(const std::filesystem::path& file);

}  // namespace sulcus
