#include <algorithm>
#include <cstdio>

#include "core/scene/scene.h"

namespace sulcus {

std::string ObjectName(const SceneSpec& spec, int object) {
  if (object >= 0 && object < static_cast<int>(spec.objects.size())) return spec.objects[object].name;
  return "object " + std::to_string(object);
}

std::string DescribeEvent(const SceneSpec& spec, const HapticEvent& e) {
  char text[160];
  const std::string name = ObjectName(spec, e.object);
  const char* site = kSiteCodes[std::clamp(static_cast<int>(e.value2), 0, 5)];
  switch (e.kind) {
    case EventKind::kContactBegan:
    case EventKind::kContactEnded:
      std::snprintf(text, sizeof text, "%s: %s", ToString(e.kind), name.c_str());
      break;
    case EventKind::kForceAbove:
    case EventKind::kForceBelow:
      std::snprintf(text, sizeof text, "%s %.2f N", ToString(e.kind), e.value);
      break;
    case EventKind::kCommand:
      std::snprintf(text, sizeof text, "command: %s", ToString(static_cast<HapticCommand::Kind>(e.object)));
      break;
    case EventKind::kEffect:
      switch (static_cast<EffectEvent>(e.detail)) {
        case EffectEvent::kProbeReading:
          std::snprintf(text, sizeof text, "reading %.1f mm at %s %s", e.value, name.c_str(), site);
          break;
        case EffectEvent::kBleeding: std::snprintf(text, sizeof text, "bleeding at %s %s", name.c_str(), site); break;
        case EffectEvent::kTissueDamage:
          std::snprintf(text, sizeof text, "%.2f N on %s: above its damage limit", e.value, name.c_str());
          break;
        case EffectEvent::kSoftContact: std::snprintf(text, sizeof text, "soft contact: %s", name.c_str()); break;
        default: std::snprintf(text, sizeof text, "effect %d", e.detail); break;
      }
      break;
    default: std::snprintf(text, sizeof text, "%s", ToString(e.kind)); break;
  }
  return text;
}

}  // namespace sulcus
