#pragma once
// Periodontal probes and dental explorers: the working end, the bent shank and
// the handle as one closed mesh, the markings as data, and the tip frame.
//
// Tool frame T = tip frame: origin at the tip's end, +z along the working end
// toward the shank (so markings are distances along +z from the tip). The shank
// turns 70 degrees in the x-z plane toward -x, so the handle rises away from the
// working end at 110 degrees to it.

#include <string>
#include <vector>

#include "core/geometry/mesh.h"

namespace sulcus {

struct ProbeMarking {
  double from_mm, to_mm;  // along the working end from the tip; a line has from == to
  bool band = false;      // a coloured band rather than a line
};

struct ProbeModel {
  std::string name;             // williams, unc15, who
  TriangleMesh mesh;            // the whole probe, in the tip frame (for display)
  TriangleMesh collision_mesh;  // working end, bend and 8 mm of shank (for the engine)
  std::vector<ProbeMarking> markings;
  double tip_radius_mm = 0;  // ball (WHO) or rounded taper
  bool ball_tip = false;
  bool explorer = false;         // a sharp explorer (no markings), not a probe
  double working_length_mm = 0;  // straight part from the tip to the bend
};

/// Known names: the periodontal probes "williams", "unc15", "who" (its 0.5 mm ball
/// is also the ball-ended probe used to detect caries without damage), and the
/// explorers "explorer23" (shepherd's hook No. 23) and "explorer1112" (11/12).
/// Throws std::invalid_argument otherwise.
ProbeModel MakeProbe(const std::string& name);

}  // namespace sulcus
