#pragma once
// The start page: who the student is (picked or added, remembered), the lessons
// shipped and the instructor's own folder, each with its description and this
// student's last score, broken lesson files listed as broken with their errors,
// practice or assessment, and for a lesson that generates its case, which case:
// the lesson's own (or a new one), this student's last case again, or the case
// of a seed the instructor gives.

#include <QDialog>
#include <QLineEdit>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/lesson/lesson_spec.h"
#include "core/lesson/results.h"

class QComboBox;
class QLabel;
class QGroupBox;
class QListWidget;
class QRadioButton;
class QPushButton;
class QSpinBox;
class QTimer;

namespace sulcus::ui {

class StartDialog : public QDialog {
 public:
  /// `lesson_dirs`: folders to list lessons from (the shipped ones first).
  StartDialog(std::vector<std::filesystem::path> lesson_dirs, ResultsPlace results,
              QWidget* parent = nullptr);

  std::string student() const;
  /// Why the typed name is refused ("" when it is not).
  QString name_problem() const;
  /// The names offered to pick from (a shared store offers none of the cohort's).
  std::vector<std::string> offered_students() const;
  std::filesystem::path lesson() const;
  /// Empty: the lesson's own mode.
  std::optional<LessonSpec::Mode> mode() const;
  /// A generated case's seed chosen here; empty: the lesson's own (its seed,
  /// or a new one drawn at the start when it says `seed: random`).
  std::optional<std::uint64_t> seed() const;
  /// The lessons listed, with the broken ones (for tests).
  struct Item {
    std::filesystem::path file;
    std::string title, description, errors;
    bool broken = false;
    CaseSpec generated_case;                 // .generated: the lesson draws its case
    std::optional<std::uint64_t> last_seed;  // this student's last attempt's case
  };
  const std::vector<Item>& items() const { return items_; }
  void SetStudent(const QString& name);
  bool SelectLesson(const std::filesystem::path& file);
  enum class CaseChoice { kOwn, kLast, kSeed };
  /// Chooses the case as a student would (`seed` for kSeed). False when the
  /// choice is not offered for the selected lesson.
  bool ChooseCase(CaseChoice choice, std::uint64_t seed = 0);
  void Refresh();
  /// While the page is open, `prepare` is called (a moment after the choice
  /// settles) with the lesson and case chosen, so its scene is prepared while the
  /// student types; `status` says how far that is, shown at the bottom.
  void SetPreparation(
      std::function<void(const std::filesystem::path&, std::optional<std::uint64_t>)>
          prepare,
      std::function<QString()> status);
  /// What the page says of the scene's preparation (for tests).
  QString preparation_text() const;
  /// Whether the store keeps a roster: the student picks a name from it and
  /// signs in with a passphrase (set at first use) to start.
  bool signs_in() const { return !roster_.empty(); }
  void SetPassphrase(const QString& passphrase);
  /// The sign-in's token once the student signed in (on Start), else "".
  const std::string& sign_in_token() const { return sign_in_token_; }
  /// Starts as the Start button does: signs the student in first when the store
  /// keeps a roster (a wrong passphrase or a name not on it says why, in red,
  /// and the page stays open). False when it stayed open.
  bool TryStart();

 private:
  std::vector<std::filesystem::path> dirs_;
  ResultsPlace results_db_;
  // Opened once: a shared store is not connected to again at every keystroke.
  // Null when it cannot be opened (the window says so when it stores).
  std::unique_ptr<ResultsStore> store_;
  std::vector<Item> items_;
  QComboBox* student_ = nullptr;
  QListWidget* list_ = nullptr;
  QLabel* about_ = nullptr;
  QLabel* name_problem_ = nullptr;   // why the typed name cannot be used
  QLineEdit* passphrase_ = nullptr;  // shown when the store keeps a roster
  QLabel* passphrase_label_ = nullptr;
  std::vector<std::string> roster_;
  std::string sign_in_token_;
  QRadioButton *own_mode_ = nullptr, *practice_ = nullptr, *assessment_ = nullptr;
  QPushButton* start_ = nullptr;
  QGroupBox* case_box_ = nullptr;
  QRadioButton *own_case_ = nullptr, *last_case_ = nullptr, *seed_case_ = nullptr;
  QSpinBox* case_seed_ = nullptr;
  std::function<void(const std::filesystem::path&, std::optional<std::uint64_t>)>
      prepare_;
  std::function<QString()> status_;
  QLabel* ready_ = nullptr;
  QTimer* settle_ = nullptr;
  void RequestPreparation();
  const Item* Current() const;  // the selected lesson, or null
  void ShowCase(const Item& it);
};

}  // namespace sulcus::ui
