#pragma once
// The start page: who the student is (picked or added, remembered), the lessons
// shipped and the instructor's own folder, each with its description and this
// student's last score, broken lesson files listed as broken with their errors,
// and practice or assessment.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <QDialog>

#include "core/lesson/lesson_spec.h"

class QComboBox;
class QLabel;
class QListWidget;
class QRadioButton;
class QPushButton;

namespace sulcus::ui {

class StartDialog : public QDialog {
 public:
  /// `lesson_dirs`: folders to list lessons from (the shipped ones first).
  StartDialog(std::vector<std::filesystem::path> lesson_dirs, std::filesystem::path results_db,
              QWidget* parent = nullptr);

  std::string student() const;
  std::filesystem::path lesson() const;
  /// Empty: the lesson's own mode.
  std::optional<LessonSpec::Mode> mode() const;
  /// The lessons listed, with the broken ones (for tests).
  struct Item {
    std::filesystem::path file;
    std::string title, description, errors;
    bool broken = false;
  };
  const std::vector<Item>& items() const { return items_; }
  void SetStudent(const QString& name);
  bool SelectLesson(const std::filesystem::path& file);
  void Refresh();

 private:
  std::vector<std::filesystem::path> dirs_;
  std::filesystem::path results_db_;
  std::vector<Item> items_;
  QComboBox* student_ = nullptr;
  QListWidget* list_ = nullptr;
  QLabel* about_ = nullptr;
  QRadioButton *own_mode_ = nullptr, *practice_ = nullptr, *assessment_ = nullptr;
  QPushButton* start_ = nullptr;
};

}  // namespace sulcus::ui
