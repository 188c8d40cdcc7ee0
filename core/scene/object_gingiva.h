#pragma once
// A scene object's gingiva as the generator takes it: shared by the compiler
// (core/scene/compile.cpp) and the scripted devices' aim (script_target.cpp).

#include "core/anatomy/gingiva.h"
#include "core/scene/scene.h"

namespace sulcus {

/// The gingiva parameters of a tooth object (or a share of an arch's gingiva):
/// its pockets, recession and, for a share, the bone crest it reaches.
GingivaParams GingivaOf(const ObjectSpec& o);

}  // namespace sulcus
