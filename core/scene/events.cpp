#include <algorithm>
#include <cstdio>

#include "core/scene/scene.h"

namespace sulcus {

std::string ObjectName(const SceneSpec& spec, int object) {
  if (object >= 0 && object < static_cast<int>(spec.objects.size()))
    return spec.objects[object].name;
  return "object " + std::to_string(object);
}

std::string DescribeEvent(const SceneSpec& spec, const HapticEvent& e) {
  char text[200];
  const std::string name = ObjectName(spec, e.object);
  auto site = [](int s) { return kSiteCodes[std::clamp(s, 0, 5)]; };
  switch (e.kind) {
    case EventKind::kContactBegan:
      std::snprintf(text, sizeof text, "touching %s", name.c_str());
      break;
    case EventKind::kContactEnded:
      std::snprintf(text, sizeof text, "off %s", name.c_str());
      break;
    case EventKind::kForceAbove:
      std::snprintf(text, sizeof text, "force above %.2f N", e.payload.force.force_n);
      break;
    case EventKind::kForceBelow:
      std::snprintf(text, sizeof text, "force back down (%.2f N)",
                    e.payload.force.force_n);
      break;
    case EventKind::kCommand:
      std::snprintf(
          text, sizeof text, "command: %s",
          ToString(static_cast<HapticCommand::Kind>(e.payload.command.command)));
      break;
    case EventKind::kDeviceLost:
      std::snprintf(text, sizeof text,
                    "the device stopped answering: no force until it is back");
      break;
    case EventKind::kDeviceBack:
      std::snprintf(text, sizeof text, "the device is back: the force ramps in");
      break;
    case EventKind::kOverrun:
      std::snprintf(text, sizeof text,
                    "the haptic thread was late: no force for that tick");
      break;
    case EventKind::kProbeReading: {
      const ReadingPayload& r = e.payload.reading;
      // A reading pressed past 0.5 N drove the tip into the attachment: said plainly.
      std::snprintf(text, sizeof text, "reading %.1f mm at %d %s (%.2f N, %.0f deg)%s",
                    r.depth_mm, r.fdi, site(r.site), r.peak_force_n, r.axis_angle_deg,
                    r.peak_force_n > 0.5
                        ? ": too hard, the tip went into the attachment (tissue damage)"
                        : "");
      break;
    }
    case EventKind::kBleeding:
      std::snprintf(text, sizeof text, "bleeding at %d %s", e.payload.bleeding.fdi,
                    site(e.payload.bleeding.site));
      break;
    case EventKind::kTissueDamage:
      std::snprintf(text, sizeof text, "%.2f N on %s: above its damage limit (%.2f N)",
                    e.payload.damage.force_n, name.c_str(), e.payload.damage.limit_n);
      break;
    case EventKind::kSoftContact:
      std::snprintf(text, sizeof text, "pressing %s", name.c_str());
      break;
    case EventKind::kCalculusTouched:
      std::snprintf(text, sizeof text, "the tip met calculus at %d %s (%.2f N)",
                    e.payload.calculus.fdi, site(e.payload.calculus.site),
                    e.payload.calculus.force_n);
      break;
    case EventKind::kCariesCatch:
      std::snprintf(text, sizeof text,
                    "the tip caught in a carious lesion on %s (%.2f N)", name.c_str(),
                    e.payload.damage.force_n);
      break;
    default:
      std::snprintf(text, sizeof text, "%s", ToString(e.kind));
      break;
  }
  return text;
}

}  // namespace sulcus
