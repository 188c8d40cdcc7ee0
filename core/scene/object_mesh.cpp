// Scene objects' meshes: what generates each (GeneratorKey), the generator
// called (MakeObjectMesh), and the on-disk cache of generated meshes, their
// drawing normals and the drawn shares' cap faces (MakeObjectMeshCached).
#include "core/scene/object_mesh.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

#include "core/anatomy/arch.h"
#include "core/anatomy/findings.h"
#include "core/anatomy/gingiva.h"
#include "core/anatomy/soft_tissue.h"
#include "core/anatomy/tooth.h"
#include "core/geometry/mesh_io.h"
#include "core/geometry/primitives.h"
#include "core/scene/object_gingiva.h"
#include "core/scene/scene.h"
#include "core/spheretree/tree_files.h"

namespace sulcus {

namespace {

// A tooth's gingiva parameters: its sites and, for a share (crest_drop_mm >
// 0), the bone crest it reaches, along the world's vertical toward the crown
// in its (unmirrored) tooth frame placed at X_WO.
GingivaParams GingivaParamsOf(int fdi, bool mirrored, const RigidTransform& X_WO,
                              const std::array<double, 6>& pocket_mm,
                              const std::array<double, 6>& recession_mm,
                              double crest_drop_mm,
                              const std::array<double, 6>& site_angle) {
  GingivaParams p;
  p.pocket_mm = pocket_mm;
  p.recession_mm = recession_mm;
  p.site_angle = site_angle;
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
                         o.share_crest_drop_mm, o.site_angle);
}

namespace {

// A share's neighbour `s` as its generator sees it: its collar's parameters,
// and the map from the share's tooth's (unmirrored) frame to the neighbour's.
GingivaParams NeighbourParams(const ObjectSpec& o, const GingivaNeighbourSpec& s) {
  return GingivaParamsOf(s.fdi, s.mirrored, s.X_WO, s.pocket_mm, s.recession_mm,
                         o.share_crest_drop_mm > 0 ? s.crest_drop_mm : 0, s.site_angle);
}

}  // namespace

void NeighbourFrame(const ObjectSpec& o, const GingivaNeighbourSpec& s, Matrix3* A,
                    Vector3* b) {
  const Matrix3 mirror_self = Vector3(o.mirrored ? -1 : 1, 1, 1).asDiagonal();
  const Matrix3 mirror = Vector3(s.mirrored ? -1 : 1, 1, 1).asDiagonal();
  const Matrix3 Rt = s.X_WO.rotation().transpose();
  *A = mirror * Rt * o.X_WO.rotation() * mirror_self;
  *b = mirror * Rt * (o.X_WO.translation() - s.X_WO.translation());
}

std::array<double, 6> ShareLineAngles(const ObjectSpec& o) {
  if (o.kind != ObjectSpec::Kind::kGingiva || o.gingiva_neighbours.empty())
    return kSiteAngles;
  // What the lines depend on, in the tooth's unmirrored frame: its shape, its
  // sites' depths and recession, its neighbours' shapes and frames. A scene is
  // linked when it is loaded and again when it is compiled (and a mirrored
  // twin has the same lines): each share's lines are found once a process.
  std::vector<Matrix3> frames;
  std::vector<Vector3> offsets;
  std::ostringstream key;
  key << o.fdi;
  for (int i = 0; i < 6; ++i) key << '|' << o.pocket_mm[i] << '|' << o.recession_mm[i];
  for (const GingivaNeighbourSpec& s : o.gingiva_neighbours) {
    Matrix3 A;
    Vector3 b;
    NeighbourFrame(o, s, &A, &b);
    frames.push_back(A);
    offsets.push_back(b);
    key << "|next " << s.fdi;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) key << ' ' << std::llround(A(r, c) * 1e9);
      key << ' ' << std::llround(b[r] * 1e9);
    }
  }
  static std::mutex mutex;
  static std::map<std::string, std::array<double, 6>> found;
  {
    const std::lock_guard lock(mutex);
    if (const auto it = found.find(key.str()); it != found.end()) return it->second;
  }
  const ToothModel tooth = GenerateTooth(o.fdi);
  std::vector<ClipPlane> cuts;
  for (std::size_t i = 0; i < o.gingiva_neighbours.size(); ++i)
    cuts.push_back(CutToward(tooth, GenerateTooth(o.gingiva_neighbours[i].fdi), frames[i],
                             offsets[i]));
  GingivaParams p = GingivaOf(o);
  p.site_angle = kSiteAngles;
  const std::array<double, 6> lines = LineAnglesClearOfCuts(tooth, p, cuts);
  const std::lock_guard lock(mutex);
  found.emplace(key.str(), lines);
  return lines;
}

ShareNeighbours::ShareNeighbours(const ObjectSpec& o) {
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

namespace {

// A generated tooth's shape depends on its arch and position only: 11 and 21
// are one shape (21's placed mirrored).
std::string ToothShapeKey(int fdi) {
  const FdiTooth t = FdiTooth::Parse(fdi);
  return std::string(t.upper() ? "upper " : "lower ") + std::to_string(t.position);
}

// A placement's number to 1e-9 mm (or of a unit vector): the two sides of the
// arch are placed by separate arithmetic and differ in the last bits.
double Placed(double v) { return std::round(v * 1e9) * 1e-9 + 0.0; }  // (+ 0.0: no -0)

}  // namespace

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
      if (g.site_angle != kSiteAngles)
        for (const double a : g.site_angle) k << "|line " << Placed(a);
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
        if (p.site_angle != kSiteAngles)
          for (const double a : p.site_angle) e << "|line " << Placed(a);
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

namespace {

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

}  // namespace sulcus
