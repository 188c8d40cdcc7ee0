#include <cstdio>

#include "core/base/text.h"
#include "core/haptics/scripted_device.h"
#include "core/session/session.h"

namespace sulcus {

DeviceName ParseDeviceName(const std::string& spelling) {
  const auto colon = spelling.find(':');
  const std::string kind = spelling.substr(0, colon);
  const std::string what = colon == std::string::npos ? "" : spelling.substr(colon + 1);
  using K = DeviceName::Kind;
  if (spelling == "mouse") return {K::kMouse, ""};
  if (kind == "scripted" && !what.empty()) {
    const bool csv = what.size() > 4 && what.substr(what.size() - 4) == ".csv";
    return {csv ? K::kScriptFile : K::kScripted, what};
  }
  if (kind == "replay" && !what.empty()) return {K::kReplay, what};
  if (kind == "student" && !what.empty()) return {K::kStudent, what};
  throw std::invalid_argument(
      "a device is mouse, scripted:NAME, scripted:FILE.csv, replay:FILE or "
      "student:NAME (in a lesson), not '" +
      Shorten(spelling) + "' (hardware devices: see `sulcus-cli devices`)");
}

std::string DeviceKindOf(const std::string& name) {
  if (name == "mouse" || name == "mouse and keyboard") return "keys";
  if (name.rfind("replay", 0) == 0) return "replay";  // "replay:FILE", "replay of ..."
  if (name.rfind("student:", 0) == 0 || name.rfind("scripted", 0) == 0) return "scripted";
  return "haptic";
}

DeviceSpec MakeDevice(const std::string& spelling, const CompiledScene& scene,
                      double seconds, std::uint64_t seed, int object) {
  const DeviceName name = ParseDeviceName(spelling);
  DeviceSpec d;
  d.name = spelling;
  const std::string& what = name.what;
  switch (name.kind) {
    case DeviceName::Kind::kScriptFile:
      d.device = std::make_unique<ScriptedDevice>(LoadTrajectoryCsv(what), spelling);
      break;
    case DeviceName::Kind::kScripted: {
      const ScriptTarget target = FindScriptTarget(scene, what, object);
      Trajectory trajectory = MakeScript(what, target, seconds, seed);
      char note[200];
      std::snprintf(note, sizeof note, "scripted '%s' on %s at (%.2f, %.2f, %.2f) mm",
                    what.c_str(), ObjectName(scene.spec, target.object).c_str(),
                    target.p_W.x(), target.p_W.y(), target.p_W.z());
      d.notes.push_back(note);
      d.device = std::make_unique<ScriptedDevice>(std::move(trajectory), spelling);
      break;
    }
    case DeviceName::Kind::kReplay:
      d.replayed = std::make_unique<Recording>(ReadRecording(what));
      if (!d.replayed->warning.empty()) d.notes.push_back(d.replayed->warning);
      if (d.replayed->header.scene_hash != HashFile(scene.spec.file))
        d.notes.push_back(what + " was recorded on another version of " +
                          scene.spec.file.string() + " (scene hash differs)");
      d.device = std::make_unique<ReplayDevice>(*d.replayed);
      d.name = "replay of " + d.replayed->header.device_name;
      break;
    case DeviceName::Kind::kStudent:
      throw std::invalid_argument(
          "'" + spelling +
          "' is a scripted student: it takes a lesson (sulcus-cli "
          "lesson run ... --device " +
          spelling + ")");
    case DeviceName::Kind::kMouse:
      throw std::invalid_argument(
          "the mouse drives the probe in the window (sulcus); here give scripted:NAME, "
          "scripted:FILE.csv or replay:FILE");
  }
  return d;
}

}  // namespace sulcus
