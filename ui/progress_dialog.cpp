#include "ui/progress_dialog.h"

#include <QVTKOpenGLNativeWidget.h>
#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkRenderer.h>
#include <vtkTable.h>

#include <QComboBox>
#include <QDialogButtonBox>
#include <QFileDialog>
#include <QHeaderView>
#include <QLabel>
#include <QPushButton>
#include <QTableWidget>
#include <QVBoxLayout>
#include <algorithm>
#include <fstream>
#include <map>

namespace sulcus::ui {
namespace {

QString Q(const std::string& s) { return QString::fromStdString(s); }

}  // namespace

ProgressDialog::ProgressDialog(ResultsPlace results, const std::string& student,
                               QWidget* parent)
    : QDialog(parent), db_file_(std::move(results)), student_(student) {
  setWindowTitle(Q("Progress: " + student));
  resize(980, 720);
  auto* layout = new QVBoxLayout(this);
  lesson_ = new QComboBox;
  layout->addWidget(lesson_);
  summary_ = new QLabel;
  summary_->setWordWrap(true);
  layout->addWidget(summary_);
  chart_widget_ = new QVTKOpenGLNativeWidget;
  chart_widget_->setMinimumHeight(260);
  auto window = vtkSmartPointer<vtkGenericOpenGLRenderWindow>::New();
  chart_widget_->setRenderWindow(window);
  view_ = vtkSmartPointer<vtkContextView>::New();
  view_->SetRenderWindow(window);
  view_->GetRenderer()->SetBackground(1, 1, 1);
  chart_ = vtkSmartPointer<vtkChartXY>::New();
  view_->GetScene()->AddItem(chart_);
  chart_->SetShowLegend(true);
  chart_->GetAxis(vtkAxis::BOTTOM)->SetTitle("attempt");
  chart_->GetAxis(vtkAxis::LEFT)->SetTitle("%");
  chart_->GetAxis(vtkAxis::LEFT)->SetBehavior(vtkAxis::FIXED);
  chart_->GetAxis(vtkAxis::LEFT)->SetRange(0, 100);
  table_ = vtkSmartPointer<vtkTable>::New();
  for (const char* name :
       {"attempt", "total score", "within 1 mm (%)", "force in band (%)"}) {
    auto c = vtkSmartPointer<vtkDoubleArray>::New();
    c->SetName(name);
    table_->AddColumn(c);
  }
  layout->addWidget(chart_widget_, 1);
  sites_ = new QTableWidget;
  sites_->setToolTip(
      "Charted minus true depth at each site, attempt by attempt: the sites that keep "
      "failing stand out");
  layout->addWidget(sites_, 1);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Close);
  auto* csv = buttons->addButton("Export CSV...", QDialogButtonBox::ActionRole);
  layout->addWidget(buttons);
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::hide);
  connect(csv, &QPushButton::clicked, this, [this] {
    const QString f =
        QFileDialog::getSaveFileName(this, "Export", Q(student_ + ".csv"), "CSV (*.csv)");
    if (f.isEmpty()) return;
    const auto db = OpenResults(db_file_);
    std::ofstream out(f.toStdString());
    ExportAttemptsCsv(
        db->Attempts(student_, lesson_->currentData().toString().toStdString()), out);
    std::ofstream sites(f.toStdString().substr(0, f.size() - 4) + "_sites.csv");
    ExportSitesCsv(db->Sites(student_, lesson_->currentData().toString().toStdString()),
                   sites);
  });
  // The lessons this student took.
  try {
    const auto db = OpenResults(db_file_);
    std::map<std::string, std::string> lessons;
    for (const AttemptRow& a : db->Attempts(student_))
      lessons[a.lesson_file] = a.lesson_name;
    for (const auto& [file, name] : lessons) lesson_->addItem(Q(name), Q(file));
  } catch (const ResultsError& e) {
    summary_->setText(Q(e.what()));
  }
  connect(lesson_, qOverload<int>(&QComboBox::currentIndexChanged), this,
          [this](int) { ShowLesson(lesson_->currentData().toString().toStdString()); });
  if (lesson_->count() > 0)
    ShowLesson(lesson_->currentData().toString().toStdString());
  else if (summary_->text().isEmpty())
    summary_->setText("No attempts yet.");
}

void ProgressDialog::ShowLesson(const std::string& lesson_file) {
  const auto db = OpenResults(db_file_);
  attempts_ = db->Attempts(student_, lesson_file);
  const std::vector<SiteRow> sites = db->Sites(student_, lesson_file);
  const int n = static_cast<int>(attempts_.size());
  table_->SetNumberOfRows(n);
  double sum = 0;
  int incomplete = 0;
  for (int i = 0; i < n; ++i) {
    incomplete += attempts_[i].complete ? 0 : 1;
    table_->SetValue(i, 0, i + 1);
    table_->SetValue(i, 1, attempts_[i].total);
    table_->SetValue(i, 2, attempts_[i].within_1mm_pct);
    table_->SetValue(i, 3, attempts_[i].force_in_band_pct);
    sum += attempts_[i].total;
  }
  table_->Modified();
  chart_->ClearPlots();
  const unsigned char colours[3][3] = {{31, 95, 168}, {58, 157, 74}, {224, 160, 32}};
  // An inspection has no sites: only its score is plotted.
  const bool probing = std::any_of(attempts_.begin(), attempts_.end(),
                                   [](const AttemptRow& a) { return a.sites_total > 0; });
  for (int c = 1; c <= (probing ? 3 : 1); ++c) {
    vtkPlot* p = chart_->AddPlot(n > 1 ? vtkChart::LINE : vtkChart::POINTS);
    p->SetInputData(table_, 0, c);
    p->SetColor(colours[c - 1][0], colours[c - 1][1], colours[c - 1][2], 255);
    p->SetWidth(2.5);
  }
  // Whole attempts on the axis: 0.5 to n + 0.5, ticks at each attempt (one
  // attempt is not an axis from 0.95 to 1.05).
  vtkAxis* x = chart_->GetAxis(vtkAxis::BOTTOM);
  x->SetBehavior(vtkAxis::FIXED);
  x->SetRange(0.5, n + 0.5);
  x->SetNotation(vtkAxis::FIXED_NOTATION);
  x->SetPrecision(0);
  if (n <= 12) {
    auto at = vtkSmartPointer<vtkDoubleArray>::New();
    for (int i = 1; i <= n; ++i) at->InsertNextValue(i);
    x->SetCustomTickPositions(at);
  } else {
    x->SetCustomTickPositions(nullptr);
  }
  chart_widget_->renderWindow()->Render();
  summary_->setText(QString("%1 attempts%4; mean score %2, last %3. Averages over many "
                            "attempts predict clinical "
                            "performance better than any single one.")
                        .arg(n)
                        .arg(n ? sum / n : 0, 0, 'f', 1)
                        .arg(n ? attempts_.back().total : 0, 0, 'f', 1)
                        .arg(incomplete
                                 ? QString(" (%1 incomplete, scored as far as they went)")
                                       .arg(incomplete)
                                 : QString()));
  // Sites x attempts, signed error of the charted depth.
  std::vector<std::pair<int, int>> keys;
  std::map<std::pair<std::int64_t, std::pair<int, int>>, int> err;
  for (const SiteRow& s : sites) {
    const std::pair<int, int> k{s.fdi, s.site};
    if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
    if (s.entered_mm) err[{s.attempt, k}] = *s.entered_mm - s.truth_mm;
  }
  sites_->clear();
  sites_->setRowCount(static_cast<int>(keys.size()));
  sites_->setColumnCount(n);
  QStringList rows, cols;
  for (const auto& k : keys)
    rows << QString("%1 %2").arg(k.first).arg(SiteCode(k.second));
  for (int i = 0; i < n; ++i) cols << QString("#%1").arg(i + 1);
  sites_->setVerticalHeaderLabels(rows);
  sites_->setHorizontalHeaderLabels(cols);
  for (int r = 0; r < static_cast<int>(keys.size()); ++r)
    for (int c = 0; c < n; ++c) {
      const auto it = err.find({attempts_[c].id, keys[r]});
      auto* item = new QTableWidgetItem(
          it == err.end()
              ? "-"
              : QString("%1%2").arg(it->second > 0 ? "+" : "").arg(it->second));
      if (it != err.end())
        item->setBackground(it->second == 0             ? QColor(200, 235, 200)
                            : std::abs(it->second) == 1 ? QColor(250, 225, 160)
                                                        : QColor(240, 170, 170));
      item->setTextAlignment(Qt::AlignCenter);
      sites_->setItem(r, c, item);
    }
  sites_->horizontalHeader()->setSectionResizeMode(QHeaderView::Stretch);
}

}  // namespace sulcus::ui
