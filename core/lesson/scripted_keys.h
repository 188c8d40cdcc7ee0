#pragma once
// The scripted "keys" student: a probing lesson taken with the window's keys,
// on the same mouse-and-keyboard device the window uses (key_device.h) and the
// same key moves (probe_keys.h). For each site of the path in turn: N places
// the probe over it (or, when the tip is already in the sulcus of the same
// surface of the same tooth, comma and period walk it there along the sulcus in
// up-and-down steps); R twelve times, 0.05 s apart, press 0.24 N; it waits for
// the gauge to hold still at the floor for half a second and charts the depth
// the probe shows, with the probe still in; at an interdental site next to a
// contact, T takes the tip under the contact into the col, holds it there, and
// T again stands the probe up. When every site is charted it waits two
// seconds, charts bleeding where blood showed at the margin, and declares the
// diagnosis of its chart.

#include <memory>

#include "core/lesson/scripted_student.h"

namespace sulcus {

std::unique_ptr<ScriptedHand> MakeScriptedKeys(const LessonSpec& spec,
                                               const CompiledScene& scene);

}  // namespace sulcus
