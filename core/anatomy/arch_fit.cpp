#include "core/anatomy/arch_fit.h"

#include <algorithm>
#include <limits>

#include "core/anatomy/mesh_contact.h"

namespace sulcus {

ArchFit FitArchCentres(bool upper, double clearance_mm, double tolerance_mm) {
  ArchFit fit;
  const int quadrant = upper ? 2 : 3;  // the patient's left: x > 0
  TriangleMesh previous;
  for (int pos = 1; pos <= 8; ++pos) {
    const int fdi = 10 * quadrant + pos;
    const TriangleMesh tooth = GenerateTooth(fdi).mesh;
    const double width = Dimensions(FdiTooth::Parse(fdi)).md_crown;
    auto placed = [&](double s) { return PlacedMesh(PlaceTooth(fdi, s), tooth); };
    // Apart at `hi`, touching (or crossing) at `lo`.
    double lo, hi;
    if (pos == 1) {
      // The central's mesial surface at the midline plane x = 0, where its
      // mirror image, the other central, meets it.
      auto nearest_x = [&](double s) {
        double m = std::numeric_limits<double>::infinity();
        const TriangleMesh mesh = placed(s);
        for (const Vector3& v : mesh.vertices()) m = std::min(m, v.x());
        return m;
      };
      lo = 0;
      hi = width;
      while (hi - lo > tolerance_mm) {
        const double mid = 0.5 * (lo + hi);
        (nearest_x(mid) > clearance_mm / 2 ? hi : lo) = mid;
      }
      fit.centre_mm[0] = hi;
    } else {
      lo = fit.centre_mm[pos - 2];
      hi = lo + width + 4;
      while (hi - lo > tolerance_mm) {
        const double mid = 0.5 * (lo + hi);
        (MeshesIntersect(previous, placed(mid)) ? lo : hi) = mid;
      }
      fit.centre_mm[pos - 1] = hi + clearance_mm;
    }
    previous = placed(fit.centre_mm[pos - 1]);
  }
  return fit;
}

}  // namespace sulcus
