#pragma once
// The instructor's view, behind the passphrase: every student's attempts, the
// cohort's sites ranked by how wrong they are charted, export, and deleting a
// student's results.

#include <filesystem>
#include <string>

#include <QDialog>

class QTableWidget;
class QLabel;

namespace sulcus::ui {

class InstructorDialog : public QDialog {
 public:
  InstructorDialog(std::filesystem::path results_db, QWidget* parent = nullptr);
  void Refresh();
  int students() const { return students_; }
  const QTableWidget* attempts_table() const { return attempts_; }
  const QTableWidget* cohort_table() const { return cohort_; }
  /// Deletes a student's results (after the window asked to confirm).
  int DeleteStudent(const std::string& name);

 private:
  std::filesystem::path db_file_;
  QTableWidget* attempts_ = nullptr;
  QTableWidget* cohort_ = nullptr;
  QLabel* summary_ = nullptr;
  int students_ = 0;
};

}  // namespace sulcus::ui
