#include "ui/start_dialog.h"

#include <QComboBox>
#include <QDialogButtonBox>
#include <QFileDialog>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QListWidget>
#include <QPushButton>
#include <QRadioButton>
#include <QSettings>
#include <QSpinBox>
#include <QTimer>
#include <QVBoxLayout>
#include <algorithm>

#include "core/base/names.h"
#include "core/base/text.h"
#include "core/lesson/results.h"
#include "core/lesson/sign_in.h"

namespace sulcus::ui {
namespace {

QString Q(const std::string& s) { return QString::fromStdString(s); }

}  // namespace

StartDialog::StartDialog(std::vector<std::filesystem::path> lesson_dirs,
                         ResultsPlace results, QWidget* parent)
    : QDialog(parent), dirs_(std::move(lesson_dirs)), results_db_(std::move(results)) {
  setWindowTitle("Sulcus: start a lesson");
  resize(760, 520);
  auto* layout = new QVBoxLayout(this);
  auto* title = new QLabel(
      "<h2>Sulcus</h2>Haptic dental training: periodontal probing and oral inspection. "
      "Say who you are, pick a lesson and start.");
  layout->addWidget(title);
  auto* form = new QFormLayout;
  student_ = new QComboBox;
  student_->setEditable(true);
  student_->setToolTip(
      "Your name: pick it, or type a new one. Your results are kept under it.");
  form->addRow("Student", student_);
  name_problem_ = new QLabel;
  name_problem_->setStyleSheet("color: #c02020");
  name_problem_->setWordWrap(true);
  name_problem_->hide();
  form->addRow("", name_problem_);
  passphrase_ = new QLineEdit;
  passphrase_->setEchoMode(QLineEdit::Password);
  passphrase_->setToolTip(
      "Your passphrase. The first time, choose one of at least 8 characters: it is "
      "yours from then on (your instructor can reset a forgotten one).");
  passphrase_label_ = new QLabel("Passphrase");
  form->addRow(passphrase_label_, passphrase_);
  passphrase_->hide();
  passphrase_label_->hide();
  layout->addLayout(form);
  list_ = new QListWidget;
  list_->setToolTip("The lessons shipped with Sulcus and your instructor's own.");
  layout->addWidget(list_, 1);
  about_ = new QLabel;
  about_->setWordWrap(true);
  about_->setMinimumHeight(60);
  about_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  layout->addWidget(about_);
  auto* modes = new QGroupBox("Mode");
  auto* mode_row = new QHBoxLayout(modes);
  own_mode_ = new QRadioButton("as the lesson says");
  practice_ = new QRadioButton("practice (the truth as you go, aids allowed)");
  assessment_ = new QRadioButton("assessment (no aids, the truth only in the report)");
  own_mode_->setChecked(true);
  for (QRadioButton* b : {own_mode_, practice_, assessment_}) mode_row->addWidget(b);
  layout->addWidget(modes);
  // Only for a lesson that draws its case: which one.
  case_box_ = new QGroupBox("Case");
  case_box_->setToolTip(
      "This lesson draws its patient's pockets, recession and bleeding from a seed: "
      "the same seed always gives the same case");
  auto* case_row = new QHBoxLayout(case_box_);
  own_case_ = new QRadioButton;
  last_case_ = new QRadioButton;
  last_case_->setToolTip(
      "Take the case of your last attempt at this lesson again, to see what you "
      "improved");
  seed_case_ = new QRadioButton("the case of seed");
  seed_case_->setToolTip(
      "The case your instructor gave you by its seed (the report of an attempt shows its "
      "seed)");
  case_seed_ = new QSpinBox;
  case_seed_->setRange(0, 2147483647);
  case_seed_->setValue(1);
  own_case_->setChecked(true);
  case_row->addWidget(own_case_);
  case_row->addWidget(last_case_);
  case_row->addWidget(seed_case_);
  case_row->addWidget(case_seed_);
  case_row->addStretch(1);
  connect(case_seed_, qOverload<int>(&QSpinBox::valueChanged), this,
          [this] { seed_case_->setChecked(true); });
  case_box_->hide();
  layout->addWidget(case_box_);
  ready_ = new QLabel;
  ready_->setWordWrap(true);
  ready_->setStyleSheet("color: #555");
  layout->addWidget(ready_);
  settle_ = new QTimer(this);
  settle_->setSingleShot(true);
  connect(settle_, &QTimer::timeout, this, [this] {
    const Item* it = Current();
    if (prepare_ && it && !it->broken) prepare_(it->file, seed());
  });
  for (QRadioButton* b : {own_case_, last_case_, seed_case_})
    connect(b, &QRadioButton::toggled, this, [this](bool on) {
      if (on) RequestPreparation();
    });
  connect(case_seed_, qOverload<int>(&QSpinBox::valueChanged), this,
          [this] { RequestPreparation(); });
  auto* buttons = new QDialogButtonBox;
  auto* folder =
      buttons->addButton("Instructor's folder...", QDialogButtonBox::ActionRole);
  folder->setToolTip("Add a folder of lesson files written by your instructor");
  start_ = buttons->addButton("Start the lesson", QDialogButtonBox::AcceptRole);
  buttons->addButton("Workbench (no lesson)", QDialogButtonBox::RejectRole);
  layout->addWidget(buttons);
  connect(buttons, &QDialogButtonBox::accepted, this, [this] { TryStart(); });
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  connect(folder, &QPushButton::clicked, this, [this] {
    const QString dir =
        QFileDialog::getExistingDirectory(this, "Instructor's lesson folder");
    if (dir.isEmpty()) return;
    QSettings().setValue("lessons/folder", dir);
    Refresh();
  });
  connect(list_, &QListWidget::currentRowChanged, this, [this](int row) {
    if (row < 0 || row >= static_cast<int>(items_.size())) return;
    const Item& it = items_[static_cast<std::size_t>(row)];
    about_->setText(
        it.broken ? "<b>This lesson file has errors</b> (tell your instructor):<br><tt>" +
                        Q(it.errors).toHtmlEscaped().replace("\n", "<br>") + "</tt>"
                  : Q(it.description).toHtmlEscaped());
    start_->setEnabled(!it.broken && name_problem_->isHidden());
    ShowCase(it);
    RequestPreparation();
  });
  connect(student_, &QComboBox::currentTextChanged, this, [this] { Refresh(); });
  // Who was here last.
  QSettings settings;
  try {
    store_ = OpenResults(results_db_);
    // A station's own store offers the names of those who used it. A lab's
    // shared store holds the whole cohort: each student types their name and
    // sees their own attempts only.
    // A store that keeps the class's roster offers its names: the student
    // picks theirs and signs in.
    roster_ = store_->Roster();
    if (!roster_.empty()) {
      for (const std::string& s : roster_) student_->addItem(Q(s));
      student_->setEditable(false);
      student_->setToolTip("Your name on the class's roster: pick it, then sign in.");
      passphrase_->show();
      passphrase_label_->show();
    } else if (results_db_.url.empty()) {
      for (const std::string& s : store_->Students()) student_->addItem(Q(s));
    }
  } catch (const ResultsError&) {
    // No database yet (or an unreadable one: the window reports it when storing).
    store_.reset();
  }
  const QString last = settings.value("student/last").toString();
  if (!last.isEmpty()) SetStudent(last);
  Refresh();
}

void StartDialog::SetPassphrase(const QString& passphrase) {
  passphrase_->setText(passphrase);
}

bool StartDialog::TryStart() {
  if (!start_->isEnabled()) return false;
  sign_in_token_.clear();
  if (signs_in()) {
    try {
      sign_in_token_ =
          SignIn(*store_, student(), passphrase_->text().toStdString()).token;
    } catch (const ResultsError& e) {
      QString why = Q(e.what());
      if (!why.isEmpty()) why[0] = why[0].toUpper();
      name_problem_->setText(why);
      name_problem_->show();
      passphrase_->clear();
      passphrase_->setFocus();
      return false;
    }
    passphrase_->clear();
  }
  accept();
  return true;
}

std::vector<std::string> StartDialog::offered_students() const {
  std::vector<std::string> names;
  for (int i = 0; i < student_->count(); ++i)
    names.push_back(student_->itemText(i).toStdString());
  return names;
}

void StartDialog::SetStudent(const QString& name) {
  const int at = student_->findText(name);
  if (at < 0 && signs_in()) return;  // (only names on the roster)
  if (at < 0) student_->addItem(name);
  student_->setCurrentIndex(student_->findText(name));
}

void StartDialog::Refresh() {
  // The name checked where it is typed: a name the results could not keep, or
  // would show wrongly, is refused here with the reason, never after the lesson.
  const std::string typed = student_->currentText().trimmed().toStdString();
  const std::string why = typed.empty() ? "" : NameProblem(student());
  name_problem_->setText(Q(why));
  name_problem_->setVisible(!why.empty());
  const int keep = list_->currentRow();
  items_.clear();
  list_->clear();
  std::vector<std::filesystem::path> dirs = dirs_;
  if (const QString extra = QSettings().value("lessons/folder").toString();
      !extra.isEmpty())
    dirs.push_back(extra.toStdString());
  std::vector<AttemptRow> attempts;
  try {
    if (store_) attempts = store_->Attempts(student());
  } catch (const ResultsError&) {
    // The shared store went away: the lessons are listed without last scores.
  }
  for (const auto& f : LessonFiles(dirs)) {
    Item it;
    it.file = std::filesystem::absolute(f).lexically_normal();
    try {
      const LessonSpec s = LoadLessonSpec(it.file);
      it.title =
          (s.name.empty() ? f.stem().string() : s.name) + "  (" + ToString(s.mode) + ")";
      it.description = s.description;
      it.generated_case = s.case_spec;
    } catch (const LoadError& e) {
      it.broken = true;
      it.title = f.filename().string() + " (broken)";
      it.errors = e.what();
    }
    std::string last;
    for (const AttemptRow& a : attempts)
      if (a.lesson_file == it.file.string()) {
        last = "  last score " + std::to_string(static_cast<int>(a.total + 0.5));
        it.last_seed =
            a.generated_case ? std::optional<std::uint64_t>(a.case_seed) : std::nullopt;
      }
    auto* item = new QListWidgetItem(Q(it.title + last));
    if (it.broken) item->setForeground(QColor(190, 30, 30));
    list_->addItem(item);
    items_.push_back(it);
  }
  if (!items_.empty())
    list_->setCurrentRow(keep >= 0 && keep < static_cast<int>(items_.size()) ? keep : 0);
  if (start_) {
    const Item* it = Current();
    start_->setEnabled(why.empty() && (!it || !it->broken));
  }
}

void StartDialog::SetPreparation(
    std::function<void(const std::filesystem::path&, std::optional<std::uint64_t>)>
        prepare,
    std::function<QString()> status) {
  prepare_ = std::move(prepare);
  status_ = std::move(status);
  auto* poll = new QTimer(this);
  connect(poll, &QTimer::timeout, this,
          [this] { ready_->setText(status_ ? status_() : QString()); });
  poll->start(250);
  RequestPreparation();
}

QString StartDialog::preparation_text() const { return ready_->text(); }

void StartDialog::RequestPreparation() {
  if (prepare_) settle_->start(400);
}

void StartDialog::ShowCase(const Item& it) {
  const CaseSpec& c = it.generated_case;
  case_box_->setVisible(!it.broken && c.generated);
  if (!c.generated) return;
  own_case_->setText(c.random_seed ? "a new case"
                                   : QString("the lesson's case (seed %1)").arg(c.seed));
  own_case_->setToolTip(
      c.random_seed ? "A case drawn for this attempt: its seed is kept with your result"
                    : "The case the lesson file names");
  last_case_->setEnabled(it.last_seed.has_value());
  last_case_->setText(it.last_seed
                          ? QString("my last case again (seed %1)").arg(*it.last_seed)
                          : QString("my last case again (none yet)"));
  if (!it.last_seed && last_case_->isChecked()) own_case_->setChecked(true);
}

const StartDialog::Item* StartDialog::Current() const {
  const int row = list_->currentRow();
  return row >= 0 && row < static_cast<int>(items_.size())
             ? &items_[static_cast<std::size_t>(row)]
             : nullptr;
}

bool StartDialog::ChooseCase(CaseChoice choice, std::uint64_t seed) {
  const Item* it = Current();
  if (!it || !it->generated_case.generated) return false;
  switch (choice) {
    case CaseChoice::kOwn:
      own_case_->setChecked(true);
      return true;
    case CaseChoice::kLast:
      if (!it->last_seed) return false;
      last_case_->setChecked(true);
      return true;
    case CaseChoice::kSeed:
      if (seed > static_cast<std::uint64_t>(case_seed_->maximum())) return false;
      case_seed_->setValue(static_cast<int>(seed));
      seed_case_->setChecked(true);
      return true;
  }
  return false;
}

std::optional<std::uint64_t> StartDialog::seed() const {
  const Item* it = Current();
  if (!it || !it->generated_case.generated) return std::nullopt;
  if (last_case_->isChecked() && it->last_seed) return it->last_seed;
  if (seed_case_->isChecked()) return static_cast<std::uint64_t>(case_seed_->value());
  return std::nullopt;
}

bool StartDialog::SelectLesson(const std::filesystem::path& file) {
  const auto want = std::filesystem::absolute(file).lexically_normal();
  for (std::size_t i = 0; i < items_.size(); ++i)
    if (items_[i].file == want) {
      list_->setCurrentRow(static_cast<int>(i));
      return true;
    }
  return false;
}

std::string StartDialog::student() const {
  // Trimmed and as Unicode composes it (NFC): one name, however the keyboard
  // spelled it (the same rule as the command line's).
  const std::string s = NormalName(student_->currentText().toStdString());
  return s.empty() ? "student" : s;
}

QString StartDialog::name_problem() const {
  return name_problem_->isHidden() ? QString() : name_problem_->text();
}

std::filesystem::path StartDialog::lesson() const {
  const Item* it = Current();
  return it ? it->file : std::filesystem::path();
}

std::optional<LessonSpec::Mode> StartDialog::mode() const {
  if (practice_->isChecked()) return LessonSpec::Mode::kPractice;
  if (assessment_->isChecked()) return LessonSpec::Mode::kAssessment;
  return std::nullopt;
}

}  // namespace sulcus::ui
