#include "ui/instructor_dialog.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>

#include <QDialogButtonBox>
#include <QFileDialog>
#include <QHeaderView>
#include <QLabel>
#include <QMessageBox>
#include <QPushButton>
#include <QTabWidget>
#include <QTableWidget>
#include <QVBoxLayout>

#include "core/lesson/results.h"

namespace sulcus::ui {
namespace {

QString Q(const std::string& s) { return QString::fromStdString(s); }

QTableWidget* Table(const QStringList& headers) {
  auto* t = new QTableWidget;
  t->setColumnCount(headers.size());
  t->setHorizontalHeaderLabels(headers);
  t->setEditTriggers(QAbstractItemView::NoEditTriggers);
  t->setSelectionBehavior(QAbstractItemView::SelectRows);
  t->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  t->horizontalHeader()->setStretchLastSection(true);
  return t;
}

}  // namespace

InstructorDialog::InstructorDialog(std::filesystem::path results_db, QWidget* parent)
    : QDialog(parent), db_file_(std::move(results_db)) {
  setWindowTitle("Sulcus: instructor");
  resize(1000, 680);
  auto* layout = new QVBoxLayout(this);
  summary_ = new QLabel;
  layout->addWidget(summary_);
  auto* tabs = new QTabWidget;
  attempts_ = Table({"attempt", "student", "lesson", "started", "mode", "score", "within 1 mm", "force in band",
                     "declared", "truth"});
  cohort_ = Table({"site", "attempts", "mean |charted - true| (mm)", "within 1 mm", "signed bias (mm)"});
  cohort_->setToolTip("The sites the cohort charts worst, across every attempt of every student");
  tabs->addTab(attempts_, "Every attempt");
  tabs->addTab(cohort_, "The cohort's sites");
  layout->addWidget(tabs, 1);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Close);
  auto* csv = buttons->addButton("Export every attempt (CSV)...", QDialogButtonBox::ActionRole);
  auto* del = buttons->addButton("Delete the selected student's results...", QDialogButtonBox::DestructiveRole);
  layout->addWidget(buttons);
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::close);
  connect(csv, &QPushButton::clicked, this, [this] {
    const QString f = QFileDialog::getSaveFileName(this, "Export", "cohort.csv", "CSV (*.csv)");
    if (f.isEmpty()) return;
    ResultsDb db(db_file_);
    std::ofstream out(f.toStdString());
    ExportAttemptsCsv(db.Attempts(), out);
    std::ofstream sites(f.toStdString().substr(0, f.size() - 4) + "_sites.csv");
    ExportSitesCsv(db.Sites(), sites);
  });
  connect(del, &QPushButton::clicked, this, [this] {
    const int row = attempts_->currentRow();
    if (row < 0) return;
    const std::string name = attempts_->item(row, 1)->text().toStdString();
    if (QMessageBox::question(this, "Delete results",
                              Q("Delete every result of " + name + "? Their recordings and reports stay on disk.")) ==
        QMessageBox::Yes)
      DeleteStudent(name);
  });
  Refresh();
}

int InstructorDialog::DeleteStudent(const std::string& name) {
  ResultsDb db(db_file_);
  const int n = db.DeleteStudent(name);
  Refresh();
  return n;
}

void InstructorDialog::Refresh() {
  ResultsDb db(db_file_);
  const auto attempts = db.Attempts();
  students_ = static_cast<int>(db.Students().size());
  attempts_->setRowCount(static_cast<int>(attempts.size()));
  for (int r = 0; r < static_cast<int>(attempts.size()); ++r) {
    const AttemptRow& a = attempts[static_cast<std::size_t>(r)];
    const QStringList cells = {QString::number(a.id), Q(a.student), Q(a.lesson_name), Q(a.started), Q(a.mode),
                               QString::number(a.total, 'f', 1), QString("%1 %").arg(a.within_1mm_pct, 0, 'f', 0),
                               QString("%1 %").arg(a.force_in_band_pct, 0, 'f', 0), Q(a.declared_dx), Q(a.true_dx)};
    for (int c = 0; c < cells.size(); ++c) attempts_->setItem(r, c, new QTableWidgetItem(cells[c]));
  }
  // Sites across the cohort, worst first.
  struct Acc {
    int n = 0, within = 0;
    double abs = 0, signed_sum = 0;
  };
  std::map<std::pair<int, int>, Acc> acc;
  for (const SiteRow& s : db.Sites()) {
    if (!s.entered_mm) continue;
    Acc& a = acc[{s.fdi, s.site}];
    const int e = *s.entered_mm - s.truth_mm;
    ++a.n;
    a.within += std::abs(e) <= 1;
    a.abs += std::abs(e);
    a.signed_sum += e;
  }
  std::vector<std::pair<std::pair<int, int>, Acc>> rows(acc.begin(), acc.end());
  std::sort(rows.begin(), rows.end(), [](const auto& x, const auto& y) { return x.second.abs / x.second.n > y.second.abs / y.second.n; });
  cohort_->setRowCount(static_cast<int>(rows.size()));
  for (int r = 0; r < static_cast<int>(rows.size()); ++r) {
    const auto& [key, a] = rows[static_cast<std::size_t>(r)];
    const QStringList cells = {QString("%1 %2").arg(key.first).arg(SiteCode(key.second)), QString::number(a.n),
                               QString::number(a.abs / a.n, 'f', 2), QString("%1 %").arg(100.0 * a.within / a.n, 0, 'f', 0),
                               QString("%1").arg(a.signed_sum / a.n, 0, 'f', 2)};
    for (int c = 0; c < cells.size(); ++c) cohort_->setItem(r, c, new QTableWidgetItem(cells[c]));
  }
  summary_->setText(QString("%1 students, %2 attempts. %3")
                        .arg(students_)
                        .arg(attempts.size())
                        .arg(rows.empty() ? QString()
                                          : QString("The site charted worst: %1.").arg(cohort_->item(0, 0)->text())));
}

}  // namespace sulcus::ui
