#pragma once
// Each group of subcommands registers itself on the CLI11 app.

#include <CLI/CLI.hpp>

namespace sulcus::cli {

/// `mesh info`, `mesh convert`, `mesh make`.
void AddMeshCommands(CLI::App& app);

/// `spheretree build`, `spheretree eval`.
void AddSphereTreeCommands(CLI::App& app);

/// `qp-bench`, `qp-gen`.
void AddQpCommands(CLI::App& app);

/// `accuracy-cost`.
void AddAccuracyCommands(CLI::App& app);

/// `anatomy tooth`.
void AddAnatomyCommands(CLI::App& app);

/// `scene validate`, `scene export`.
void AddSceneCommands(CLI::App& app);

/// `run`, `devices`, `recording export|info`.
void AddRunCommands(CLI::App& app);

/// `lesson validate|run|report`, `results list|show|export`.
void AddLessonCommands(CLI::App& app);

/// Exit status of the subcommand that ran (set by its callback).
int& ExitStatus();

}  // namespace sulcus::cli
