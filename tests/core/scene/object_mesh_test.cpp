// Scene objects' meshes (core/scene/object_mesh.cpp): what generates each,
// the gingiva as felt and as drawn, the jaw round them, and the mesh cache
// twins share.
#include "core/scene/object_mesh.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/anatomy/mesh_contact.h"
#include "core/scene/scene.h"
#include "tests/common/output.h"
#include "tests/core/scene/scene_file_errors.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

using test::Dir;
using test::Write;

// Two objects whose generators see the same thing have one key (a share of
// the gingiva and its mirrored twin across the midline: one build); a change
// the generator sees changes it; a shape is not generated and has none.
TEST(ObjectMesh, TheGeneratorKeyIsWhatTheGeneratorSees) {
  const SceneSpec spec = LoadSceneSpec(
      Write("generator_keys.yaml",
            "arch: true\ngingiva: arch\nobjects:\n  - tooth: 11\n  - tooth: 12\n"
            "  - tooth: 21\n  - tooth: 22\n  - box: [2, 2, 2]\n    tissue: bone\n"));
  std::map<int, const ObjectSpec*> share, tooth;
  const ObjectSpec* box = nullptr;
  for (const ObjectSpec& o : spec.objects) {
    if (o.kind == ObjectSpec::Kind::kGingiva) share[o.fdi] = &o;
    if (o.kind == ObjectSpec::Kind::kTooth) tooth[o.fdi] = &o;
    if (o.kind == ObjectSpec::Kind::kBox) box = &o;
  }
  ASSERT_EQ(share.size(), 4u);
  ASSERT_NE(box, nullptr);
  EXPECT_EQ(GeneratorKey(*share[11]), GeneratorKey(*share[21]))
      << "21's is 11's mirrored";
  EXPECT_NE(GeneratorKey(*share[11]), GeneratorKey(*share[12]));
  ObjectSpec deeper = *share[11];
  deeper.pocket_mm[0] += 2;
  EXPECT_NE(GeneratorKey(deeper), GeneratorKey(*share[11]));
  ObjectSpec cavity = *tooth[11];
  cavity.caries_mm[0] = 1.0;
  cavity.cavity_mm[0] = 1.0;
  EXPECT_FALSE(GeneratorKey(*tooth[11]).empty());
  EXPECT_NE(GeneratorKey(cavity), GeneratorKey(*tooth[11]));
  EXPECT_TRUE(GeneratorKey(*box).empty());
}

// The gingiva meets the jaw along one line just below the bone crest: below
// it, the gingiva lies inside the jaw (its lower edge hidden in the jaw's
// mucosa), around every tooth, between teeth and at the end of the arch. The
// line is drawn on a 0.3 mm grid and rounded, so a point counts as hidden
// when it is inside the jaw or within 1 mm of it, toward its tooth's axis.
// (Tipped teeth, the lower molars lingually and the incisors labially, once
// showed their gingiva's faces 1.5 mm and more outside the jaw here, and the
// gingiva beside the canine, whose crest is lower than its neighbours', too.)
TEST(SceneAnatomy, BelowTheCrestTheGingivaIsInsideTheJaw) {
  const SceneSpec spec =
      LoadSceneSpec(Write("gingiva_in_jaw.yaml",
                          "arch: true\ngingiva: arch\nobjects:\n  - tooth: 32\n  - "
                          "tooth: 31\n  - tooth: 41\n  - tooth: 42\n"
                          "  - tooth: 43\n  - tooth: 44\n  - tooth: 45\n  - tooth: 46\n  "
                          "- tooth: 47\n  - anatomy: jaw_lower\n"));
  TriangleMesh jaw;
  std::vector<std::pair<Vector3, double>>
      crests;  // each tooth's CEJ centre and crest height, in arch order
  for (const ObjectSpec& o : spec.objects) {
    if (o.kind == ObjectSpec::Kind::kAnatomy) {
      jaw = MakeObjectMesh(o);
      jaw.Transform(o.X_WO.rotation(), o.X_WO.translation());
    }
  }
  for (const ObjectSpec& o : spec.objects)
    if (o.kind == ObjectSpec::Kind::kGingiva)
      crests.emplace_back(o.X_WO.translation(),
                          o.X_WO.translation().z() - o.share_crest_drop_mm);
  ASSERT_EQ(crests.size(), 9u);
  // The crest under a point: straight from one tooth's centre to the next's
  // (the line nearest the point), level past the ends.
  auto crest_under = [&](const Vector3& v) {
    double best = 1e9, z = crests.front().second;
    for (std::size_t k = 0; k + 1 < crests.size(); ++k) {
      const Eigen::Vector2d a = crests[k].first.head<2>(),
                            b = crests[k + 1].first.head<2>();
      const double t =
          std::clamp((v.head<2>() - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      const double d = (v.head<2>() - (a + t * (b - a))).norm();
      if (d < best)
        best = d, z = crests[k].second + t * (crests[k + 1].second - crests[k].second);
    }
    return z;
  };
  ASSERT_GT(jaw.num_faces(), 0u);
  int shares = 0;
  for (const ObjectSpec& o : spec.objects) {
    // (32's distal end is free here, as no mouth has it: 33 is not in the scene)
    if (o.kind != ObjectSpec::Kind::kGingiva || o.fdi == 32) continue;
    ++shares;
    ASSERT_GT(o.share_crest_drop_mm, 0) << o.name;
    TriangleMesh g = MakeObjectMesh(o);
    g.Transform(o.X_WO.rotation(), o.X_WO.translation());
    std::vector<Vector3> below, nearer;
    for (const Vector3& v : g.vertices()) {
      if (v.z() >= crest_under(v) - 0.5) continue;
      Vector3 toward = o.X_WO.translation() - v;
      toward.z() = 0;
      below.push_back(v);
      nearer.push_back(v + 1.0 * toward.normalized());
    }
    ASSERT_GT(below.size(), 50u) << o.name << " reaches below its crest";
    const std::vector<bool> inside = InsideSolid(jaw, below),
                            near = InsideSolid(jaw, nearer);
    int out = 0, far_out = 0;
    for (std::size_t k = 0; k < below.size(); ++k) {
      out += !inside[k];
      far_out += !inside[k] && !near[k];
    }
    std::printf(
        "%s: %d of %zu vertices more than 0.5 mm below the crest outside the jaw, %d "
        "more than 1 mm\n",
        o.name.c_str(), out, below.size(), far_out);
    EXPECT_EQ(far_out, 0) << o.name << ": " << far_out << " of " << below.size()
                          << " vertices more than 0.5 mm below the crest are more than 1 "
                             "mm outside the jaw ("
                          << out << " outside it at all)";
  }
  EXPECT_EQ(shares, 8);
}

// A share of the arch's gingiva on the patient's left is its twin's on the
// right, mirrored, when the two are the same (one build through the cache,
// and the two sides are exact mirror images); a pocket on one side makes it
// its own.
TEST(SceneCompile, AMirroredGingivaShareIsItsTwinsMirrored) {
  const std::string teeth =
      "arch: true\ngingiva: arch\nobjects:\n  - tooth: 11\n  - tooth: 12\n  - tooth: "
      "21\n  - tooth: 22\n";
  auto gingiva = [](const CompiledScene& scene, int fdi) -> const TriangleMesh& {
    for (std::size_t i = 0; i < scene.spec.objects.size(); ++i)
      if (scene.spec.objects[i].kind == ObjectSpec::Kind::kGingiva &&
          scene.spec.objects[i].fdi == fdi)
        return scene.meshes[i];
    throw std::runtime_error("no gingiva " + std::to_string(fdi));
  };
  auto mesh_files = [](const fs::path& cache) {
    int n = 0;
    for (const auto& f : fs::directory_iterator(cache / "meshes"))
      n += f.path().extension() == ".mesh";
    return n;
  };
  auto mirrored = [](const TriangleMesh& a, const TriangleMesh& b) {
    if (a.num_vertices() != b.num_vertices() || a.num_faces() != b.num_faces())
      return false;
    for (std::size_t v = 0; v < a.num_vertices(); ++v)
      if (a.vertices()[v] !=
          Vector3(-b.vertices()[v].x(), b.vertices()[v].y(), b.vertices()[v].z()))
        return false;
    return true;
  };
  {
    const fs::path cache = Dir() / "cache-gingiva-twins";
    fs::remove_all(cache);
    const auto scene =
        CompileScene(LoadSceneSpec(Write("gingiva_twins.yaml", teeth)), cache);
    EXPECT_TRUE(mirrored(gingiva(*scene, 21), gingiva(*scene, 11)));
    EXPECT_TRUE(mirrored(gingiva(*scene, 22), gingiva(*scene, 12)));
    EXPECT_GT(gingiva(*scene, 11).num_faces(), 1000u);
    EXPECT_EQ(mesh_files(cache), 4 + 2) << "four teeth and two shares";
    // The shares' drawing normals: one per vertex, mirrored with the mesh,
    // and the same when read back from the cache; none for a tooth.
    auto normals = [](const CompiledScene& scene, int fdi,
                      ObjectSpec::Kind kind) -> const std::vector<Vector3>& {
      for (std::size_t i = 0; i < scene.spec.objects.size(); ++i)
        if (scene.spec.objects[i].kind == kind && scene.spec.objects[i].fdi == fdi)
          return scene.normals[i];
      throw std::runtime_error("no object " + std::to_string(fdi));
    };
    const auto& n11 = normals(*scene, 11, ObjectSpec::Kind::kGingiva);
    const auto& n21 = normals(*scene, 21, ObjectSpec::Kind::kGingiva);
    ASSERT_EQ(n11.size(), gingiva(*scene, 11).num_vertices());
    ASSERT_EQ(n21.size(), n11.size());
    for (std::size_t v = 0; v < n11.size(); ++v)
      EXPECT_EQ(n21[v], Vector3(-n11[v].x(), n11[v].y(), n11[v].z())) << v;
    EXPECT_TRUE(normals(*scene, 11, ObjectSpec::Kind::kTooth).empty());
    const auto again =
        CompileScene(LoadSceneSpec(Write("gingiva_twins.yaml", teeth)), cache);
    for (int fdi : {11, 12, 21, 22})
      EXPECT_EQ(normals(*again, fdi, ObjectSpec::Kind::kGingiva),
                normals(*scene, fdi, ObjectSpec::Kind::kGingiva))
          << fdi;
  }
  {
    const fs::path cache = Dir() / "cache-gingiva-not-twins";
    fs::remove_all(cache);
    const std::string pocket = teeth + "    pockets_mm: [5, 3, 3, 3, 3, 3]\n";  // on 22
    const auto scene =
        CompileScene(LoadSceneSpec(Write("gingiva_not_twins.yaml", pocket)), cache);
    EXPECT_FALSE(mirrored(gingiva(*scene, 22), gingiva(*scene, 12)))
        << "22 has a pocket 12 does not";
    EXPECT_FALSE(mirrored(gingiva(*scene, 21), gingiva(*scene, 11)))
        << "21's neighbour 22 has a pocket 11's neighbour 12 does not";
    EXPECT_EQ(mesh_files(cache), 4 + 4);
  }
}

// The window draws each share of the gingiva as the eye sees it (the sulcus
// closed round the tooth): a closed mesh of its own with its drawing normals,
// mirrored from its twin's cache entry on the patient's left like the felt
// one, and with the faces of its flat caps marked (the cut toward a
// neighbour), which the window hides through translucent gingiva.
TEST(SceneCompile, TheGingivaAsDrawnIsAClosedMeshWithItsCapsMarked) {
  const fs::path cache = Dir() / "cache-gingiva-seen";
  fs::remove_all(cache);
  const auto scene = CompileScene(
      LoadSceneSpec(Write("gingiva_seen.yaml",
                          "arch: true\ngingiva: arch\nobjects:\n  - tooth: 11\n  - "
                          "tooth: 12\n  - tooth: 21\n  - tooth: 22\n")),
      cache, {}, {.seen_gingiva = true});
  const SeenGingiva& seen = scene->seen;
  const std::size_t n = scene->spec.objects.size();
  ASSERT_EQ(seen.meshes.size(), n);
  ASSERT_EQ(seen.caps.size(), n);
  std::map<int, std::size_t> share;
  for (std::size_t i = 0; i < n; ++i) {
    const ObjectSpec& o = scene->spec.objects[i];
    if (o.kind != ObjectSpec::Kind::kGingiva) {
      EXPECT_EQ(seen.meshes[i].num_faces(), 0u)
          << o.name << ": drawn as the engine has it";
      continue;
    }
    share[o.fdi] = i;
    const TriangleMesh& m = seen.meshes[i];
    EXPECT_TRUE(m.Check().IsSolid()) << o.name;
    EXPECT_NE(m.num_faces(), scene->meshes[i].num_faces())
        << o.name << ": not the felt share";
    ASSERT_EQ(seen.normals[i].size(), m.num_vertices()) << o.name;
    ASSERT_EQ(seen.caps[i].size(), m.num_faces()) << o.name;
    // The caps: some faces, each flat on one of the share's cuts (12 and 22
    // have one neighbour here, so one plane: all their cap faces face one way).
    std::vector<Vector3> cap_normals;
    for (std::size_t f = 0; f < m.num_faces(); ++f) {
      if (!seen.caps[i][f]) continue;
      const auto& face = m.faces()[f];
      const Vector3 e = (m.vertices()[face[1]] - m.vertices()[face[0]])
                            .cross(m.vertices()[face[2]] - m.vertices()[face[0]]);
      if (e.norm() > 1e-9) cap_normals.push_back(e.normalized());
    }
    EXPECT_GT(cap_normals.size(), 20u) << o.name;
    EXPECT_LT(cap_normals.size(), m.num_faces() / 4) << o.name;
    if (o.fdi == 12 || o.fdi == 22) {
      for (const Vector3& c : cap_normals)
        EXPECT_GT(c.dot(cap_normals.front()), 0.999) << o.name;
    }
  }
  ASSERT_EQ(share.size(), 4u);
  // 21's is 11's mirrored, caps and all.
  const TriangleMesh &a = seen.meshes[share[11]], &b = seen.meshes[share[21]];
  ASSERT_EQ(a.num_vertices(), b.num_vertices());
  for (std::size_t v = 0; v < a.num_vertices(); ++v)
    EXPECT_EQ(b.vertices()[v],
              Vector3(-a.vertices()[v].x(), a.vertices()[v].y(), a.vertices()[v].z()))
        << v;
  EXPECT_EQ(seen.caps[share[11]], seen.caps[share[21]]);
}

}  // namespace
}  // namespace sulcus
