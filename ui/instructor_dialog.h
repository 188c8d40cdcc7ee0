#pragma once
// The instructor's view, behind the passphrase: every student's attempts, the
// cohort's sites ranked by how wrong they are charted, export, and deleting a
// student's results.

#include <QDialog>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/lesson/lesson_spec.h"
#include "core/lesson/results.h"

class QTableWidget;
class QLabel;
class QComboBox;
class QSpinBox;
class QPushButton;
class QTabWidget;

namespace sulcus::ui {

class ChartWidget;

class InstructorDialog : public QDialog {
 public:
  /// `lesson_dirs`: where the lessons a case can be drawn for are found.
  InstructorDialog(ResultsPlace results,
                   std::vector<std::filesystem::path> lesson_dirs = {},
                   QWidget* parent = nullptr);
  void Refresh();
  int students() const { return students_; }
  const QTableWidget* attempts_table() const { return attempts_; }
  const QTableWidget* cohort_table() const { return cohort_; }
  /// Each student's calibration against the target, and how many meet it.
  const QTableWidget* calibration_table() const { return calibration_; }
  int calibrated() const { return calibrated_; }
  /// Deletes a student's results (after the window asked to confirm).
  int DeleteStudent(const std::string& name);

  // A case drawn for a probing lesson (stage, extent, grade, seed), previewed as its
  // true chart and classification, saved as a scene of its own.
  /// Draws it; false (and the reason shown) when no such case fits the lesson's teeth.
  /// A grade (or stage IV) gives the case a patient drawn with it.
  bool DrawCase(const std::filesystem::path& lesson, Stage stage, Extent extent,
                std::uint64_t seed, Grade grade = Grade::kNone);
  /// Saves the drawn case; false (and the reason shown) when it cannot.
  bool SaveCase(const std::filesystem::path& scene_file);
  const ChartWidget* case_chart() const { return case_chart_; }
  QString case_summary() const;

 private:
  void BuildCaseTab(QTabWidget* tabs);
  ResultsPlace db_file_;
  QTableWidget* attempts_ = nullptr;
  QTableWidget* cohort_ = nullptr;
  QTableWidget* calibration_ = nullptr;
  int calibrated_ = 0;
  QLabel* summary_ = nullptr;
  int students_ = 0;
  std::vector<std::filesystem::path> lesson_dirs_;
  QComboBox *case_lesson_ = nullptr, *case_stage_ = nullptr, *case_extent_ = nullptr,
            *case_grade_ = nullptr;
  QSpinBox* case_seed_ = nullptr;
  QPushButton* case_save_ = nullptr;
  ChartWidget* case_chart_ = nullptr;
  QLabel* case_label_ = nullptr;
  std::optional<LessonSpec> case_spec_;  // the lesson the drawn case is for
  CaseSpec case_;
  std::uint64_t case_seed_value_ = 0;
};

}  // namespace sulcus::ui
