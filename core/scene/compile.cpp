#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <exception>
#include <fstream>
#include <iterator>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

#include "core/anatomy/arch.h"
#include "core/anatomy/findings.h"
#include "core/anatomy/gingiva.h"
#include "core/anatomy/probe.h"
#include "core/anatomy/soft_tissue.h"
#include "core/anatomy/tooth.h"
#include "core/geometry/mesh_io.h"
#include "core/geometry/primitives.h"
#include "core/scene/object_gingiva.h"
#include "core/scene/scene.h"
#include "core/spheretree/cache.h"
#include "core/spheretree/tree_files.h"

namespace sulcus {

namespace {

// A tooth's gingiva parameters: its sites and, for a share (crest_drop_mm >
// 0), the bone crest it reaches, along the world's vertical toward the crown
// in its (unmirrored) tooth frame placed at X_WO.
GingivaParams GingivaParamsOf(int fdi, bool mirrored, const RigidTransform& X_WO,
                              const std::array<double, 6>& pocket_mm,
                              const std::array<double, 6>& recession_mm,
                              double crest_drop_mm) {
  GingivaParams p;
  p.pocket_mm = pocket_mm;
  p.recession_mm = recession_mm;
  if (crest_drop_mm > 0) {
    const Vector3 v(0, 0, FdiTooth::Parse(fdi).upper() ? -1.0 : 1.0);
    p.crest_drop_mm = crest_drop_mm;
    p.crest_up = (Vector3(mirrored ? -1 : 1, 1, 1).asDiagonal() *
                  (X_WO.rotation().transpose() * v))
                     .normalized();
  }
  return p;
}

}  // namespace

GingivaParams GingivaOf(const ObjectSpec& o) {
  return GingivaParamsOf(o.fdi, o.mirrored, o.X_WO, o.pocket_mm, o.recession_mm,
                         o.share_crest_drop_mm);
}

namespace {

// A share's neighbour `s` as its generator sees it: its collar's parameters,
// and the map from the share's tooth's (unmirrored) frame to the neighbour's.
GingivaParams NeighbourParams(const ObjectSpec& o, const GingivaNeighbourSpec& s) {
  return GingivaParamsOf(s.fdi, s.mirrored, s.X_WO, s.pocket_mm, s.recession_mm,
                         o.share_crest_drop_mm > 0 ? s.crest_drop_mm : 0);
}

void NeighbourFrame(const ObjectSpec& o, const GingivaNeighbourSpec& s, Matrix3* A,
                    Vector3* b) {
  const Matrix3 mirror_self = Vector3(o.mirrored ? -1 : 1, 1, 1).asDiagonal();
  const Matrix3 mirror = Vector3(s.mirrored ? -1 : 1, 1, 1).asDiagonal();
  const Matrix3 Rt = s.X_WO.rotation().transpose();
  *A = mirror * Rt * o.X_WO.rotation() * mirror_self;
  *b = mirror * Rt * (o.X_WO.translation() - s.X_WO.translation());
}

// A share of the arch's gingiva's neighbours: their teeth and collars, and
// the map from this tooth's (unmirrored) frame to each of theirs.
struct ShareNeighbours {
  explicit ShareNeighbours(const ObjectSpec& o) {
    const std::size_t n = o.gingiva_neighbours.size();
    teeth.reserve(n);
    collars.reserve(n);
    next.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const GingivaNeighbourSpec& s = o.gingiva_neighbours[i];
      teeth.push_back(GenerateTooth(s.fdi));
      collars.push_back(GenerateGingiva(teeth.back(), NeighbourParams(o, s)));
      NeighbourFrame(o, s, &next[i].A, &next[i].b);
      next[i].tooth = &teeth[i];
      next[i].gingiva = &collars[i];
    }
  }
  ShareNeighbours(const ShareNeighbours&) = delete;
  ShareNeighbours& operator=(const ShareNeighbours&) = delete;
  std::vector<ToothModel> teeth;
  std::vector<GingivaModel> collars;
  std::vector<GingivaNeighbour> next;
};

// A generated tooth's shape depends on its arch and position only: 11 and 21
// are one shape (21's placed mirrored).
std::string ToothShapeKey(int fdi) {
  const FdiTooth t = FdiTooth::Parse(fdi);
  return std::string(t.upper() ? "upper " : "lower ") + std::to_string(t.position);
}

// A placement's number to 1e-9 mm (or of a unit vector): the two sides of the
// arch are placed by separate arithmetic and differ in the last bits.
double Placed(double v) { return std::round(v * 1e9) * 1e-9 + 0.0; }  // (+ 0.0: no -0)

// What generates an object's mesh, as text; empty for meshes not generated.
std::string GeneratorKey(const ObjectSpec& o) {
  std::ostringstream k;
  k.precision(17);
  k << "sulcus-generated-mesh v4|tooth shape " << kToothShapeVersion << '|';
  switch (o.kind) {
    case ObjectSpec::Kind::kTooth:
      k << "tooth|" << o.fdi << '|' << o.mirrored;
      for (int s = 0; s < 5; ++s)
        if (o.cavity_mm[s] > 0)
          k << "|cavity " << s << ':' << o.caries_mm[s] << ':' << o.cavity_mm[s];
      break;
    case ObjectSpec::Kind::kGingiva: {
      // What the generator sees, in the tooth's unmirrored frame (the cache
      // holds the share unmirrored): a share and its mirrored twin on the
      // other side of the arch have one key, and one build.
      const GingivaParams g = GingivaOf(o);
      k << "gingiva " << kGingivaShareVersion << "|unmirrored|" << ToothShapeKey(o.fdi);
      for (int i = 0; i < 6; ++i) k << '|' << g.pocket_mm[i] << '|' << g.recession_mm[i];
      if (g.crest_drop_mm > 0)
        k << "|crest " << g.crest_drop_mm << '|' << Placed(g.crest_up.x()) << '|'
          << Placed(g.crest_up.y()) << '|' << Placed(g.crest_up.z());
      std::vector<std::string> next;
      for (const GingivaNeighbourSpec& n : o.gingiva_neighbours) {
        std::ostringstream e;
        e.precision(17);
        const GingivaParams p = NeighbourParams(o, n);
        Matrix3 A;
        Vector3 b;
        NeighbourFrame(o, n, &A, &b);
        e << "|next " << ToothShapeKey(n.fdi);
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) e << '|' << Placed(A(r, c));
        for (int r = 0; r < 3; ++r) e << '|' << Placed(b[r]);
        for (int i = 0; i < 6; ++i)
          e << '|' << p.pocket_mm[i] << '|' << p.recession_mm[i];
        e << '|' << p.crest_drop_mm << '|' << Placed(p.crest_up.x()) << '|'
          << Placed(p.crest_up.y()) << '|' << Placed(p.crest_up.z());
        next.push_back(e.str());
      }
      std::sort(next.begin(),
                next.end());  // (the order of the neighbours does not shape the share)
      for (const std::string& e : next) k << e;
      break;
    }
    case ObjectSpec::Kind::kCalculus:
      k << "calculus " << kCalculusVersion << '|' << o.fdi << '|' << o.mirrored << '|'
        << o.calculus_site << '|' << o.calculus[o.calculus_site] << '|' << o.with_gingiva;
      for (int i = 0; i < 6; ++i) k << '|' << o.pocket_mm[i] << '|' << o.recession_mm[i];
      break;
    case ObjectSpec::Kind::kAnatomy:
      k << "anatomy " << kSoftTissueVersion << '|' << o.anatomy << '|' << o.mouth_open_mm;
      for (const auto& [fdi, drop] : o.crest_drop_mm) k << '|' << fdi << ':' << drop;
      for (const auto& [fdi, classes] : o.furcation_of)
        for (const auto& [entrance, hamp] : classes)
          k << '|' << fdi << entrance << ':' << hamp;
      break;
    default:
      return {};
  }
  return k.str();
}

constexpr char kMeshMagic[8] = {'S', 'U', 'L', 'M', 'E', 'S', 'H', '1'};

std::optional<TriangleMesh> ReadCachedMesh(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  char magic[8];
  std::uint64_t nv = 0, nf = 0, checksum = 0;
  in.read(magic, 8);
  in.read(reinterpret_cast<char*>(&nv), 8);
  in.read(reinterpret_cast<char*>(&nf), 8);
  if (!in || std::memcmp(magic, kMeshMagic, 8) != 0 || nv > (1u << 26) || nf > (1u << 27))
    return std::nullopt;
  std::vector<Vector3> v(nv);
  std::vector<TriangleMesh::Face> f(nf);
  in.read(reinterpret_cast<char*>(v.data()),
          static_cast<std::streamsize>(nv * sizeof(Vector3)));
  in.read(reinterpret_cast<char*>(f.data()),
          static_cast<std::streamsize>(nf * sizeof(TriangleMesh::Face)));
  in.read(reinterpret_cast<char*>(&checksum), 8);
  if (!in) return std::nullopt;
  const std::uint64_t sum = Fnv1a(f.data(), nf * sizeof(TriangleMesh::Face),
                                  Fnv1a(v.data(), nv * sizeof(Vector3)));
  if (sum != checksum) return std::nullopt;
  for (const auto& face : f)
    for (int i : face)
      if (i < 0 || static_cast<std::uint64_t>(i) >= nv) return std::nullopt;
  return TriangleMesh(std::move(v), std::move(f));
}

// A per-vertex or per-face array as the cache holds it (a mesh's normals, a
// share's cap faces): the count, the items, their checksum. Empty when the
// file is missing, or does not hold `expected` items, or is corrupt.
template <typename T>
std::vector<T> ReadCachedArray(const std::filesystem::path& file, std::size_t expected) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return {};
  std::uint64_t n = 0, checksum = 0;
  in.read(reinterpret_cast<char*>(&n), 8);
  if (!in || n != expected) return {};
  std::vector<T> v(n);
  in.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(n * sizeof(T)));
  in.read(reinterpret_cast<char*>(&checksum), 8);
  if (!in || Fnv1a(v.data(), n * sizeof(T)) != checksum) return {};
  return v;
}

// Writes a cache file under a name of this process and thread, then renames it
// into place: a reader never sees half a file.
template <typename Write>
void WriteCacheFile(const std::filesystem::path& file, Write write) {
  std::error_code ec;
  std::filesystem::create_directories(file.parent_path(), ec);
  const std::filesystem::path tmp =
      file.string() + ".tmp" + std::to_string(::getpid()) + "-" +
      std::to_string(std::hash<std::thread::id>{}(std::this_thread::get_id()));
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) return;  // an unwritable cache only costs time
    write(out);
  }
  std::filesystem::rename(tmp, file, ec);
}

template <typename T>
void WriteCachedArray(const std::vector<T>& items, const std::filesystem::path& file) {
  WriteCacheFile(file, [&](std::ofstream& out) {
    const std::uint64_t n = items.size();
    const std::uint64_t sum = Fnv1a(items.data(), n * sizeof(T));
    out.write(reinterpret_cast<const char*>(&n), 8);
    out.write(reinterpret_cast<const char*>(items.data()),
              static_cast<std::streamsize>(n * sizeof(T)));
    out.write(reinterpret_cast<const char*>(&sum), 8);
  });
}

void WriteCachedMesh(const TriangleMesh& m, const std::filesystem::path& file) {
  WriteCacheFile(file, [&](std::ofstream& out) {
    const std::uint64_t nv = m.num_vertices(), nf = m.num_faces();
    out.write(kMeshMagic, 8);
    out.write(reinterpret_cast<const char*>(&nv), 8);
    out.write(reinterpret_cast<const char*>(&nf), 8);
    out.write(reinterpret_cast<const char*>(m.vertices().data()),
              static_cast<std::streamsize>(nv * sizeof(Vector3)));
    out.write(reinterpret_cast<const char*>(m.faces().data()),
              static_cast<std::streamsize>(nf * sizeof(TriangleMesh::Face)));
    const std::uint64_t sum = Fnv1a(m.faces().data(), nf * sizeof(TriangleMesh::Face),
                                    Fnv1a(m.vertices().data(), nv * sizeof(Vector3)));
    out.write(reinterpret_cast<const char*>(&sum), 8);
  });
}

}  // namespace

std::vector<CariesLesion> SceneCariesLesions(const SceneSpec& spec) {
  std::vector<CariesLesion> out;
  const auto& objs = spec.objects;
  for (int i = 0; i < static_cast<int>(objs.size()); ++i) {
    const ObjectSpec& o = objs[i];
    if (o.kind != ObjectSpec::Kind::kTooth) continue;
    std::optional<ToothModel> tooth;
    for (int s = 0; s < 5; ++s) {
      if (o.caries_mm[s] <= 0) continue;
      if (!tooth) tooth = GenerateTooth(o.fdi);
      const SurfacePoint p = CariesSpot(*tooth, static_cast<ToothSurface>(s));
      out.push_back({i, o.X_WO * ArchMirror(o.mirrored, p.point),
                     o.X_WO.rotation() * ArchMirror(o.mirrored, p.normal), o.caries_mm[s],
                     s});
    }
  }
  return out;
}

namespace {

// What the scene's effects need: damage limits, probing sites, soft objects.
void BuildEffectsModel(CompiledScene* scene, int soft_first,
                       const std::vector<CollisionWorld::Object>& soft_objects) {
  EffectsModel& m = scene->effects;
  const auto& objs = scene->spec.objects;
  const SceneSpec& spec = scene->spec;
  m.on.gingiva_compliance = spec.HasEffect(Effect::kGingivaCompliance);
  m.on.probing_depth = spec.HasEffect(Effect::kProbingDepth);
  m.on.bleeding_on_probing = spec.HasEffect(Effect::kBleedingOnProbing);
  m.on.tissue_damage = spec.HasEffect(Effect::kTissueDamage);
  m.on.caries_catch = spec.HasEffect(Effect::kCariesCatch);
  m.on.surface_texture = spec.HasEffect(Effect::kSurfaceTexture);
  m.on.calculus = spec.HasEffect(Effect::kCalculus);
  if (m.on.calculus)
    for (int i = 0; i < static_cast<int>(objs.size()); ++i)
      m.deposits.push_back(objs[i].kind == ObjectSpec::Kind::kCalculus && i < soft_first
                               ? EffectsModel::Deposit{objs[i].fdi, objs[i].calculus_site}
                               : EffectsModel::Deposit{});
  if (m.on.surface_texture) {
    for (int i = 0; i < static_cast<int>(objs.size()); ++i) {
      const ObjectSpec& o = objs[i];
      m.texture_kind.push_back(i >= soft_first                      ? TextureKind::kNone
                               : o.kind == ObjectSpec::Kind::kTooth ? TextureKind::kTooth
                               : o.kind == ObjectSpec::Kind::kCalculus
                                   ? TextureKind::kCalculus
                                   : TextureKind::kNone);
      // Mirrored teeth keep z: the tooth frame's height is the same either way.
      m.X_OW.push_back(o.X_WO.inverse());
    }
  }
  if (m.on.caries_catch)
    for (const CariesLesion& c : SceneCariesLesions(spec))
      if (c.tooth < soft_first) m.lesions.push_back(c);
  for (const ObjectSpec& o : objs) m.damage_limit_n.push_back(o.material.damage_limit_n);
  const SphereTree& tool = scene->tool_tree;
  m.tool_working_end.assign(tool.size(), 0);
  for (std::size_t i = 0; i < tool.size(); ++i)
    m.tool_working_end[i] =
        tool.IsLeaf(i) && tool.center(i).norm() <= EffectsModel::kWorkingEndMm;
  m.soft_first = soft_first;
  const bool sites = spec.gingiva && (m.on.probing_depth || m.on.bleeding_on_probing);
  // Every collar's model, once: a lone collar's leaves that reach into a
  // neighbour's sulcus are left out of the compliance (lone collars are rings
  // that may overlap between teeth; the sulcus belongs to its own tooth, so a
  // probe walking around a tooth meets that tooth's floor, not the neighbour's).
  std::vector<std::optional<GingivaModel>> models(objs.size());
  for (int i = 0; i < static_cast<int>(objs.size()); ++i)
    if (objs[i].kind == ObjectSpec::Kind::kGingiva && (sites || i >= soft_first))
      models[i] = GenerateGingiva(GenerateTooth(objs[i].fdi), GingivaOf(objs[i]));
  auto in_sulcus = [&](int j, const Vector3& c_W, double r) {
    const GingivaModel& g = *models[j];
    const Vector3 c = ArchMirror(objs[j].mirrored, objs[j].X_WO.inverse() * c_W);
    const int k = g.SegmentAt(std::atan2(c.y(), c.x()));
    const double r_in = g.sulcus_r[k] + 0.5 * GingivaParams{}.gap_mm;
    return std::hypot(c.x(), c.y()) - r < r_in && c.z() - r < g.margin_z[k] &&
           c.z() + r > g.floor_z[k];
  };
  // Under a neighbour's part of the col: within its sulcus' outer wall and
  // at or below its floor (a share of the arch's gingiva meets the
  // shallower tooth's floor under a contact, which is firm as its own is).
  auto under_floor = [&](int j, const Vector3& c_W, double r) {
    const GingivaModel& g = *models[j];
    const Vector3 c = ArchMirror(objs[j].mirrored, objs[j].X_WO.inverse() * c_W);
    const int k = g.SegmentAt(std::atan2(c.y(), c.x()));
    return std::hypot(c.x(), c.y()) - r < g.wall_r[k] && c.z() + r <= g.floor_z[k] + 0.25;
  };
  // In a neighbour's sulcus and not in its own (where the two sulci meet, at
  // the col, both floors stay).
  auto in_other_sulcus = [&](int self, const Vector3& c_W, double r) {
    if (in_sulcus(self, c_W, r)) return false;
    for (int j = 0; j < static_cast<int>(objs.size()); ++j)
      if (j != self && models[j] && in_sulcus(j, c_W, r)) return true;
    return false;
  };
  for (int i = 0; i < static_cast<int>(objs.size()); ++i) {
    const ObjectSpec& o = objs[i];
    if (o.kind != ObjectSpec::Kind::kGingiva) continue;
    const bool soft = i >= soft_first;
    if (!sites && !soft) continue;
    const GingivaModel& g = *models[i];
    int tooth = -1;
    for (int t = 0; t < static_cast<int>(objs.size()); ++t)
      if (objs[t].kind == ObjectSpec::Kind::kTooth && objs[t].fdi == o.fdi) tooth = t;
    if (sites) {
      std::vector<GingivaShareField::CutPlane> cuts;
      if (!o.gingiva_neighbours.empty()) {
        const ShareNeighbours nb(o);
        cuts = GingivaShareField(GenerateTooth(o.fdi), g, nb.next).cuts();
      }
      for (int s = 0; s < 6; ++s) {
        ProbingSite site;
        site.tooth = tooth;
        site.fdi = o.fdi;
        site.site = s;
        site.axis_W = (tooth >= 0 ? objs[tooth].X_WO : o.X_WO).rotation().col(2);
        site.origin_W = o.X_WO.translation();
        site.sulcus_r_mm = std::hypot(g.margin[s].x(), g.margin[s].y());
        for (const GingivaShareField::CutPlane& c : cuts) {
          if (site.num_cuts == static_cast<int>(site.cut_q_W.size())) break;
          site.cut_q_W[site.num_cuts] = o.X_WO * ArchMirror(o.mirrored, c.q);
          site.cut_n_W[site.num_cuts] =
              o.X_WO.rotation() * ArchMirror(o.mirrored, c.normal);
          ++site.num_cuts;
        }
        site.margin_W = o.X_WO * ArchMirror(o.mirrored, g.margin[s]);
        site.floor_W = o.X_WO * ArchMirror(o.mirrored, g.floor[s]);
        site.pocket_mm = o.pocket_mm[s];
        site.bleeding = o.bleeding[s];
        m.sites.push_back(site);
      }
    }
    if (soft) {
      // Leaves near or below the pocket floor are firm (the attachment), the rest soft.
      const SphereTree& t = scene->trees[i];
      std::vector<int> neighbours;
      for (const GingivaNeighbourSpec& nb : o.gingiva_neighbours)
        for (int j = 0; j < static_cast<int>(objs.size()); ++j)
          if (objs[j].kind == ObjectSpec::Kind::kGingiva && objs[j].fdi == nb.fdi &&
              models[j])
            neighbours.push_back(j);
      std::vector<float> k(t.size(), static_cast<float>(kGingivaWallStiffness));
      for (std::size_t n = 0; n < t.size(); ++n) {
        const Vector3 c = ArchMirror(o.mirrored, t.center(n));
        const double r = t.r[n];
        if (c.z() + r <= g.FloorAt(std::atan2(c.y(), c.x())) + 0.25)
          k[n] = static_cast<float>(kPocketFloorStiffness);
        for (const int j : neighbours)
          if (under_floor(j, o.X_WO * t.center(n), r))
            k[n] = static_cast<float>(kPocketFloorStiffness);
        // (a share of the arch's gingiva has every neighbour's sulcus carved out already)
        if (o.gingiva_neighbours.empty() && in_other_sulcus(i, o.X_WO * t.center(n), r))
          k[n] = 0;
      }
      m.soft_leaf_stiffness.push_back(std::move(k));
    }
  }
  if (!soft_objects.empty())
    m.soft_world = std::make_unique<CollisionWorld>(scene->tool_tree, soft_objects);
}

}  // namespace

TriangleMesh MakeObjectMeshCached(const ObjectSpec& o,
                                  const std::filesystem::path& cache_dir,
                                  std::vector<Vector3>* normals, bool seen,
                                  std::vector<char>* caps) {
  seen = seen && o.kind == ObjectSpec::Kind::kGingiva && !o.gingiva_neighbours.empty();
  std::string key = GeneratorKey(o);
  if (key.empty() || cache_dir.empty()) return MakeObjectMesh(o, normals, seen, caps);
  if (seen)
    key += "|seen " + std::to_string(kSeenGingivaVersion) + "|" +
           std::to_string(kSeenWallMm);
  // A gingiva is cached unmirrored (its key is in that frame) and mirrored here.
  const bool mirror_here = o.kind == ObjectSpec::Kind::kGingiva && o.mirrored;
  char name[32];
  std::snprintf(name, sizeof name, "%016llx.mesh",
                static_cast<unsigned long long>(Fnv1a(key.data(), key.size())));
  const std::filesystem::path file = cache_dir / "meshes" / name;
  std::filesystem::path normals_file = file, caps_file = file;
  normals_file.replace_extension(".normals");
  caps_file.replace_extension(".caps");
  if (auto cached = ReadCachedMesh(file)) {
    // (no normals file, or one that does not fit: drawn from the faces; no
    // caps file: none marked)
    if (normals)
      *normals = ArchMirror(
          mirror_here, ReadCachedArray<Vector3>(normals_file, cached->num_vertices()));
    if (caps) *caps = ReadCachedArray<char>(caps_file, cached->num_faces());
    return ArchMirror(mirror_here, std::move(*cached));
  }
  std::vector<Vector3> made_normals;
  std::vector<char> made_caps;
  TriangleMesh m = MakeObjectMesh(o, &made_normals, seen, &made_caps);
  // (the normals and caps first: a reader that finds the mesh finds them)
  if (!made_normals.empty())
    WriteCachedArray(ArchMirror(mirror_here, made_normals), normals_file);
  if (!made_caps.empty()) WriteCachedArray(made_caps, caps_file);
  if (caps) *caps = made_caps;
  WriteCachedMesh(ArchMirror(mirror_here, m), file);
  if (normals) *normals = std::move(made_normals);
  return m;
}

TriangleMesh MakeObjectMesh(const ObjectSpec& o, std::vector<Vector3>* normals, bool seen,
                            std::vector<char>* caps) {
  if (normals) normals->clear();
  if (caps) caps->clear();
  switch (o.kind) {
    case ObjectSpec::Kind::kTooth: {
      ToothModel tooth = GenerateTooth(o.fdi);
      CarveCavities(&tooth, o.caries_mm, o.cavity_mm);
      return ArchMirror(o.mirrored, tooth.mesh);
    }
    case ObjectSpec::Kind::kGingiva: {
      const ToothModel tooth = GenerateTooth(o.fdi);
      if (o.gingiva_neighbours.empty())
        return ArchMirror(o.mirrored, GenerateGingiva(tooth, GingivaOf(o)).mesh);
      const ShareNeighbours nb(o);
      GingivaModel g =
          GenerateGingiva(tooth, GingivaOf(o), nb.next, 0.3,
                          seen ? GingivaSurface::kSeen : GingivaSurface::kFelt);
      if (normals) *normals = ArchMirror(o.mirrored, std::move(g.normals));
      if (caps) *caps = std::move(g.caps);
      return ArchMirror(o.mirrored, std::move(g.mesh));
    }
    case ObjectSpec::Kind::kCalculus: {
      const ToothModel tooth = GenerateTooth(o.fdi);
      std::optional<GingivaModel> g;
      if (o.with_gingiva) g = GenerateGingiva(tooth, GingivaOf(o));
      return ArchMirror(o.mirrored,
                        MakeCalculus(tooth, g ? &*g : nullptr, o.calculus_site,
                                     o.calculus[o.calculus_site] == 2));
    }
    case ObjectSpec::Kind::kAnatomy:
      return MakeSoftTissue(o.anatomy, ArchParams{.upper_lift_mm = o.mouth_open_mm},
                            o.crest_drop_mm, o.furcation_of);
    case ObjectSpec::Kind::kMesh: {
      TriangleMesh m = LoadMesh(o.mesh);
      // Scene meshes are in millimetres: a mouth is about 60 mm across. A mesh of
      // metres read as millimetres, or a scan in microns, would build its trees for
      // minutes and mean nothing: refused with the size it has.
      const Aabb b = m.Bounds();
      const double across = (b.max - b.min).norm();
      if (across > kMaxSceneObjectMm)
        throw MeshError(o.mesh.string(),
                        "is " + std::to_string(static_cast<long long>(across)) +
                            " mm across; a scene object may be at most " +
                            std::to_string(static_cast<int>(kMaxSceneObjectMm)) +
                            " mm (is the mesh in another unit than millimetres?)");
      return m;
    }
    case ObjectSpec::Kind::kBox:
      return MakeBox(o.size,
                     std::max(1, static_cast<int>(std::ceil(o.size.maxCoeff() / 2))));
    case ObjectSpec::Kind::kSphere:
      return MakeIcosphere(o.radius_mm, 4);
    case ObjectSpec::Kind::kCylinder:
      return MakeCylinder(o.radius_mm, o.height_mm, 48,
                          std::max(1, static_cast<int>(o.height_mm / 2)));
  }
  return {};
}

namespace {

// A failure while building one object's collision spheres, named: the scene
// file, the object and its place in the file (a tree's own error names none of
// them). Other failures pass as they are (a mesh's error names its file).
std::exception_ptr NamedFailure(const SceneSpec& spec, const ObjectSpec& o) {
  try {
    throw;
  } catch (const SphereTreeError& e) {
    std::string where = spec.file.empty() ? std::string("the scene") : spec.file.string();
    if (o.line > 0) where += ":" + std::to_string(o.line);
    where += ": object '" + o.name + "'";
    return std::make_exception_ptr(
        SphereTreeError(where + ": its collision spheres cannot be built: " + e.what()));
  } catch (...) {
    return std::current_exception();
  }
}

// Runs `work` on one thread per core, at most `jobs` of them, the caller's
// among them, and returns when all have returned (each takes its jobs itself).
template <typename Work>
void OnEachCore(int jobs, const Work& work) {
  const int threads = std::clamp(static_cast<int>(std::thread::hardware_concurrency()), 1,
                                 std::max(jobs, 1));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
}

// The shares of the seen gingiva to build (`jobs`) and, as for CompileScene's
// meshes, for each share whose generator sees what an earlier one's sees (its
// mirrored twin) that share (`twin`, else -1): its mesh is the twin's, mirrored.
struct SeenPlan {
  std::vector<int> jobs, twin;
};

SeenPlan PlanSeenGingiva(const std::vector<ObjectSpec>& objects) {
  const int n = static_cast<int>(objects.size());
  SeenPlan plan;
  plan.twin.assign(n, -1);
  std::map<std::string, int> first;
  for (int i = 0; i < n; ++i) {
    if (objects[i].kind != ObjectSpec::Kind::kGingiva ||
        objects[i].gingiva_neighbours.empty())
      continue;
    const auto [it, added] = first.try_emplace(GeneratorKey(objects[i]), i);
    if (added)
      plan.jobs.push_back(i);
    else
      plan.twin[i] = it->second;
  }
  return plan;
}

void MirrorSeenTwins(const std::vector<ObjectSpec>& objects, const SeenPlan& plan,
                     SeenGingiva* out) {
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const int j = plan.twin[i];
    if (j < 0) continue;
    const bool mirror = objects[i].mirrored != objects[j].mirrored;
    out->meshes[i] = ArchMirror(mirror, out->meshes[j]);
    out->normals[i] = ArchMirror(mirror, out->normals[j]);
    out->caps[i] = out->caps[j];  // (mirroring keeps the faces' order)
  }
}

}  // namespace

std::unique_ptr<CompiledScene> CompileScene(const SceneSpec& spec,
                                            const std::filesystem::path& cache_dir,
                                            const BuildProgress& progress,
                                            const CompileOptions& options) {
  auto scene = std::make_unique<CompiledScene>();
  scene->spec = spec;
  FollowAttachmentLoss(&scene->spec);  // the pockets may have changed since loading
  LinkGingivaNeighbours(&scene->spec);
  const bool compliance = spec.HasEffect(Effect::kGingivaCompliance);
  // Soft objects (gingiva, under gingiva_compliance) go last: the engine's hard
  // world is the objects before them, with the same indices as the scene's.
  auto soft = [&](const ObjectSpec& o) {
    return compliance && o.tissue == Tissue::kGingiva;
  };
  std::stable_partition(scene->spec.objects.begin(), scene->spec.objects.end(),
                        [&](const ObjectSpec& o) { return !soft(o); });
  const int n = static_cast<int>(spec.objects.size());
  // The seen gingiva's shares, when asked for: jobs after the trees'.
  const SeenPlan seen_plan =
      options.seen_gingiva ? PlanSeenGingiva(scene->spec.objects) : SeenPlan{};
  const int seen_jobs = static_cast<int>(seen_plan.jobs.size());
  if (options.seen_gingiva) {
    scene->seen.meshes.resize(n);
    scene->seen.normals.resize(n);
    scene->seen.caps.resize(n);
  }
  // One bar over meshes and trees: each object's mesh is the first tenth of
  // its share, its tree the rest; the tool's tree and each seen share are one
  // more share.
  const int shares = n + 1 + seen_jobs;
  using Clock = std::chrono::steady_clock;
  const auto Since = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  const auto t_meshes = Clock::now();
  // Meshes (a gingiva's share of its arch takes about a second to sample and
  // simplify), made by the workers below. A share whose generator sees what
  // an earlier one's sees (its twin on the other side of the arch, the key in
  // the unmirrored frame) is not built: it is its twin's mesh, mirrored.
  scene->meshes.resize(n);
  scene->normals.resize(n);
  scene->object_tree_seconds.assign(n, 0.0);
  scene->tree_built.assign(n, 0);
  std::vector<int> twin(n, -1);
  {
    std::map<std::string, int> first;
    for (int i = 0; i < n; ++i) {
      const ObjectSpec& o = scene->spec.objects[i];
      if (o.kind != ObjectSpec::Kind::kGingiva) continue;
      const auto [it, added] = first.try_emplace(GeneratorKey(o), i);
      if (!added) twin[i] = it->second;
    }
  }
  // Trees: a tree's job waits for its object's mesh only, so that a long
  // tree (a generated case's jaw) starts while the other meshes are made.
  scene->trees.resize(n);
  scene->planes.resize(n);
  scene->tool_mesh = MakeProbe(spec.probe).collision_mesh;
  // One worker per core takes the jobs in this order: the hard objects'
  // meshes, job 0 (the tool's tree) and their trees, then the soft objects'
  // meshes (a share whose twin's is made is not among them) and trees (the
  // soft, quick ones last, so that no core is left alone with a long job at
  // the end), then the seen gingiva's shares. A long hard tree (a generated
  // case's jaw) so starts while the gingiva's meshes are made.
  // Progress from the workers is serialised, and a cancel or an error stops
  // them all. A mirrored object (a tooth on the left of the arch, its gingiva)
  // gets the tree of its unmirrored mesh, mirrored: the same tooth on the
  // right has that mesh, so the two share one build (through the cache). The
  // mirrored ones go after all the others, so that their twin is built first.
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i) order[i] = i;
  std::stable_partition(order.begin(), order.end(),
                        [&](int i) { return !scene->spec.objects[i].mirrored; });
  // slots: >= 0 a tree job (job 0 the tool, j the tree of order[j - 1], past n a
  // seen share), < 0 the mesh of object -1 - slot.
  std::vector<int> slots;
  for (const bool soft_part : {false, true}) {
    for (int i = 0; i < n; ++i)
      if (twin[i] < 0 && soft(scene->spec.objects[i]) == soft_part)
        slots.push_back(-1 - i);
    if (!soft_part) slots.push_back(0);
    for (int j = 1; j <= n; ++j)
      if (soft(scene->spec.objects[order[j - 1]]) == soft_part) slots.push_back(j);
  }
  for (int j = n + 1; j < shares; ++j) slots.push_back(j);
  const int num_slots = static_cast<int>(slots.size());
  // done[j] is tree job j's fraction; an object's mesh is the first 0.1 of its
  // share, its tree the rest.
  std::vector<double> done(shares, 0.0);
  std::vector<char> mesh_ready(n, 0);
  int meshes_left = n;
  auto t_trees = Clock::now();
  std::mutex progress_mutex;
  std::condition_variable mesh_made;
  std::atomic<int> next{0};
  std::atomic<bool> stop{false};
  std::exception_ptr failure;
  // Under progress_mutex: reports the whole build's fraction.
  auto overall = [&](std::string_view stage) {
    double total = done[0];
    for (int j = 1; j <= n; ++j) total += 0.1 * mesh_ready[order[j - 1]] + 0.9 * done[j];
    for (int j = n + 1; j < shares; ++j) total += done[j];
    if (progress && !progress(stage, total / shares)) {
      stop = true;
      mesh_made.notify_all();  // no tree waits for a mesh no one will make
    }
  };
  auto worker = [&] {
    for (int k = next++; k < num_slots && !stop; k = next++) {
      if (slots[k] < 0) {
        const int i = -1 - slots[k];
        try {
          TriangleMesh mesh =
              MakeObjectMeshCached(scene->spec.objects[i], cache_dir, &scene->normals[i]);
          std::lock_guard lock(progress_mutex);
          scene->meshes[i] = std::move(mesh);
          mesh_ready[i] = 1;
          // Its twins: its mesh, mirrored.
          for (int k = 0; k < n; ++k) {
            if (twin[k] != i) continue;
            const bool mirror =
                scene->spec.objects[k].mirrored != scene->spec.objects[i].mirrored;
            scene->meshes[k] = ArchMirror(mirror, scene->meshes[i]);
            scene->normals[k] = ArchMirror(mirror, scene->normals[i]);
            mesh_ready[k] = 1;
            --meshes_left;
          }
          if (--meshes_left == 0) {
            scene->mesh_seconds = Since(t_meshes);
            t_trees = Clock::now();
          }
          overall(scene->spec.objects[i].name);
        } catch (...) {
          std::lock_guard lock(progress_mutex);
          if (!failure) failure = std::current_exception();
          stop = true;
        }
        mesh_made.notify_all();
        continue;
      }
      const int job = slots[k];
      const BuildProgress inner = [&, job](std::string_view stage, double f) {
        if (stop) return false;
        std::lock_guard lock(progress_mutex);
        done[job] = f;
        overall(stage);
        return !stop.load();
      };
      try {
        if (job > n) {
          const int i = seen_plan.jobs[job - n - 1];
          SeenGingiva& seen = scene->seen;
          seen.meshes[i] = MakeObjectMeshCached(scene->spec.objects[i], cache_dir,
                                                &seen.normals[i], true, &seen.caps[i]);
          inner("the gingiva as drawn, " + scene->spec.objects[i].name, 1.0);
        } else if (job == 0) {
          scene->tool_tree =
              LoadOrBuildSphereTree(scene->tool_mesh, ToolTreeParams(), cache_dir, inner);
          inner("tool", 1.0);
        } else {
          // The partitioned list's own settings: spec.objects is in the file's order.
          const int i = order[job - 1];
          {
            std::unique_lock lock(progress_mutex);
            mesh_made.wait(lock, [&] { return mesh_ready[i] || stop; });
          }
          if (stop) continue;
          const ObjectSpec& o = scene->spec.objects[i];
          CacheOutcome cached;
          const auto t0 = Clock::now();
          SphereTree t = LoadOrBuildSphereTree(ArchMirror(o.mirrored, scene->meshes[i]),
                                               o.trees, cache_dir, inner, &cached);
          if (o.mirrored)
            for (double& x : t.x) x = -x;
          scene->trees[i] = std::move(t);
          scene->object_tree_seconds[i] = Since(t0);
          scene->tree_built[i] = cached.kind != CacheOutcome::Kind::kHit;
          if (scene->spec.leaf_planes)
            scene->planes[i] = FitLeafPlanes(scene->meshes[i], scene->trees[i]);
          inner(o.name, 1.0);
        }
      } catch (...) {
        std::lock_guard lock(progress_mutex);
        if (!failure) {
          if (job == 0 || job > n) {
            failure = std::current_exception();
          } else {
            failure = NamedFailure(scene->spec, scene->spec.objects[order[job - 1]]);
          }
        }
        stop = true;
        mesh_made.notify_all();
      }
    }
  };
  OnEachCore(num_slots, worker);
  if (failure) std::rethrow_exception(failure);
  if (stop) throw BuildCancelled();
  if (options.seen_gingiva) MirrorSeenTwins(scene->spec.objects, seen_plan, &scene->seen);
  const auto& objs = scene->spec.objects;
  int soft_first = n;
  while (soft_first > 0 && soft(objs[soft_first - 1])) --soft_first;
  std::vector<CollisionWorld::Object> hard, soft_objects;
  for (int i = 0; i < n; ++i)
    (i < soft_first ? hard : soft_objects)
        .push_back({&scene->trees[i], objs[i].X_WO, &scene->planes[i]});
  scene->model = std::make_unique<EngineModel>(scene->tool_tree, hard, spec.haptics);
  // Friction on the hard objects (soft gingiva is springs, not constraints).
  if (spec.HasEffect(Effect::kFriction))
    for (int i = 0; i < soft_first; ++i)
      scene->model->friction.push_back(objs[i].material.friction);
  BuildEffectsModel(scene.get(), soft_first, soft_objects);
  scene->tree_seconds = Since(t_trees);
  return scene;
}

}  // namespace sulcus
