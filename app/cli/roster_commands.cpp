// The class's roster and its students' sign-in: what the instructor keeps
// (names, a forgotten passphrase reset, whether the store asks every student
// to sign in). On a lab's PostgreSQL store the instructor's role writes these
// (a station's may not); on a station's own file the instructor's passphrase
// guards them.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "app/cli/commands.h"
#include "core/base/text.h"
#include "core/lesson/results.h"
#include "core/lesson/sign_in.h"

namespace sulcus::cli {

void AddRosterCommands(CLI::App* results) {
  CLI::App* roster = results->add_subcommand(
      "roster",
      "The class's roster: the names students sign in with (the instructor's: "
      "$SULCUS_INSTRUCTOR_PASSPHRASE or typed)");
  roster->require_subcommand(1);

  auto list_where = std::make_shared<std::string>();
  CLI::App* list = roster->add_subcommand("list", "The names on the roster");
  list->add_option("--results", *list_where, "Results folder, or a PostgreSQL URL");
  list->callback([list_where] {
    const auto store = OpenResults(ResultsOf(*list_where));
    const std::vector<std::string> names = store->Roster();
    for (const std::string& n : names) std::printf("%s\n", TerminalSafe(n).c_str());
    std::fprintf(stderr, "%zu name(s) on the roster of %s\n", names.size(),
                 store->where().c_str());
  });

  struct AddArgs {
    std::vector<std::string> names;
    std::string file, where;
  };
  auto add_args = std::make_shared<AddArgs>();
  CLI::App* add = roster->add_subcommand(
      "add",
      "Put names on the roster, typed or from a file (one a line, or a CSV whose first "
      "column is the name); a look-alike of a name there is refused");
  add->add_option("NAME", add_args->names, "Names to add");
  add->add_option("--file", add_args->file, "A roster file (UTF-8)");
  add->add_option("--results", add_args->where, "Results folder, or a PostgreSQL URL");
  add->callback([add_args] {
    std::vector<std::string> names = add_args->names;
    if (!add_args->file.empty())
      for (const std::string& n : ReadRosterFile(add_args->file)) names.push_back(n);
    if (names.empty())
      throw std::invalid_argument("roster add: give names, or a roster file with --file");
    if (!IsResultsUrl(ResultsOf(add_args->where).url)) RequireInstructor(add_args->where);
    const auto store = OpenResults(ResultsOf(add_args->where));
    std::vector<std::string> refused;
    const int added = AddNamesToRoster(*store, names, &refused);
    for (const std::string& r : refused)
      std::fprintf(stderr, "refused: %s\n", TerminalSafe(r).c_str());
    std::printf("%d name(s) added to the roster of %s (%zu given, %zu refused)\n", added,
                store->where().c_str(), names.size(), refused.size());
    if (!refused.empty()) Finish(1);
  });

  auto reset_args = std::make_shared<std::array<std::string, 2>>();
  CLI::App* reset = roster->add_subcommand(
      "reset",
      "Forget a student's passphrase: they choose a new one at their next sign-in");
  reset->add_option("NAME", (*reset_args)[0], "The student")->required();
  reset->add_option("--results", (*reset_args)[1], "Results folder, or a PostgreSQL URL");
  reset->callback([reset_args] {
    const ResultsPlace place = ResultsOf((*reset_args)[1]);
    if (!IsResultsUrl(place.url)) RequireInstructor((*reset_args)[1]);
    if (!OpenResults(place)->ResetPassphrase((*reset_args)[0]))
      throw std::invalid_argument("roster reset: " + (*reset_args)[0] +
                                  " is not on the roster, or has no passphrase yet");
    std::printf("%s chooses a new passphrase at the next sign-in\n",
                TerminalSafe((*reset_args)[0]).c_str());
  });

  auto sign_args = std::make_shared<std::array<std::string, 2>>();
  CLI::App* sign = roster->add_subcommand(
      "sign-in",
      "Whether the store takes a student's attempt only from that student, signed in "
      "(required), or also from students who did not sign in, marked so (off)");
  sign->add_option("WHAT", (*sign_args)[0], "required or off")
      ->required()
      ->check(CLI::IsMember({"required", "off"}));
  sign->add_option("--results", (*sign_args)[1], "Results folder, or a PostgreSQL URL");
  sign->callback([sign_args] {
    const ResultsPlace place = ResultsOf((*sign_args)[1]);
    if (!IsResultsUrl(place.url)) RequireInstructor((*sign_args)[1]);
    OpenResults(place)->SetSetting(kSignInSetting, (*sign_args)[0]);
    std::printf("sign-in %s in %s\n", (*sign_args)[0].c_str(), place.Describe().c_str());
  });
}

}  // namespace sulcus::cli
