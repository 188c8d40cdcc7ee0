// sulcus-cli: everything Sulcus does, without a window.

#include <exception>
#include <iostream>

#include "app/cli/commands.h"

int main(int argc, char** argv) {
  CLI::App app{"Sulcus: haptic dental training simulator, command-line tools"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "sulcus-cli 0.1.0");
  sulcus::cli::AddMeshCommands(app);
  sulcus::cli::AddSphereTreeCommands(app);
  sulcus::cli::AddQpCommands(app);
  sulcus::cli::AddAccuracyCommands(app);
  sulcus::cli::AddAnatomyCommands(app);
  sulcus::cli::AddSceneCommands(app);
  sulcus::cli::AddRunCommands(app);
  sulcus::cli::AddLessonCommands(app);
  try {
    app.parse(argc, argv);
  } catch (const sulcus::cli::CommandStatus& s) {
    return s.code;
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
