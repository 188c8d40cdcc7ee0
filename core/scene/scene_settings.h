#pragma once
// A scene file's settings sections, read for LoadSceneSpec: 'haptics' (the
// engine's stiffnesses, limits, rate, surface and slip easing) and 'effects'
// (which effects the scene simulates). Errors go to the reader, with their
// line and column; a value not given keeps the spec's default.

#include <yaml-cpp/yaml.h>

#include "core/base/yaml_reader.h"
#include "core/scene/scene.h"

namespace sulcus {

/// `h` is the 'haptics' map.
void ReadHaptics(YamlReader& r, const YAML::Node& h, SceneSpec* spec);

/// `e` is the 'effects' node (a list of effect names).
void ReadEffects(YamlReader& r, const YAML::Node& e, SceneSpec* spec);

}  // namespace sulcus
