#include "ui/force_plot.h"

#include <QVTKOpenGLNativeWidget.h>
#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkPlot.h>
#include <vtkRenderer.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>

#include <QVBoxLayout>

namespace sulcus::ui {
namespace {

constexpr double kHistoryS = 5.0;

}  // namespace

ForcePlot::ForcePlot(QWidget* parent)
    : QWidget(parent), widget_(new QVTKOpenGLNativeWidget(this)) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(widget_);
  setMinimumHeight(150);
  auto window = vtkSmartPointer<vtkGenericOpenGLRenderWindow>::New();
  widget_->setRenderWindow(window);
  view_ = vtkSmartPointer<vtkContextView>::New();
  view_->SetRenderWindow(window);
  view_->GetRenderer()->SetBackground(0.14, 0.15, 0.17);
  chart_ = vtkSmartPointer<vtkChartXY>::New();
  view_->GetScene()->AddItem(chart_);
  table_ = vtkSmartPointer<vtkTable>::New();
  for (const char* name : {"t (s)", "force along the probe (N)", "torque (N*m x 10)",
                           "band low (N)", "band high (N)"}) {
    auto column = vtkSmartPointer<vtkDoubleArray>::New();
    column->SetName(name);
    table_->AddColumn(column);
  }
  chart_->SetShowLegend(false);
  chart_->GetLegend()->GetLabelProperties()->SetColor(0.1, 0.1,
                                                      0.12);  // on the legend's white box
  // Top left, over the oldest seconds: the newest (right) stay visible.
  chart_->GetLegend()->SetHorizontalAlignment(vtkChartLegend::LEFT);
  chart_->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);
  for (int axis : {vtkAxis::LEFT, vtkAxis::BOTTOM}) {
    chart_->GetAxis(axis)->GetLabelProperties()->SetColor(0.8, 0.8, 0.8);
    chart_->GetAxis(axis)->GetTitleProperties()->SetColor(0.8, 0.8, 0.8);
  }
  chart_->GetAxis(vtkAxis::BOTTOM)->SetTitle("seconds ago");
  chart_->GetAxis(vtkAxis::LEFT)->SetTitle("N");
  struct Line {
    int column;
    unsigned char r, g, b;
    float width;
  };
  for (const Line& l : {Line{1, 110, 190, 255, 2.5f}, Line{2, 170, 170, 170, 1.0f},
                        Line{3, 70, 170, 90, 1.0f}, Line{4, 70, 170, 90, 1.0f}}) {
    vtkPlot* plot = chart_->AddPlot(vtkChart::LINE);
    plots_.push_back(plot);
    plot->SetVisible(false);  // until there are two points to draw
    plot->SetInputData(table_, 0, l.column);
    plot->SetColor(l.r, l.g, l.b, 255);
    plot->SetWidth(l.width);
  }
}

ForcePlot::~ForcePlot() = default;

void ForcePlot::Push(double t, double f, double tq) {
  if (!history_.empty() && t < history_.back().t) history_.clear();  // a new session
  history_.push_back({t, f, tq});
  while (!history_.empty() && history_.front().t < t - kHistoryS) history_.pop_front();
  if (t - last_draw_ >= 0.1 || t < last_draw_) {
    last_draw_ = t;
    Redraw();
  }
}

void ForcePlot::SetSamples(const std::vector<std::array<double, 3>>& samples) {
  history_.clear();
  for (const auto& s : samples) history_.push_back({s[0], s[1], s[2]});
  last_draw_ = samples.empty() ? -1 : samples.back()[0];
  Redraw();
}

void ForcePlot::Clear() {
  history_.clear();
  last_draw_ = -1;
  table_->SetNumberOfRows(0);
  Redraw();
}

void ForcePlot::SetBand(double low_n, double high_n) {
  band_low_ = low_n;
  band_high_ = high_n;
}

int ForcePlot::rows() const { return static_cast<int>(table_->GetNumberOfRows()); }

void ForcePlot::Redraw() {
  // At most a few hundred rows: one every 20 ms of the last 5 s.
  table_->SetNumberOfRows(0);
  if (history_.size() >= 2) {  // a line needs two points
    const double now = history_.back().t;
    double next = history_.front().t;
    double last_t = -1e300;
    for (const Sample& s : history_) {
      if ((s.t < next && &s != &history_.back()) || s.t <= last_t) continue;
      last_t = s.t;
      next = s.t + 0.02;
      const vtkIdType row = table_->InsertNextBlankRow();
      table_->SetValue(row, 0, s.t - now);
      table_->SetValue(row, 1, s.f);
      table_->SetValue(row, 2, s.tq / 100.0);
      table_->SetValue(row, 3, band_low_);
      table_->SetValue(row, 4, band_high_);
    }
  }
  table_->Modified();
  const bool drawable = table_->GetNumberOfRows() >= 2;
  for (vtkPlot* p : plots_) p->SetVisible(drawable);
  chart_->SetShowLegend(drawable);
  chart_->GetAxis(vtkAxis::BOTTOM)->SetRange(-kHistoryS, 0);
  chart_->GetAxis(vtkAxis::BOTTOM)->SetBehavior(vtkAxis::FIXED);
  widget_->renderWindow()->Render();
}

}  // namespace sulcus::ui
