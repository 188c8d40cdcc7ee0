#include "ui/force_gauge.h"

#include <QPainter>
#include <QPainterPath>

#include <algorithm>

namespace sulcus::ui {

ForceGauge::ForceGauge(QWidget* parent) : QWidget(parent) {
  setMinimumSize(260, 170);
  setToolTip("Probing force; the green band is the clinical probing force, 0.20 to 0.25 N");
}

void ForceGauge::Push(double t, double f, double tq) {
  force_ = f;
  torque_ = tq;
  history_.push_back({t, f, tq});
  while (!history_.empty() && history_.front().t < t - kHistoryS) history_.pop_front();
  update();
}

void ForceGauge::paintEvent(QPaintEvent*) {
  QPainter p(this);
  p.setRenderHint(QPainter::Antialiasing);
  const QRectF all = rect().adjusted(6, 6, -6, -6);
  p.fillRect(rect(), QColor(36, 38, 44));
  // The bar.
  const QRectF bar(all.left(), all.top() + 22, all.width(), 26);
  auto x_of = [&](double n) { return bar.left() + bar.width() * std::clamp(n / kScaleN, 0.0, 1.0); };
  p.fillRect(bar, QColor(58, 60, 68));
  p.fillRect(QRectF(QPointF(x_of(kBandLow), bar.top()), QPointF(x_of(kBandHigh), bar.bottom())), QColor(60, 170, 90));
  const QColor fill = InBand() ? QColor(90, 220, 120) : (force_ > kBandHigh ? QColor(235, 120, 60) : QColor(120, 170, 240));
  p.fillRect(QRectF(bar.left(), bar.top() + 7, x_of(force_) - bar.left(), 12), fill);
  p.setPen(QColor(200, 200, 205));
  for (double n = 0; n <= kScaleN + 1e-9; n += 0.1) {
    p.drawLine(QPointF(x_of(n), bar.bottom()), QPointF(x_of(n), bar.bottom() + 4));
    p.drawText(QPointF(x_of(n) - 9, bar.bottom() + 16), QString::number(n, 'f', 1));
  }
  QFont big = p.font();
  big.setBold(true);
  p.setFont(big);
  p.drawText(QPointF(all.left(), all.top() + 14),
             QString("Force %1 N%2").arg(force_, 0, 'f', 3).arg(force_ > kScaleN ? "  (off scale)" : ""));
  p.setFont(QFont());
  // The plot of the last seconds: force (blue/green) and torque/100 (grey).
  const QRectF plot(all.left(), bar.bottom() + 24, all.width(), all.bottom() - bar.bottom() - 24);
  p.fillRect(plot, QColor(28, 30, 34));
  if (history_.size() < 2 || plot.height() < 10) return;
  const double t1 = history_.back().t, t0 = t1 - kHistoryS;
  const double top = std::max(kScaleN, std::max_element(history_.begin(), history_.end(), [](auto& a, auto& b) {
                                         return a.f < b.f;
                                       })->f);
  auto pt = [&](double t, double v) {
    return QPointF(plot.left() + plot.width() * (t - t0) / kHistoryS, plot.bottom() - plot.height() * std::min(v / top, 1.0));
  };
  p.fillRect(QRectF(pt(t0, kBandHigh), pt(t1, kBandLow)), QColor(40, 90, 55));
  QPainterPath force, torque;
  force.moveTo(pt(history_.front().t, history_.front().f));
  torque.moveTo(pt(history_.front().t, history_.front().tq / 100));
  for (const Sample& s : history_) {
    force.lineTo(pt(s.t, s.f));
    torque.lineTo(pt(s.t, s.tq / 100));
  }
  p.setPen(QPen(QColor(150, 150, 155), 1));
  p.drawPath(torque);
  p.setPen(QPen(QColor(120, 200, 255), 2));
  p.drawPath(force);
  p.setPen(QColor(170, 170, 175));
  p.drawText(plot.adjusted(4, 2, 0, 0), Qt::AlignLeft | Qt::AlignTop, "last 5 s: force (blue), torque/100 N*mm (grey)");
}

}  // namespace sulcus::ui
