#pragma once
// Fitting the teeth's places along the arches on their exact meshes: each tooth
// as close to its mesial neighbour as it goes without the two meshes
// intersecting. PlaceArch uses the result as a table (ArchCentreMm); this is how
// the table is made and checked.

#include <array>

#include "core/anatomy/arch.h"

namespace sulcus {

struct ArchFit {
  std::array<double, 8>
      centre_mm{};  // per position 1..8: arc length of the crown's centre
};

/// Fits one arch (the left side; the right is its mirror image), central
/// incisor first: the centrals touch the midline plane, then each tooth is
/// moved mesially by bisection (to `tolerance_mm`) until its mesh would
/// intersect its mesial neighbour's, and left `clearance_mm` distal of that.
ArchFit FitArchCentres(bool upper, double clearance_mm = 0.01,
                       double tolerance_mm = 0.002);

}  // namespace sulcus
