#include "ui/instructor_dialog.h"

#include <QColor>
#include <QComboBox>
#include <QDialogButtonBox>
#include <QFileDialog>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QMessageBox>
#include <QPushButton>
#include <QRandomGenerator>
#include <QSpinBox>
#include <QTabWidget>
#include <QTableWidget>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>

#include "core/lesson/calibration.h"
#include "core/lesson/results.h"
#include "core/scene/scene.h"
#include "ui/chart_widget.h"

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

InstructorDialog::InstructorDialog(ResultsPlace results,
                                   std::vector<std::filesystem::path> lesson_dirs,
                                   QWidget* parent)
    : QDialog(parent),
      db_file_(std::move(results)),
      lesson_dirs_(std::move(lesson_dirs)) {
  setWindowTitle("Sulcus: instructor");
  resize(1000, 680);
  auto* layout = new QVBoxLayout(this);
  summary_ = new QLabel;
  layout->addWidget(summary_);
  auto* tabs = new QTabWidget;
  attempts_ = Table({"attempt", "student", "lesson", "started", "mode", "device", "score",
                     "within 1 mm", "force in band", "declared", "truth"});
  cohort_ = Table({"site", "attempts", "mean |charted - true| (mm)", "within 1 mm",
                   "signed bias (mm)"});
  cohort_->setToolTip(
      "The sites the cohort charts worst, across every attempt of every student");
  calibration_ = Table({"student", "sites charted", "within 1 mm", "weighted kappa",
                        "signed bias (mm)", "interdental bias (mm)",
                        "deep-site bias (mm)", "target"});
  calibration_->setToolTip(
      "Each student's charted depths over all their attempts against the truth; the "
      "target examiners are calibrated to: within 1 mm at 90 % of sites or more and a "
      "weighted kappa above 0.6");
  tabs->addTab(attempts_, "Every attempt");
  tabs->addTab(cohort_, "The cohort's sites");
  tabs->addTab(calibration_, "Calibration");
  BuildCaseTab(tabs);
  layout->addWidget(tabs, 1);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Close);
  auto* csv =
      buttons->addButton("Export every attempt (CSV)...", QDialogButtonBox::ActionRole);
  auto* del = buttons->addButton("Delete the selected student's results...",
                                 QDialogButtonBox::DestructiveRole);
  layout->addWidget(buttons);
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::close);
  connect(csv, &QPushButton::clicked, this, [this] {
    const QString f =
        QFileDialog::getSaveFileName(this, "Export", "cohort.csv", "CSV (*.csv)");
    if (f.isEmpty()) return;
    const auto db = OpenResults(db_file_);
    std::ofstream out(f.toStdString());
    ExportAttemptsCsv(db->Attempts(), out);
    std::ofstream sites(f.toStdString().substr(0, f.size() - 4) + "_sites.csv");
    ExportSitesCsv(db->Sites(), sites);
  });
  connect(del, &QPushButton::clicked, this, [this] {
    const int row = attempts_->currentRow();
    if (row < 0) return;
    const std::string name = attempts_->item(row, 1)->text().toStdString();
    if (QMessageBox::question(this, "Delete results",
                              Q("Delete every result of " + name +
                                "? Their recordings and reports stay on disk.")) ==
        QMessageBox::Yes)
      DeleteStudent(name);
  });
  Refresh();
}

void InstructorDialog::BuildCaseTab(QTabWidget* tabs) {
  auto* page = new QWidget;
  auto* layout = new QVBoxLayout(page);
  layout->addWidget(
      new QLabel("Draw a periodontitis case on a probing lesson's teeth: pockets, "
                 "recession and bleeding until the true chart "
                 "classifies as asked (2017 classification). Preview its chart, then "
                 "save it as a scene that lessons can use."));
  auto* form = new QFormLayout;
  case_lesson_ = new QComboBox;
  for (const std::filesystem::path& f : LessonFiles(lesson_dirs_)) {
    try {
      const LessonSpec spec = LoadLessonSpec(f);
      case_lesson_->addItem(Q(spec.name + "  (" + f.filename().string() + ")"),
                            Q(f.string()));
    } catch (const std::exception&) {
      // broken lessons are listed as broken on the start page; a case needs one that
      // loads
    }
  }
  case_stage_ = new QComboBox;
  case_stage_->addItems({"I", "II", "III", "IV"});
  case_stage_->setCurrentIndex(2);
  case_extent_ = new QComboBox;
  case_extent_->addItems({"localized", "generalized"});
  case_grade_ = new QComboBox;
  case_grade_->addItems({"not assessed", "A", "B", "C"});
  case_grade_->setToolTip(
      "A grade (or stage IV) gives the case a patient: age, smoking, diabetes, teeth "
      "lost, the bite");
  case_seed_ = new QSpinBox;
  case_seed_->setRange(0, 2147483647);
  case_seed_->setValue(1);
  case_seed_->setToolTip(
      "The same lesson, stage, extent and seed always draw the same case");
  auto* seed_row = new QHBoxLayout;
  auto* reseed = new QPushButton("Another");
  reseed->setToolTip("A new seed: another case of the same stage and extent");
  seed_row->addWidget(case_seed_, 1);
  seed_row->addWidget(reseed);
  form->addRow("Lesson", case_lesson_);
  form->addRow("Stage", case_stage_);
  form->addRow("Extent", case_extent_);
  form->addRow("Grade", case_grade_);
  form->addRow("Seed", seed_row);
  layout->addLayout(form);
  auto* buttons = new QHBoxLayout;
  auto* draw = new QPushButton("Draw the case");
  case_save_ = new QPushButton("Save as a scene...");
  case_save_->setEnabled(false);
  buttons->addWidget(draw);
  buttons->addWidget(case_save_);
  buttons->addStretch(1);
  layout->addLayout(buttons);
  case_label_ = new QLabel;
  case_label_->setWordWrap(true);
  case_label_->setTextFormat(Qt::RichText);
  layout->addWidget(case_label_);
  case_chart_ = new ChartWidget;
  layout->addWidget(case_chart_, 1);
  auto redraw = [this] {
    if (case_lesson_->currentIndex() < 0) return;
    DrawCase(
        case_lesson_->currentData().toString().toStdString(),
        *StageFromString(case_stage_->currentText().toStdString()),
        *ExtentFromString(case_extent_->currentText().toStdString()),
        static_cast<std::uint64_t>(case_seed_->value()),
        GradeFromString(case_grade_->currentText().toStdString()).value_or(Grade::kNone));
  };
  connect(draw, &QPushButton::clicked, this, redraw);
  connect(reseed, &QPushButton::clicked, this, [this, redraw] {
    case_seed_->setValue(
        static_cast<int>(QRandomGenerator::global()->bounded(1, 999999)));
    redraw();
  });
  connect(case_save_, &QPushButton::clicked, this, [this] {
    if (!case_spec_) return;
    const std::filesystem::path scene = case_spec_->scene;
    const std::string name =
        scene.stem().string() + "_stage_" + ToString(case_.stage) + "_" +
        ToString(case_.extent) +
        (case_.grade == Grade::kNone ? std::string()
                                     : std::string("_grade_") + ToString(case_.grade)) +
        "_" + std::to_string(case_seed_value_) + ".yaml";
    const QString f = QFileDialog::getSaveFileName(
        this, "Save the case as a scene", Q((scene.parent_path() / name).string()),
        "Scenes (*.yaml)");
    if (!f.isEmpty()) SaveCase(f.toStdString());
  });
  tabs->addTab(page, "Cases");
}

bool InstructorDialog::DrawCase(const std::filesystem::path& lesson, Stage stage,
                                Extent extent, std::uint64_t seed, Grade grade) {
  case_spec_.reset();
  case_save_->setEnabled(false);
  try {
    LessonSpec spec = LoadLessonSpec(lesson);
    CaseSpec c;
    c.generated = true;
    c.stage = stage;
    c.extent = extent;
    c.grade = grade;
    c.seed = seed;
    const SceneSpec scene = ApplyCase(LoadSceneSpec(spec.scene), spec.teeth, c, seed);
    const PerioChart truth = TrueChart(scene, spec.teeth);
    const Diagnosis d = Classify2017(truth);
    case_chart_->ShowChart(truth);
    QString path;
    for (const std::string& step : d.path)
      path += "<li>" + Q(step).toHtmlEscaped() + "</li>";
    case_label_->setText(QString("<b>%1</b> on %2 (seed %3)<ul>%4</ul>")
                             .arg(Q(d.Summary()).toHtmlEscaped(),
                                  Q(spec.scene.filename().string()).toHtmlEscaped())
                             .arg(seed)
                             .arg(path));
    // The form says what was drawn (also when drawn by a call, not the form).
    int index = case_lesson_->findData(Q(lesson.string()));
    if (index < 0) {
      case_lesson_->addItem(Q(spec.name + "  (" + lesson.filename().string() + ")"),
                            Q(lesson.string()));
      index = case_lesson_->count() - 1;
    }
    case_lesson_->setCurrentIndex(index);
    case_stage_->setCurrentText(ToString(stage));
    case_extent_->setCurrentText(ToString(extent));
    case_grade_->setCurrentIndex(grade == Grade::kNone ? 0 : static_cast<int>(grade));
    case_seed_->setValue(static_cast<int>(seed));
    case_spec_ = std::move(spec);
    case_ = c;
    case_seed_value_ = seed;
    case_save_->setEnabled(true);
    return true;
  } catch (const std::exception& e) {
    case_label_->setText(QString("<span style='color:#c02020'>No case drawn: %1</span>")
                             .arg(Q(e.what()).toHtmlEscaped()));
    return false;
  }
}

bool InstructorDialog::SaveCase(const std::filesystem::path& scene_file) {
  if (!case_spec_) return false;
  try {
    SaveCaseScene(*case_spec_, case_, case_seed_value_, scene_file);
    case_label_->setText(case_label_->text() +
                         QString("Saved as <b>%1</b>. A lesson uses it with <tt>scene: "
                                 "%2</tt> (and no <tt>case:</tt>).")
                             .arg(Q(scene_file.string()).toHtmlEscaped(),
                                  Q(scene_file.filename().string()).toHtmlEscaped()));
    return true;
  } catch (const std::exception& e) {
    case_label_->setText(case_label_->text() +
                         QString("<span style='color:#c02020'>Not saved: %1</span>")
                             .arg(Q(e.what()).toHtmlEscaped()));
    return false;
  }
}

QString InstructorDialog::case_summary() const {
  return case_label_ ? case_label_->text() : QString();
}

int InstructorDialog::DeleteStudent(const std::string& name) {
  const auto db = OpenResults(db_file_);
  const int n = db->DeleteStudent(name);
  Refresh();
  return n;
}

void InstructorDialog::Refresh() {
  const auto db = OpenResults(db_file_);
  const auto attempts = db->Attempts();
  students_ = static_cast<int>(db->Students().size());
  attempts_->setRowCount(static_cast<int>(attempts.size()));
  for (int r = 0; r < static_cast<int>(attempts.size()); ++r) {
    const AttemptRow& a = attempts[static_cast<std::size_t>(r)];
    // An inspection has no sites and no diagnosis, an attempt that probed
    // nothing has no agreement: those cells say so ("-").
    const bool sites = a.sites_total > 0, read = a.sites_read > 0;
    const QStringList cells = {
        QString::number(a.id), Q(a.student), Q(a.lesson_name), Q(a.started), Q(a.mode),
        // Scripted and replayed attempts are demonstrations, not a student's work.
        // A lab's store says whether the student signed in for it.
        a.device.empty() ? QString("-")
        : a.device == "scripted" || a.device == "replay"
            ? Q(a.device) + " (demonstration)"
        : a.signed_in           ? Q(a.device) + ", signed in"
        : !db_file_.url.empty() ? Q(a.device) + ", not signed in"
                                : Q(a.device),
        QString::number(a.total, 'f', 1) + (a.complete ? "" : " (incomplete)"),
        sites && a.sites_charted > 0 ? QString("%1 %").arg(a.within_1mm_pct, 0, 'f', 0)
                                     : QString("-"),
        sites && read ? QString("%1 %").arg(a.force_in_band_pct, 0, 'f', 0)
                      : QString("-"),
        sites ? Q(a.declared_dx) : QString("-"), sites ? Q(a.true_dx) : QString("-")};
    for (int c = 0; c < cells.size(); ++c) {
      auto* item = new QTableWidgetItem(cells[c]);
      if (!a.complete) {
        item->setForeground(QColor(150, 90, 0));
        item->setToolTip(QString("Incomplete: %1").arg(Q(a.ended)));
      }
      attempts_->setItem(r, c, item);
    }
  }
  // Each student's calibration over their attempts, against the target.
  std::vector<ChartedSite> charted;
  const std::vector<SiteRow> site_rows = db->Sites();
  for (const SiteRow& s : site_rows)
    if (s.entered_mm)
      charted.push_back({s.student, s.fdi, s.site, *s.entered_mm, s.truth_mm});
  const std::vector<ExaminerCalibration> cal = CohortCalibration(charted);
  calibration_->setRowCount(static_cast<int>(cal.size()));
  int on_target = 0;
  for (int r = 0; r < static_cast<int>(cal.size()); ++r) {
    const Agreement& g = cal[static_cast<std::size_t>(r)].depths;
    on_target += g.MeetsTarget();
    auto mm = [](const Bias& b) {
      return b.mean_mm() ? QString::asprintf("%+.2f", *b.mean_mm()) : QString("-");
    };
    const QStringList cells = {
        Q(cal[static_cast<std::size_t>(r)].student),
        QString::number(g.sites),
        QString("%1 %").arg(g.within_1mm_pct, 0, 'f', 0),
        g.depth_kappa ? QString::number(*g.depth_kappa, 'f', 2) : QString("-"),
        mm(g.all),
        mm(g.interdental),
        mm(g.deep),
        g.MeetsTarget() ? QString("met") : QString("not met")};
    for (int c = 0; c < cells.size(); ++c) {
      auto* item = new QTableWidgetItem(cells[c]);
      if (c == cells.size() - 1 && !g.MeetsTarget())
        item->setForeground(QColor(190, 40, 40));
      calibration_->setItem(r, c, item);
    }
  }
  calibrated_ = on_target;
  // Sites across the cohort, worst first.
  struct Acc {
    int n = 0, within = 0;
    double abs = 0, signed_sum = 0;
  };
  std::map<std::pair<int, int>, Acc> acc;
  for (const SiteRow& s : site_rows) {
    if (!s.entered_mm) continue;
    Acc& a = acc[{s.fdi, s.site}];
    const int e = *s.entered_mm - s.truth_mm;
    ++a.n;
    a.within += std::abs(e) <= 1;
    a.abs += std::abs(e);
    a.signed_sum += e;
  }
  std::vector<std::pair<std::pair<int, int>, Acc>> rows(acc.begin(), acc.end());
  std::sort(rows.begin(), rows.end(), [](const auto& x, const auto& y) {
    return x.second.abs / x.second.n > y.second.abs / y.second.n;
  });
  cohort_->setRowCount(static_cast<int>(rows.size()));
  for (int r = 0; r < static_cast<int>(rows.size()); ++r) {
    const auto& [key, a] = rows[static_cast<std::size_t>(r)];
    const QStringList cells = {QString("%1 %2").arg(key.first).arg(SiteCode(key.second)),
                               QString::number(a.n), QString::number(a.abs / a.n, 'f', 2),
                               QString("%1 %").arg(100.0 * a.within / a.n, 0, 'f', 0),
                               QString("%1").arg(a.signed_sum / a.n, 0, 'f', 2)};
    for (int c = 0; c < cells.size(); ++c)
      cohort_->setItem(r, c, new QTableWidgetItem(cells[c]));
  }
  summary_->setText(QString("%1 %2, %3 %4. %5%6")
                        .arg(students_)
                        .arg(students_ == 1 ? "student" : "students")
                        .arg(attempts.size())
                        .arg(attempts.size() == 1 ? "attempt" : "attempts")
                        .arg(rows.empty() ? QString()
                                          : QString("The site charted worst: %1. ")
                                                .arg(cohort_->item(0, 0)->text()))
                        .arg(cal.empty() ? QString()
                                         : QString("%1 of %2 students on the calibration "
                                                   "target.")
                                               .arg(on_target)
                                               .arg(cal.size())));
}

}  // namespace sulcus::ui
