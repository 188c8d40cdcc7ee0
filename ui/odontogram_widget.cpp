#include "ui/odontogram_widget.h"

#include <QKeyEvent>
#include <QMenu>
#include <QMouseEvent>
#include <QPainter>
#include <QPainterPath>
#include <algorithm>

#include "core/anatomy/soft_tissue.h"

namespace sulcus::ui {
namespace {

constexpr int kBox = 34, kColumn = 40, kMidGap = 12, kLeft = 8, kTop = 18, kRowGap = 26,
              kRegionRow = 19;

// Upper 18..11 21..28, lower 48..41 31..38: the chart's order.
int Rank(int fdi) {
  const int q = fdi / 10, p = fdi % 10;
  switch (q) {
    case 1:
      return 10 - p;
    case 2:
      return 10 + p;
    case 4:
      return 10 - p;
    case 3:
      return 10 + p;
  }
  return 100;
}
bool Upper(int fdi) { return fdi / 10 <= 2; }
// On the chart, quadrants 1 and 4 have their mesial side to the right.
bool MesialRight(int fdi) { return fdi / 10 == 1 || fdi / 10 == 4; }

QString Cap(const std::string& s) {
  QString q = QString::fromStdString(s);
  if (q.startsWith("the ")) q = q.mid(4);
  if (!q.isEmpty()) q[0] = q[0].toUpper();
  return q;
}

}  // namespace

OdontogramWidget::OdontogramWidget(QWidget* parent) : QWidget(parent) {
  setFocusPolicy(Qt::StrongFocus);
  setToolTip(
      "Odontogram: click a surface for caries, Ca for calculus, G for inflamed gingiva, "
      "right-click a tooth "
      "for its WHO status; keys: arrows, M D B L O, C, G, 0-9");
}

void OdontogramWidget::SetLesson(const std::vector<int>& teeth,
                                 const std::vector<std::string>& regions) {
  teeth_ = teeth;
  std::sort(teeth_.begin(), teeth_.end(), [](int a, int b) {
    return Upper(a) != Upper(b) ? Upper(a) : Rank(a) < Rank(b);
  });
  regions_ = regions;
  odontogram_ = EmptyOdontogram(teeth_);
  examined_.clear();
  selected_ = teeth_.empty() ? 0 : teeth_.front();
  Layout();
  updateGeometry();
  update();
}

void OdontogramWidget::SetExamined(const std::vector<std::string>& units) {
  if (units == examined_) return;
  examined_ = units;
  update();
}

int OdontogramWidget::SideColumns() const {
  int n = 1;
  for (int fdi : teeth_) n = std::max(n, fdi % 10);
  return n;
}

QSize OdontogramWidget::sizeHint() const {
  const int rows_h = kTop + 2 * (kBox + kRowGap) + 8;
  const int regions_h = static_cast<int>((regions_.size() + 1) / 2) * kRegionRow + 24;
  return {kLeft * 2 + 2 * SideColumns() * kColumn + kMidGap, rows_h + regions_h};
}

void OdontogramWidget::Layout() {
  cells_.clear();
  for (int fdi : teeth_) {
    const int side = SideColumns(), pos = fdi % 10;
    const bool right =
        fdi / 10 == 1 || fdi / 10 == 4;  // the patient's right: the chart's left
    const int col = right ? side - pos : side + pos - 1;
    const int x = kLeft + col * kColumn + (col >= side ? kMidGap : 0);
    const int y = Upper(fdi) ? kTop : kTop + kBox + kRowGap + 14;
    Cell c{fdi, QRect(x, y, kBox, kBox), {}, {}, {}};
    const int below = Upper(fdi) ? y + kBox + 2 : y - 14;
    c.ca = QRect(x, below, 16, 12);
    c.g = QRect(x + 18, below, 16, 12);
    c.status = QRect(x + kBox - 1, y, 8, 12);
    cells_.push_back(c);
  }
  region_rects_.clear();
  const int y0 = kTop + 2 * (kBox + kRowGap) + 24;
  const int half = (width() > 0 ? width() : sizeHint().width()) / 2 - kLeft;
  for (std::size_t i = 0; i < regions_.size(); ++i) {
    const int col = static_cast<int>(i % 2), row = static_cast<int>(i / 2);
    region_rects_.push_back(
        {regions_[i], QRect(kLeft + col * (half + 4), y0 + row * kRegionRow, half - 4,
                            kRegionRow - 3)});
  }
}

int OdontogramWidget::SurfaceAt(const Cell& c, const QPoint& p) const {
  if (!c.box.contains(p)) return -1;
  const double u = (p.x() - c.box.left()) / double(kBox),
               v = (p.y() - c.box.top()) / double(kBox);
  if (u > 1.0 / 3 && u < 2.0 / 3 && v > 1.0 / 3 && v < 2.0 / 3)
    return static_cast<int>(ToothSurface::kOcclusal);
  const bool top = v < u && v<1 - u, bottom = v> u && v > 1 - u,
             left = u < v && u < 1 - v;
  const bool upper = Upper(c.fdi);
  if (top)
    return static_cast<int>(upper ? ToothSurface::kBuccal : ToothSurface::kLingual);
  if (bottom)
    return static_cast<int>(upper ? ToothSurface::kLingual : ToothSurface::kBuccal);
  const bool mesial = left != MesialRight(c.fdi);
  return static_cast<int>(mesial ? ToothSurface::kMesial : ToothSurface::kDistal);
}

void OdontogramWidget::Apply(const Finding& f) {
  if (!odontogram_.Apply(f)) return;
  update();
  if (on_finding) on_finding(f);
}

void OdontogramWidget::Toggle(int fdi, Finding::Kind kind, ToothSurface s) {
  const ToothRecord* t = odontogram_.Find(fdi);
  if (!t || !enabled_) return;
  Finding f;
  f.kind = kind;
  f.fdi = fdi;
  f.surface = s;
  f.present = kind == Finding::Kind::kCaries     ? !t->caries[static_cast<std::size_t>(s)]
              : kind == Finding::Kind::kCalculus ? !t->calculus
                                                 : !t->inflamed;
  Apply(f);
}

void OdontogramWidget::AskStatus(int fdi, const QPoint& where) {
  if (!enabled_) return;
  QMenu menu(this);
  for (int code = 0; code <= 9; ++code) {
    QAction* a = menu.addAction(QString("%1  %2").arg(code).arg(WhoStatusName(code)));
    a->setData(code);
  }
  menu.addSeparator();
  menu.addAction("As its caries marks say")->setData(-1);
  const QAction* chosen = menu.exec(mapToGlobal(where));
  if (!chosen) return;
  Finding f;
  f.kind = Finding::Kind::kStatus;
  f.fdi = fdi;
  f.status = chosen->data().toInt();
  f.present = f.status >= 0;
  if (f.status < 0) f.status = 0;
  Apply(f);
}

void OdontogramWidget::AskLesion(const std::string& region, const QPoint& where) {
  if (!enabled_) return;
  QMenu menu(this);
  menu.addAction("No lesion")->setData(QString());
  for (const std::string& k : LesionKinds())
    menu.addAction(QString::fromStdString(k))->setData(QString::fromStdString(k));
  const QAction* chosen = menu.exec(mapToGlobal(where));
  if (!chosen) return;
  Finding f;
  f.kind = Finding::Kind::kLesion;
  f.region = region;
  f.lesion = chosen->data().toString().toStdString();
  f.present = !f.lesion.empty();
  Apply(f);
}

void OdontogramWidget::mousePressEvent(QMouseEvent* e) {
  setFocus();
  const QPoint p = e->pos();
  for (const Cell& c : cells_) {
    const bool was_selected = selected_ == c.fdi;
    if (c.box.contains(p) || c.ca.contains(p) || c.g.contains(p)) selected_ = c.fdi;
    if (e->button() == Qt::RightButton && c.box.contains(p)) return AskStatus(c.fdi, p);
    // The first click on a tooth selects it; a click on a surface of the
    // selected tooth marks caries there (selecting records nothing).
    if (const int s = SurfaceAt(c, p); s >= 0) {
      if (!was_selected) {
        update();
        return;
      }
      return Toggle(c.fdi, Finding::Kind::kCaries, static_cast<ToothSurface>(s));
    }
    if (c.ca.contains(p)) return Toggle(c.fdi, Finding::Kind::kCalculus);
    if (c.g.contains(p)) return Toggle(c.fdi, Finding::Kind::kInflamed);
  }
  for (const auto& [region, r] : region_rects_)
    if (r.contains(p)) return AskLesion(region, p);
  update();
}

void OdontogramWidget::keyPressEvent(QKeyEvent* e) {
  const auto it = std::find(teeth_.begin(), teeth_.end(), selected_);
  if (it == teeth_.end()) return QWidget::keyPressEvent(e);
  const auto i = static_cast<int>(it - teeth_.begin());
  const int n = static_cast<int>(teeth_.size());
  switch (e->key()) {
    case Qt::Key_Right:
      selected_ = teeth_[static_cast<std::size_t>(std::min(n - 1, i + 1))];
      break;
    case Qt::Key_Left:
      selected_ = teeth_[static_cast<std::size_t>(std::max(0, i - 1))];
      break;
    case Qt::Key_Down:
    case Qt::Key_Up: {
      // The tooth across the occlusal plane at the same place in the chart.
      const int want = Rank(selected_);
      for (int t : teeth_)
        if (Upper(t) != Upper(selected_) && Rank(t) == want) selected_ = t;
      break;
    }
    case Qt::Key_M:
      Toggle(selected_, Finding::Kind::kCaries, ToothSurface::kMesial);
      break;
    case Qt::Key_D:
      Toggle(selected_, Finding::Kind::kCaries, ToothSurface::kDistal);
      break;
    case Qt::Key_B:
      Toggle(selected_, Finding::Kind::kCaries, ToothSurface::kBuccal);
      break;
    case Qt::Key_L:
      Toggle(selected_, Finding::Kind::kCaries, ToothSurface::kLingual);
      break;
    case Qt::Key_O:
      Toggle(selected_, Finding::Kind::kCaries, ToothSurface::kOcclusal);
      break;
    case Qt::Key_C:
      Toggle(selected_, Finding::Kind::kCalculus);
      break;
    case Qt::Key_G:
      Toggle(selected_, Finding::Kind::kInflamed);
      break;
    default:
      if (e->key() >= Qt::Key_0 && e->key() <= Qt::Key_9 && enabled_) {
        Finding f;
        f.kind = Finding::Kind::kStatus;
        f.fdi = selected_;
        f.status = e->key() - Qt::Key_0;
        Apply(f);
        break;
      }
      return QWidget::keyPressEvent(e);
  }
  update();
}

void OdontogramWidget::paintEvent(QPaintEvent*) {
  if (region_rects_.empty() && !regions_.empty()) Layout();
  QPainter p(this);
  p.setRenderHint(QPainter::Antialiasing);
  p.fillRect(rect(), palette().base());
  QFont small = font();
  small.setPointSizeF(std::max(6.5, font().pointSizeF() * 0.8));
  p.setFont(small);
  p.setPen(QColor("#666"));
  const int side = SideColumns();
  const int mid_x = kLeft + side * kColumn + kMidGap / 2 - 2;
  p.setPen(QPen(QColor("#999"), 1, Qt::DashLine));
  p.drawLine(mid_x, kTop, mid_x, kTop + 2 * (kBox + kRowGap) + 4);
  const int occlusal_y = kTop + kBox + kRowGap / 2 + 7;
  p.drawLine(kLeft, occlusal_y, kLeft + 2 * side * kColumn + kMidGap, occlusal_y);

  auto examined = [&](const std::string& u) {
    return std::find(examined_.begin(), examined_.end(), u) != examined_.end();
  };
  for (const Cell& c : cells_) {
    const ToothRecord* t = odontogram_.Find(c.fdi);
    const QRectF b = c.box;
    const QRectF in(b.left() + b.width() / 3, b.top() + b.height() / 3, b.width() / 3,
                    b.height() / 3);
    // The four outer trapezoids and the centre, each its surface.
    struct Poly {
      QPolygonF poly;
      int surface;
    };
    const bool upper = Upper(c.fdi), mr = MesialRight(c.fdi);
    const int top =
        static_cast<int>(upper ? ToothSurface::kBuccal : ToothSurface::kLingual);
    const int bottom =
        static_cast<int>(upper ? ToothSurface::kLingual : ToothSurface::kBuccal);
    const int left = static_cast<int>(mr ? ToothSurface::kDistal : ToothSurface::kMesial);
    const int right =
        static_cast<int>(mr ? ToothSurface::kMesial : ToothSurface::kDistal);
    const std::vector<Poly> polys = {
        {QPolygonF({b.topLeft(), b.topRight(), in.topRight(), in.topLeft()}), top},
        {QPolygonF({in.bottomLeft(), in.bottomRight(), b.bottomRight(), b.bottomLeft()}),
         bottom},
        {QPolygonF({b.topLeft(), in.topLeft(), in.bottomLeft(), b.bottomLeft()}), left},
        {QPolygonF({in.topRight(), b.topRight(), b.bottomRight(), in.bottomRight()}),
         right},
        {QPolygonF(in), static_cast<int>(ToothSurface::kOcclusal)}};
    for (const Poly& poly : polys) {
      const bool caries = t && t->caries[static_cast<std::size_t>(poly.surface)];
      const std::string unit = std::to_string(c.fdi) + " " +
                               SurfaceCode(static_cast<ToothSurface>(poly.surface));
      p.setBrush(caries                     ? QColor("#9c2a1a")
                 : examined(unit)           ? QColor("#cfe3f5")
                 : examined("seen:" + unit) ? QColor("#eef1f4")
                                            : QColor("#ffffff"));
      p.setPen(QPen(QColor("#8a8a8a"), 1));
      p.drawPolygon(poly.poly);
    }
    if (c.fdi == selected_ || c.fdi == touching_) {
      p.setBrush(Qt::NoBrush);
      p.setPen(QPen(c.fdi == touching_ ? QColor("#e07800") : QColor("#2060c0"), 2.5));
      p.drawRect(c.box.adjusted(-2, -2, 2, 2));
    }
    // Its number on the outside, Ca and G toggles, the status code.
    p.setPen(QColor("#333"));
    const QRect label = upper ? QRect(c.box.left(), c.box.top() - 14, kBox, 13)
                              : QRect(c.box.left(), c.box.bottom() + 2, kBox, 13);
    p.drawText(label, Qt::AlignCenter, QString::number(c.fdi));
    for (const auto& [r, on, text, colour] :
         {std::tuple{c.ca, t && t->calculus, "Ca", QColor("#b08a00")},
          std::tuple{c.g, t && t->inflamed, "G", QColor("#c03040")}}) {
      p.setPen(QPen(on ? colour : QColor("#bbb"), 1));
      p.setBrush(on ? colour : QColor("#fafafa"));
      p.drawRoundedRect(r, 2, 2);
      p.setPen(on ? QColor("#fff") : QColor("#999"));
      p.drawText(r, Qt::AlignCenter, text);
    }
    if (t && (t->status || t->Status() != 0)) {
      p.setPen(t->status ? QColor("#2060c0") : QColor("#999"));
      p.drawText(QRect(c.box.right() + 1, c.box.top() - 1, 8, 12),
                 Qt::AlignLeft | Qt::AlignTop, QString::number(t->Status()));
    }
  }
  // The regions.
  const int y0 = kTop + 2 * (kBox + kRowGap) + 6;
  p.setPen(QColor("#666"));
  p.drawText(QRect(kLeft, y0, width() - 2 * kLeft, 16), Qt::AlignLeft | Qt::AlignVCenter,
             "Soft tissues (click to record a lesion)");
  for (const auto& [region, r] : region_rects_) {
    const auto it = odontogram_.lesions.find(region);
    const bool lesion = it != odontogram_.lesions.end();
    p.setPen(QPen(QColor("#ccc"), 1));
    p.setBrush(lesion             ? QColor("#f6d8d3")
               : examined(region) ? QColor("#cfe3f5")
                                  : QColor("#ffffff"));
    p.drawRoundedRect(r, 3, 3);
    p.setPen(QColor("#222"));
    p.drawText(r.adjusted(6, 0, -4, 0), Qt::AlignLeft | Qt::AlignVCenter,
               (examined(region) ? QString::fromUtf8("\u2713 ") : QString("   ")) +
                   Cap(RegionLabel(region)));
    if (lesion) {
      p.setPen(QColor("#9c2a1a"));
      p.drawText(r.adjusted(6, 0, -6, 0), Qt::AlignRight | Qt::AlignVCenter,
                 QString::fromStdString(it->second));
    }
  }
  if (!enabled_) p.fillRect(rect(), QColor(255, 255, 255, 120));
}

}  // namespace sulcus::ui
