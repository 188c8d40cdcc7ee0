#pragma once
// A student's progress over attempts, from the results database: per lesson the
// total score, depth agreement within 1 mm and force in band per attempt (a VTK
// chart), and the signed error of every site in every attempt (which sites keep
// failing), with CSV export.

#include <vtkSmartPointer.h>

#include <QDialog>
#include <filesystem>
#include <string>
#include <vector>

#include "core/lesson/results.h"

class QComboBox;
class QTableWidget;
class QLabel;
class QVTKOpenGLNativeWidget;
class vtkChartXY;
class vtkContextView;
class vtkTable;

namespace sulcus::ui {

class ProgressDialog : public QDialog {
 public:
  ProgressDialog(ResultsPlace results, const std::string& student,
                 QWidget* parent = nullptr);
  void ShowLesson(const std::string& lesson_file);
  int attempts_shown() const { return static_cast<int>(attempts_.size()); }
  const QTableWidget* sites_table() const { return sites_; }

 private:
  ResultsPlace db_file_;
  std::string student_;
  std::vector<AttemptRow> attempts_;
  QComboBox* lesson_ = nullptr;
  QLabel* summary_ = nullptr;
  QTableWidget* sites_ = nullptr;
  QVTKOpenGLNativeWidget* chart_widget_ = nullptr;
  vtkSmartPointer<vtkContextView> view_;
  vtkSmartPointer<vtkChartXY> chart_;
  vtkSmartPointer<vtkTable> table_;
};

}  // namespace sulcus::ui
