// Where a scripted device aims in a compiled scene (FindScriptTarget), and a
// scene file's hash (a recording keeps it, to say which version it was made on).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <string>

#include "core/anatomy/arch.h"
#include "core/anatomy/gingiva.h"
#include "core/anatomy/tooth.h"
#include "core/scene/object_gingiva.h"
#include "core/scene/scene.h"
#include "core/spheretree/tree_files.h"

namespace sulcus {

ScriptTarget FindScriptTarget(const CompiledScene& scene, const std::string& script,
                              int object) {
  const auto& objects = scene.spec.objects;
  if (objects.empty()) throw std::invalid_argument("the scene has no objects to touch");
  if (object < 0) {
    // The first lower tooth (its crown faces up, the instrument comes from
    // above), else the first tooth, else the first object; for `insert` into a
    // scene with gingiva, the tooth with the deepest buccal pocket among those.
    object = 0;
    auto rank = [&](const ObjectSpec& o) {
      const bool lower = FdiTooth::Parse(o.fdi).quadrant >= 3;
      const double depth =
          script == "insert" && scene.spec.gingiva ? o.pocket_mm[1] : 0.0;
      return std::pair(lower, depth);
    };
    std::optional<std::pair<bool, double>> best;
    for (std::size_t i = 0; i < objects.size(); ++i) {
      if (objects[i].kind != ObjectSpec::Kind::kTooth) continue;
      if (const auto r = rank(objects[i]); !best || r > *best) {
        best = r;
        object = static_cast<int>(i);
      }
    }
  }

  if (object >= static_cast<int>(objects.size()))
    throw std::invalid_argument("no object " + std::to_string(object));
  const ObjectSpec& o = objects[object];
  const TriangleMesh& mesh = scene.meshes[object];
  const Matrix3& R = o.X_WO.rotation();
  ScriptTarget t;
  t.object = object;
  if (o.kind == ObjectSpec::Kind::kTooth && script == "insert" && scene.spec.gingiva) {
    // Into the sulcus at the buccal site, down to just past the pocket floor, to
    // press it with the clinical probing force (0.20 to 0.25 N).
    const GingivaModel g = GenerateGingiva(GenerateTooth(o.fdi), GingivaOf(o));
    t.p_W = o.X_WO * ArchMirror(o.mirrored, g.margin[1]);
    t.n_W = R * Vector3::UnitY();
    t.axis_W = R * Vector3::UnitZ();
    t.along_W = R * Vector3::UnitX();
    t.tool_axis_W =
        R * Vector3(0, 0.15, 1).normalized();  // tilted buccally, as a clinician does
    t.shank_W =
        R * Vector3(0, -1, 0);  // the shank over the crown, not out through the cheek
    t.insert_offset_mm = 0;
    // How deep to go: press the probe down this path, tick by tick through the
    // engine and the scene's effects, until it feels the clinical probing force
    // (0.22 N) along its axis, as the reading measures it: the depth where the
    // sphere-trees' floor pushes back that hard (the sulcus' wall pushing
    // sideways on the shank is not the floor).
    t.insert_depth_mm = o.pocket_mm[1] + 0.22 / scene.spec.haptics.k_t;
    {
      const Quaternion q = ScriptOrientation(t);
      std::vector<Keyframe> keys;
      const double step = 0.005, from = -2.0, to = o.pocket_mm[1] + 2.0;
      for (int i = 0; from + i * step <= to; ++i)
        keys.push_back({i * 0.001, t.p_W - (from + i * step) * t.axis_W, q, 0});
      ScriptedDevice press(Trajectory(std::move(keys)), "press");
      const auto effects = MakeEffects(scene.effects);
      const auto list = EffectPointers(effects);
      LoopOptions lo;
      lo.safety.ramp_s = 0;
      HapticLoop loop(*scene.model, &press, lo, list);
      for (int i = 0; from + i * step <= to; ++i) {
        loop.Tick(false);
        const double depth =
            from +
            i * step;  // a touch above the floor's last millimetre is not the floor
        const TickRecord& r = loop.last_record();
        if (depth >= o.pocket_mm[1] - 1.0 &&
            r.force_W.dot(r.X_WG.rotation().col(2)) >= 0.22) {
          t.insert_depth_mm = depth;
          break;
        }
      }
    }
  } else if (o.kind == ObjectSpec::Kind::kTooth) {
    // Tooth frame: +z occlusal, +y buccal, +x mesial.
    Vector3 best = Vector3::Zero();
    double best_score = -1e300;
    const bool insert = script == "insert";
    for (const Vector3& v : mesh.vertices()) {
      const double score =
          insert ? (std::abs(v.z()) < 0.6 ? v.y() : -1e300) : v.z() - 0.2 * v.norm();
      if (score > best_score) {
        best_score = score;
        best = v;
      }
    }
    t.p_W = o.X_WO * ArchMirror(o.mirrored, best);
    t.n_W = R * (insert ? Vector3::UnitY() : Vector3::UnitZ());
    t.axis_W = R * Vector3::UnitZ();
    t.along_W = R * Vector3::UnitX();
  } else {
    Vector3 top = o.X_WO * mesh.vertices().front();
    for (const Vector3& v : mesh.vertices()) {
      const Vector3 w = o.X_WO * v;
      if (w.z() > top.z()) top = w;
    }
    t.p_W = top;
    t.n_W = Vector3::UnitZ();
  }
  return t;
}

std::uint64_t HashFile(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)),
                          std::istreambuf_iterator<char>());
  return Fnv1a(bytes.data(), bytes.size());
}

}  // namespace sulcus
