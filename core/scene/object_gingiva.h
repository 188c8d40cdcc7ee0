#pragma once
// A scene object's gingiva as the generator takes it: shared by the objects'
// meshes (object_mesh.cpp), the compiler's effects (compile.cpp) and the
// scripted devices' aim (script_target.cpp).

#include <vector>

#include "core/anatomy/gingiva.h"
#include "core/scene/scene.h"

namespace sulcus {

/// The gingiva parameters of a tooth object (or a share of an arch's gingiva):
/// its pockets, recession and, for a share, the bone crest it reaches.
GingivaParams GingivaOf(const ObjectSpec& o);

/// The map from a share's tooth's (unmirrored) frame to its neighbour `s`'s:
/// p_s = A p + b.
void NeighbourFrame(const ObjectSpec& o, const GingivaNeighbourSpec& s, Matrix3* A,
                    Vector3* b);

/// A share's sites' lines (GingivaParams::site_angle): the interdental lines
/// moved clear of its cuts toward its neighbours (LineAnglesClearOfCuts); a
/// collar alone keeps kSiteAngles.
std::array<double, 6> ShareLineAngles(const ObjectSpec& o);

/// A share of the arch's gingiva's neighbours: their teeth and collars, and
/// the map from this tooth's (unmirrored) frame to each of theirs (`next`, as
/// the share's generator takes them).
struct ShareNeighbours {
  explicit ShareNeighbours(const ObjectSpec& o);
  ShareNeighbours(const ShareNeighbours&) = delete;
  ShareNeighbours& operator=(const ShareNeighbours&) = delete;
  std::vector<ToothModel> teeth;
  std::vector<GingivaModel> collars;
  std::vector<GingivaNeighbour> next;
};

}  // namespace sulcus
