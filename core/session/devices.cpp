#include <cstdio>

#include "core/haptics/scripted_device.h"
#include "core/session/session.h"

namespace sulcus {

DeviceSpec MakeDevice(const std::string& spelling, const CompiledScene& scene,
                      double seconds, std::uint64_t seed, int object) {
  DeviceSpec d;
  d.name = spelling;
  const auto colon = spelling.find(':');
  const std::string kind = spelling.substr(0, colon);
  const std::string what = colon == std::string::npos ? "" : spelling.substr(colon + 1);
  if (kind == "scripted" && !what.empty()) {
    Trajectory trajectory;
    if (what.size() > 4 && what.substr(what.size() - 4) == ".csv") {
      trajectory = LoadTrajectoryCsv(what);
    } else {
      const ScriptTarget target = FindScriptTarget(scene, what, object);
      trajectory = MakeScript(what, target, seconds, seed);
      char note[200];
      std::snprintf(note, sizeof note, "scripted '%s' on %s at (%.2f, %.2f, %.2f) mm",
                    what.c_str(), ObjectName(scene.spec, target.object).c_str(),
                    target.p_W.x(), target.p_W.y(), target.p_W.z());
      d.notes.push_back(note);
    }
    d.device = std::make_unique<ScriptedDevice>(std::move(trajectory), spelling);
  } else if (kind == "replay" && !what.empty()) {
    d.replayed = std::make_unique<Recording>(ReadRecording(what));
    if (!d.replayed->warning.empty()) d.notes.push_back(d.replayed->warning);
    if (d.replayed->header.scene_hash != HashFile(scene.spec.file))
      d.notes.push_back(what + " was recorded on another version of " +
                        scene.spec.file.string() + " (scene hash differs)");
    d.device = std::make_unique<ReplayDevice>(*d.replayed);
    d.name = "replay of " + d.replayed->header.device_name;
  } else {
    throw std::invalid_argument(
        "--device must be scripted:NAME, scripted:FILE.csv or replay:FILE, not '" +
        spelling + "' (hardware devices: see `sulcus-cli devices`)");
  }
  return d;
}

}  // namespace sulcus
