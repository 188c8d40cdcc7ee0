#include "ui/chart_widget.h"

#include <QKeyEvent>
#include <QMouseEvent>
#include <QPainter>
#include <QScrollArea>
#include <algorithm>
#include <cmath>

#include "core/lesson/lesson_spec.h"

namespace sulcus::ui {
namespace {

constexpr int kCell = 24, kRowH = 20, kLabelW = 78, kToothGap = 6, kBandTitle = 18,
              kHeader = 18;
constexpr int kRows = 5;  // PD, recession, CAL, bleeding, truth (practice)
const char* const kRowNames[kRows] = {"PD mm", "GM mm", "CAL mm", "bleeding",
                                      "true PD mm"};

// Cells of a tooth in a band, left to right: distal, middle, mesial mirrored so
// that the cell nearest the midline is the mesial one.
std::array<int, 3> CellSites(int fdi, bool buccal) {
  const bool right = fdi / 10 == 1 || fdi / 10 == 4;
  if (buccal) return right ? std::array{2, 1, 0} : std::array{0, 1, 2};
  return right ? std::array{5, 4, 3} : std::array{3, 4, 5};
}

int Rank(int fdi) {
  const int q = fdi / 10, p = fdi % 10;
  return (q == 1 || q == 4) ? 10 - p : 10 + p;
}

}  // namespace

ChartWidget::ChartWidget(QWidget* parent) : QWidget(parent) {
  setFocusPolicy(Qt::StrongFocus);
  setToolTip(
      "The periodontal chart. Type the depth you read (whole mm) and it moves to the "
      "next site; B or Space marks bleeding on the site just entered; Backspace goes "
      "back. 10 mm and over: + then the second digit (+ 2 is 12 mm); a depth over 12 mm "
      "asks you to confirm it with Enter (Esc cancels). GM: the gingival margin, "
      "positive where it lies apical to the CEJ (recession), negative where the "
      "gingiva is enlarged. CAL = PD + GM. The true PD shows (practice) at a site you "
      "probed and charted.");
}

std::vector<ChartWidget::Band> ChartWidget::MakeBands(bool wrap) const {
  std::vector<Band> bands;
  for (bool upper : {true, false}) {
    std::vector<int> t;
    for (int fdi : teeth_)
      if ((fdi / 10 <= 2) == upper) t.push_back(fdi);
    std::sort(t.begin(), t.end(), [](int a, int b) { return Rank(a) < Rank(b); });
    if (t.empty()) continue;
    // Upper: buccal then palatal; lower: lingual then buccal (as the chart is read).
    const std::array<bool, 2> surfaces =
        upper ? std::array{true, false} : std::array{false, true};
    if (!wrap) {
      for (bool buccal : surfaces) bands.push_back({upper, buccal, t, ""});
      continue;
    }
    // Split at the midline: the patient's right (quadrants 1 and 4) first.
    std::vector<int> right, left;
    for (int fdi : t) (fdi / 10 == 1 || fdi / 10 == 4 ? right : left).push_back(fdi);
    for (const auto& [half, teeth] :
         {std::pair{"right", right}, std::pair{"left", left}}) {
      if (teeth.empty()) continue;
      for (bool buccal : surfaces) bands.push_back({upper, buccal, teeth, half});
    }
  }
  return bands;
}

QSize ChartWidget::NaturalSize(const std::vector<Band>& bands) const {
  int teeth = 1;
  for (const Band& b : bands)
    teeth = std::max<int>(teeth, static_cast<int>(b.teeth.size()));
  return {
      kLabelW + teeth * (3 * kCell + kToothGap) + 8,
      static_cast<int>(bands.size()) * (kBandTitle + kHeader + rows() * kRowH + 6) + 8};
}

bool ChartWidget::WrapFor(int width) const {
  // A whole arch (more than 8 teeth in a row) shrunk below 60 % is split.
  const std::vector<Band> whole = MakeBands(false);
  int most = 0;
  for (const Band& b : whole)
    most = std::max<int>(most, static_cast<int>(b.teeth.size()));
  return most > 8 && width < 0.6 * NaturalSize(whole).width();
}

void ChartWidget::Layout() {
  bands_ = MakeBands(wrap_);
  updateGeometry();
  update();
}

void ChartWidget::resizeEvent(QResizeEvent* e) {
  QWidget::resizeEvent(e);
  const bool wrap = WrapFor(width());
  if (wrap != wrap_) {
    wrap_ = wrap;
    Layout();
  }
}

void ChartWidget::SetLesson(const std::vector<int>& teeth,
                            const std::vector<SiteRef>& path,
                            const std::map<std::pair<int, int>, double>& recession_mm,
                            const std::vector<int>& missing) {
  teeth_ = teeth;
  missing_ = std::set<int>(missing.begin(), missing.end());
  for (int fdi : missing)
    if (std::find(teeth_.begin(), teeth_.end(), fdi) == teeth_.end())
      teeth_.push_back(fdi);
  path_ = path;
  cursor_ = 0;
  last_entered_.reset();
  pd_.clear();
  bleeding_.clear();
  truth_.clear();
  recession_ = recession_mm;
  read_only_ = false;
  wrap_ = width() > 0 && WrapFor(width());
  Layout();
}

void ChartWidget::ShowChart(const PerioChart& chart) {
  std::vector<int> teeth, missing;
  std::map<std::pair<int, int>, double> recession;
  for (const ToothChart& t : chart.teeth) {
    (t.present ? teeth : missing).push_back(t.fdi);
    for (int s = 0; s < kSitesPerTooth; ++s)
      recession[{t.fdi, s}] = t.sites[s].recession_mm;
  }
  SetLesson(teeth, StandardPath(teeth), recession, missing);
  for (const ToothChart& t : chart.teeth)
    for (int s = 0; s < kSitesPerTooth; ++s) {
      if (t.sites[s].pd_mm) pd_[{t.fdi, s}] = *t.sites[s].pd_mm;
      bleeding_[{t.fdi, s}] = t.sites[s].bleeding;
    }
  cursor_ = path_.size();
  read_only_ = true;
  update();
}

void ChartWidget::SetProbing(std::optional<SiteRef> site) {
  if (site == probing_) return;
  probing_ = site;
  if (site) ScrollTo(*site);
  update();
}

void ChartWidget::ScrollTo(const SiteRef& site) {
  QScrollArea* area = nullptr;
  for (QWidget* w = parentWidget(); w && !area; w = w->parentWidget())
    area = qobject_cast<QScrollArea*>(w);
  if (!area || !area->widget()) return;
  for (int b = 0; b < static_cast<int>(bands_.size()); ++b) {
    const Band& band = bands_[b];
    if (band.buccal != (site.site < 3)) continue;
    const auto it = std::find(band.teeth.begin(), band.teeth.end(), site.fdi);
    if (it == band.teeth.end()) continue;
    const int t = static_cast<int>(it - band.teeth.begin());
    const double scale = Scale();
    // The band's whole height (title, header, rows) around the site's column.
    const QRect first = CellRect(b, t, 1, 0), last = CellRect(b, t, 1, rows() - 1);
    const QPoint top(static_cast<int>(first.center().x() * scale),
                     static_cast<int>((first.top() - kBandTitle - kHeader) * scale));
    const QPoint bottom(top.x(), static_cast<int>(last.bottom() * scale));
    const QPoint a = mapTo(area->widget(), top), z = mapTo(area->widget(), bottom);
    area->ensureVisible(z.x(), z.y(), 40, 8);
    area->ensureVisible(a.x(), a.y(), 40, 8);
    return;
  }
}

void ChartWidget::SetTruth(const std::map<std::pair<int, int>, int>& truth) {
  truth_ = truth;
  updateGeometry();
  update();
}

void ChartWidget::SetProbed(const std::set<std::pair<int, int>>& probed) {
  if (probed == probed_) return;
  probed_ = probed;
  update();
}

void ChartWidget::SetEnabled(bool on) {
  enabled_ = on;
  update();
}

std::optional<SiteRef> ChartWidget::cursor() const {
  if (cursor_ >= path_.size()) return std::nullopt;
  return path_[cursor_];
}

bool ChartWidget::SelectSite(const SiteRef& s) {
  for (std::size_t i = 0; i < path_.size(); ++i)
    if (path_[i] == s) {
      cursor_ = i;
      update();
      return true;
    }
  return false;
}

std::optional<int> ChartWidget::depth(const SiteRef& s) const {
  const auto it = pd_.find({s.fdi, s.site});
  if (it == pd_.end()) return std::nullopt;
  return it->second;
}

bool ChartWidget::bleeding(const SiteRef& s) const {
  const auto it = bleeding_.find({s.fdi, s.site});
  return it != bleeding_.end() && it->second;
}

int ChartWidget::rows() const { return truth_.empty() ? kRows - 1 : kRows; }

QSize ChartWidget::sizeHint() const { return NaturalSize(bands_); }

QRect ChartWidget::CellRect(int band, int tooth_index, int cell, int row) const {
  const int y0 =
      4 + band * (kBandTitle + kHeader + rows() * kRowH + 6) + kBandTitle + kHeader;
  const int x = kLabelW + tooth_index * (3 * kCell + kToothGap) + cell * kCell;
  return {x, y0 + row * kRowH, kCell - 1, kRowH - 1};
}

double ChartWidget::Scale() const {
  // The chart shrinks to the width it is given (never grows), so the whole
  // mouth fits a narrow panel; its height follows (heightForWidth).
  const int natural = sizeHint().width();
  return natural > 0 && width() < natural ? std::max(0.4, double(width()) / natural)
                                          : 1.0;
}

QSize ChartWidget::minimumSizeHint() const {
  const QSize n = sizeHint();
  return {std::min(n.width(), 220), static_cast<int>(n.height() * 0.4)};
}

bool ChartWidget::hasHeightForWidth() const { return true; }

int ChartWidget::heightForWidth(int w) const {
  const QSize n = NaturalSize(MakeBands(WrapFor(w)));
  const double s =
      n.width() > 0 && w < n.width() ? std::max(0.4, double(w) / n.width()) : 1.0;
  return static_cast<int>(std::ceil(n.height() * s));
}

void ChartWidget::paintEvent(QPaintEvent*) {
  QPainter p(this);
  p.fillRect(rect(), palette().base());
  const double scale = Scale();
  p.scale(scale, scale);
  QFont f = font();
  f.setPointSizeF(std::max(7.0, f.pointSizeF() - 1));
  p.setFont(f);
  const std::optional<SiteRef> cur = cursor();
  for (int b = 0; b < static_cast<int>(bands_.size()); ++b) {
    const Band& band = bands_[b];
    const int y0 = 4 + b * (kBandTitle + kHeader + rows() * kRowH + 6);
    QFont bold = f;
    bold.setBold(true);
    p.setFont(bold);
    p.setPen(palette().text().color());
    p.drawText(
        QRect(4, y0, 400, kBandTitle), Qt::AlignLeft | Qt::AlignVCenter,
        QString("%1 %2%3")
            .arg(band.upper ? "upper" : "lower")
            .arg(band.buccal  ? "buccal"
                 : band.upper ? "palatal"
                              : "lingual")
            .arg(*band.half ? QString(", the patient's %1").arg(band.half) : QString()));
    p.setFont(f);
    for (int r = 0; r < rows(); ++r)
      p.drawText(QRect(4, y0 + kBandTitle + kHeader + r * kRowH, kLabelW - 6, kRowH),
                 Qt::AlignLeft | Qt::AlignVCenter, kRowNames[r]);
    for (int t = 0; t < static_cast<int>(band.teeth.size()); ++t) {
      const int fdi = band.teeth[t];
      const QRect head(CellRect(b, t, 0, 0).left(), y0 + kBandTitle, 3 * kCell, kHeader);
      p.setFont(bold);
      p.setPen(palette().text().color());
      p.drawText(head, Qt::AlignCenter, QString::number(fdi));
      p.setFont(f);
      if (missing_.count(fdi)) {
        // A missing tooth keeps its column: greyed, crossed, nothing to enter.
        const QRect col = CellRect(b, t, 0, 0).united(CellRect(b, t, 2, rows() - 1));
        p.fillRect(col, QColor(225, 225, 225));
        p.setPen(QPen(QColor(150, 150, 150), 1.5));
        p.drawLine(col.topLeft(), col.bottomRight());
        p.drawLine(col.topRight(), col.bottomLeft());
        p.setPen(QColor(90, 90, 90));
        p.drawText(col, Qt::AlignCenter, "missing");
        continue;
      }
      const std::array<int, 3> sites = CellSites(fdi, band.buccal);
      for (int c = 0; c < 3; ++c) {
        const std::pair key{fdi, sites[c]};
        const bool is_cursor = cur && cur->fdi == fdi && cur->site == sites[c];
        const bool is_probing =
            probing_ && probing_->fdi == fdi && probing_->site == sites[c];
        for (int r = 0; r < rows(); ++r) {
          const QRect cell = CellRect(b, t, c, r);
          QColor fill = palette().base().color();
          if (is_probing) fill = QColor(255, 236, 140);
          if (is_cursor && r == 0) fill = QColor(170, 205, 255);
          p.fillRect(cell, fill);
          p.setPen(QColor(190, 190, 190));
          p.drawRect(cell);
          QString text;
          QColor colour = palette().text().color();
          const auto pd = pd_.find(key);
          const auto rec = recession_.find(key);
          if (r == 0 && pd != pd_.end()) text = QString::number(pd->second);
          if (r == 0 && pd != pd_.end() && pd->second >= 4) colour = QColor(200, 30, 30);
          if (r == 1 && rec != recession_.end())
            text = QString::number(rec->second, 'f',
                                   rec->second == std::floor(rec->second) ? 0 : 1);
          if (r == 2 && pd != pd_.end() && rec != recession_.end()) {
            const double cal = pd->second + rec->second;  // never truncated
            text = QString::number(cal, 'f', cal == std::floor(cal) ? 0 : 1);
            if (cal >= 4) colour = QColor(200, 30, 30);
          }
          if (r == 3 && bleeding_.count(key) && bleeding_.at(key)) {
            p.setBrush(QColor(210, 30, 30));
            p.setPen(Qt::NoPen);
            p.drawEllipse(cell.center(), 4, 4);
            p.setBrush(Qt::NoBrush);
          }
          if (r == 4 && truth_.count(key) && pd != pd_.end() && probed_.count(key)) {
            text = QString::number(truth_.at(key));
            colour =
                truth_.at(key) == pd->second ? QColor(30, 130, 50) : QColor(200, 120, 0);
          }
          if (!text.isEmpty()) {
            p.setPen(colour);
            p.drawText(cell, Qt::AlignCenter, text);
          }
        }
      }
    }
  }
  p.resetTransform();
  if (tens_ || pending_ || zero_refused_) {
    // What the keys are waiting for, over the top right of the chart.
    const QString say = pending_
                            ? QString("%1 mm? Enter confirms, Esc cancels").arg(*pending_)
                        : tens_ ? QString("+ : the next digit is 10 + digit")
                                : QString("A depth is at least 1 mm (+ 0 is 10 mm)");
    QFont b = font();
    b.setBold(true);
    p.setFont(b);
    const QRect box(width() - 290, 2, 284, 18);
    p.fillRect(box, QColor(255, 236, 140));
    p.setPen(QColor(60, 40, 0));
    p.drawText(box, Qt::AlignCenter, say);
  }
  if (!enabled_) p.fillRect(rect(), QColor(255, 255, 255, 120));
  if (hasFocus()) {
    p.setPen(QPen(palette().highlight().color(), 2));
    p.drawRect(rect().adjusted(1, 1, -1, -1));
  }
}

void ChartWidget::Enter(int value) {
  if (!enabled_ || read_only_ || cursor_ >= path_.size()) return;
  const SiteRef s = path_[cursor_];
  pd_[{s.fdi, s.site}] = value;
  last_entered_ = cursor_;
  ChartEntry e;
  e.site = s;
  e.pd_mm = value;
  e.bleeding = bleeding(s);
  if (on_entry) on_entry(e);
  ++cursor_;
  if (cursor_ < path_.size()) ScrollTo(path_[cursor_]);
  update();
}

void ChartWidget::keyPressEvent(QKeyEvent* e) {
  if (!enabled_ || read_only_) return QWidget::keyPressEvent(e);
  const int k = e->key();
  zero_refused_ = false;
  // A depth over 12 mm waits for Enter (Esc, or any other key, cancels it).
  if (pending_) {
    const int v = *pending_;
    pending_.reset();
    if (k == Qt::Key_Return || k == Qt::Key_Enter) Enter(v);
    update();
    if (k == Qt::Key_Return || k == Qt::Key_Enter || k == Qt::Key_Escape) return;
  }
  int digit = -1;
  if (k >= Qt::Key_0 && k <= Qt::Key_9 && !(e->modifiers() & Qt::ShiftModifier))
    digit = k - Qt::Key_0;
  // Shift+digit arrives as the shifted character on most layouts.
  const QString shifted = ")!@#$%^&*(";
  int shifted_digit = -1;
  if (const int i = shifted.indexOf(e->text()); !e->text().isEmpty() && i >= 0)
    shifted_digit = i;
  else if (k >= Qt::Key_0 && k <= Qt::Key_9 && (e->modifiers() & Qt::ShiftModifier))
    shifted_digit = k - Qt::Key_0;
  if (k == Qt::Key_Plus || e->text() == "+") {  // the tens prefix
    tens_ = !tens_;
    update();
    return;
  }
  if (digit >= 0 || shifted_digit >= 0) {
    const int value = digit >= 0 ? (tens_ ? 10 + digit : digit) : 10 + shifted_digit;
    tens_ = false;
    if (value == 0) {  // no pocket reads 0 mm: a slip of the finger, not a reading
      zero_refused_ = true;
      update();
      return;
    }
    if (value > kConfirmAboveMm) {
      pending_ = value;
      update();
      return;
    }
    Enter(value);
    return;
  }
  if ((k == Qt::Key_B || k == Qt::Key_Space) && last_entered_) {
    const SiteRef s = path_[*last_entered_];
    const bool now = !bleeding(s);
    bleeding_[{s.fdi, s.site}] = now;
    ChartEntry entry;
    entry.site = s;
    entry.pd_mm = depth(s);
    entry.bleeding = now;
    if (on_entry) on_entry(entry);
    update();
    return;
  }
  if (k == Qt::Key_Backspace && cursor_ > 0) {
    --cursor_;
    const SiteRef s = path_[cursor_];
    pd_.erase({s.fdi, s.site});
    bleeding_.erase({s.fdi, s.site});
    last_entered_ = cursor_ > 0 ? std::optional<std::size_t>(cursor_ - 1) : std::nullopt;
    update();
    return;
  }
  QWidget::keyPressEvent(e);
}

void ChartWidget::mousePressEvent(QMouseEvent* e) {
  setFocus();
  const double scale = Scale();
  const QPoint at(static_cast<int>(e->pos().x() / scale),
                  static_cast<int>(e->pos().y() / scale));
  // A click on a cell puts the cursor there.
  for (int b = 0; b < static_cast<int>(bands_.size()); ++b)
    for (int t = 0; t < static_cast<int>(bands_[b].teeth.size()); ++t) {
      const std::array<int, 3> sites = CellSites(bands_[b].teeth[t], bands_[b].buccal);
      for (int c = 0; c < 3; ++c)
        if (CellRect(b, t, c, 0).contains(at)) {
          for (std::size_t i = 0; i < path_.size(); ++i)
            if (path_[i].fdi == bands_[b].teeth[t] && path_[i].site == sites[c])
              cursor_ = i;
          update();
          return;
        }
    }
}

}  // namespace sulcus::ui
