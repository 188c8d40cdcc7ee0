// Compiling a scene: its objects' meshes (object_mesh.cpp) and sphere-trees
// made on every core, then the engine's model and what the effects need.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <optional>
#include <thread>

#include "core/anatomy/arch.h"
#include "core/anatomy/findings.h"
#include "core/anatomy/gingiva.h"
#include "core/anatomy/probe.h"
#include "core/anatomy/tooth.h"
#include "core/scene/object_gingiva.h"
#include "core/scene/object_mesh.h"
#include "core/scene/scene.h"
#include "core/spheretree/cache.h"

namespace sulcus {

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
      auto ring = std::make_shared<SulcusRing>();
      ring->X_RW = o.X_WO.inverse();
      ring->mirrored = o.mirrored;
      ring->margin_z = g.margin_z;
      ring->floor_z = g.floor_z;
      ring->sulcus_r = g.sulcus_r;
      for (const GingivaShareField::CutPlane& c : cuts) {
        if (ring->num_cuts == static_cast<int>(ring->cut_q_W.size())) break;
        ring->cut_q_W[ring->num_cuts] = o.X_WO * ArchMirror(o.mirrored, c.q);
        ring->cut_n_W[ring->num_cuts] =
            o.X_WO.rotation() * ArchMirror(o.mirrored, c.normal);
        ++ring->num_cuts;
      }
      ring->MakeZones();
      for (int s = 0; s < 6; ++s) {
        ProbingSite site;
        site.ring = ring;
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
        // (an interdental line the arch crowds past the cut toward the
        // neighbour is moved round toward its mid site: the share's
        // site_angle, from LinkGingivaNeighbours)
        site.line_moved_deg =
            std::abs(g.site_angle[s] - kSiteAngles[s]) * 180 / std::numbers::pi;
        site.pocket_mm = o.pocket_mm[s];
        site.bleeding = o.bleeding[s];
        m.sites.push_back(site);
      }
      // A line moved off the cut stays in its own zone: the bound toward the
      // mid site goes half way from the moved line to the mid site's.
      const std::size_t first = m.sites.size() - 6;
      auto angle = [&](int s) {
        const Vector3 p =
            ring->ToRing(m.sites[first + static_cast<std::size_t>(s)].margin_W);
        double a = std::atan2(p.y(), p.x());
        return a < 0 ? a + 2 * std::numbers::pi : a;
      };
      constexpr double kClear = 3 * std::numbers::pi / 180;
      if (angle(0) > ring->facial_from - kClear)
        ring->facial_from = 0.5 * (angle(0) + angle(1));
      if (angle(2) < ring->facial_to + kClear)
        ring->facial_to = 0.5 * (angle(2) + angle(1));
      if (angle(5) > ring->oral_from - kClear)
        ring->oral_from = 0.5 * (angle(5) + angle(4));
      if (angle(3) < ring->oral_to + kClear) ring->oral_to = 0.5 * (angle(3) + angle(4));
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

// For each gingiva object (a share of the arch's only, with `shares_only`)
// whose generator sees what an earlier one's sees, that one (its twin,
// mirrored across the midline); -1 for the others.
std::vector<int> GingivaTwins(const std::vector<ObjectSpec>& objects, bool shares_only) {
  std::vector<int> twin(objects.size(), -1);
  std::map<std::string, int> first;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const ObjectSpec& o = objects[i];
    if (o.kind != ObjectSpec::Kind::kGingiva ||
        (shares_only && o.gingiva_neighbours.empty()))
      continue;
    const auto [it, added] = first.try_emplace(GeneratorKey(o), static_cast<int>(i));
    if (!added) twin[i] = it->second;
  }
  return twin;
}

// The shares of the seen gingiva to build (`jobs`) and, as for CompileScene's
// meshes, for each share whose generator sees what an earlier one's sees (its
// mirrored twin) that share (`twin`, else -1): its mesh is the twin's, mirrored.
struct SeenPlan {
  std::vector<int> jobs, twin;
};

SeenPlan PlanSeenGingiva(const std::vector<ObjectSpec>& objects) {
  SeenPlan plan;
  plan.twin = GingivaTwins(objects, true);
  for (std::size_t i = 0; i < objects.size(); ++i)
    if (objects[i].kind == ObjectSpec::Kind::kGingiva &&
        !objects[i].gingiva_neighbours.empty() && plan.twin[i] < 0)
      plan.jobs.push_back(static_cast<int>(i));
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
  const std::vector<int> twin = GingivaTwins(scene->spec.objects, false);
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
  // The jobs in the order the workers take them: an object's mesh, or a tree
  // job (0 the tool's, j the tree of order[j - 1], past n a seen share).
  struct Job {
    bool mesh;
    int index;  // the object (a mesh), or the tree job's number
  };
  std::vector<Job> jobs;
  for (const bool soft_part : {false, true}) {
    for (int i = 0; i < n; ++i)
      if (twin[i] < 0 && soft(scene->spec.objects[i]) == soft_part)
        jobs.push_back({true, i});
    if (!soft_part) jobs.push_back({false, 0});
    for (int j = 1; j <= n; ++j)
      if (soft(scene->spec.objects[order[j - 1]]) == soft_part)
        jobs.push_back({false, j});
  }
  for (int j = n + 1; j < shares; ++j) jobs.push_back({false, j});
  const int num_jobs = static_cast<int>(jobs.size());
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
    for (int k = next++; k < num_jobs && !stop; k = next++) {
      if (jobs[k].mesh) {
        const int i = jobs[k].index;
        try {
          TriangleMesh mesh =
              MakeObjectMeshCached(scene->spec.objects[i], cache_dir, &scene->normals[i]);
          std::lock_guard lock(progress_mutex);
          scene->meshes[i] = std::move(mesh);
          mesh_ready[i] = 1;
          // Its twins: its mesh, mirrored.
          for (int t = 0; t < n; ++t) {
            if (twin[t] != i) continue;
            const bool mirror =
                scene->spec.objects[t].mirrored != scene->spec.objects[i].mirrored;
            scene->meshes[t] = ArchMirror(mirror, scene->meshes[i]);
            scene->normals[t] = ArchMirror(mirror, scene->normals[i]);
            mesh_ready[t] = 1;
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
      const int job = jobs[k].index;
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
  OnEachCore(num_jobs, worker);
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
