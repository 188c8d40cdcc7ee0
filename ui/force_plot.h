#pragma once
// The force along the probe and the torque of the last seconds as a VTK chart
// (vtkChartXY in a QVTKOpenGLNativeWidget), with the lesson's force band drawn
// as two lines: the same quantity, from the same snapshot, as the gauge.

#include <vtkSmartPointer.h>

#include <QWidget>
#include <array>
#include <deque>
#include <vector>

class QVTKOpenGLNativeWidget;
class vtkChartXY;
class vtkContextView;
class vtkTable;
class vtkPlot;

namespace sulcus::ui {

class ForcePlot : public QWidget {
 public:
  explicit ForcePlot(QWidget* parent = nullptr);
  ~ForcePlot() override;
  /// One sample; the chart redraws at most 10 times a second.
  void Push(double t_s, double force_n, double torque_nmm);
  void Clear();
  /// The whole window at once, oldest first, (t s, force N, torque N*mm): a
  /// replay shows the last 5 s up to its cursor (the right edge).
  void SetSamples(const std::vector<std::array<double, 3>>& samples);
  int rows() const;  // samples in the chart now
  /// The band of full credit (N), drawn as two lines.
  void SetBand(double low_n, double high_n);

 private:
  void Redraw();
  struct Sample {
    double t, f, tq;
  };
  std::deque<Sample> history_;
  double last_draw_ = -1, band_low_ = 0.15, band_high_ = 0.30;
  QVTKOpenGLNativeWidget* widget_;
  vtkSmartPointer<vtkContextView> view_;
  vtkSmartPointer<vtkChartXY> chart_;
  vtkSmartPointer<vtkTable> table_;
  std::vector<vtkPlot*> plots_;  // owned by the chart
};

}  // namespace sulcus::ui
