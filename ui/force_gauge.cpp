#include "ui/force_gauge.h"

#include <QFontMetricsF>
#include <QPainter>
#include <algorithm>

namespace sulcus::ui {

ForceGauge::ForceGauge(QWidget* parent) : QWidget(parent) {
  setMinimumSize(260, 75);
  SetBand(band_low_, band_high_);
}

void ForceGauge::SetBand(double low_n, double high_n) {
  band_low_ = low_n;
  band_high_ = high_n;
  setToolTip(QString("The force along the probe; the green band (%1 to %2 N) is the "
                     "force the lesson gives full credit for at the pocket floor. The "
                     "white mark is the press set with R and F (mouse and keyboard).")
                 .arg(low_n, 0, 'f', 2)
                 .arg(high_n, 0, 'f', 2));
  update();
}

void ForceGauge::SetPress(double n) {
  if (n == press_) return;
  press_ = n;
  update();
}

void ForceGauge::SetLabel(const QString& label) {
  label_ = label;
  update();
}

void ForceGauge::SetForce(double f) {
  force_ = f;
  update();
}

void ForceGauge::paintEvent(QPaintEvent*) {
  QPainter p(this);
  p.setRenderHint(QPainter::Antialiasing);
  const QRectF all = rect().adjusted(6, 6, -6, -6);
  p.fillRect(rect(), QColor(36, 38, 44));
  // The bar.
  // Inset by half a label each side, so that the end labels (0.0, 0.6) are whole.
  const double inset = QFontMetricsF(p.font()).horizontalAdvance("0.0") / 2 + 1;
  const QRectF bar(all.left() + inset, all.top() + 22, all.width() - 2 * inset, 26);
  auto x_of = [&](double n) {
    return bar.left() + bar.width() * std::clamp(n / kScaleN, 0.0, 1.0);
  };
  p.fillRect(bar, QColor(58, 60, 68));
  p.fillRect(QRectF(QPointF(x_of(band_low_), bar.top()),
                    QPointF(x_of(band_high_), bar.bottom())),
             QColor(60, 170, 90));
  const QColor fill =
      InBand() ? QColor(90, 220, 120)
               : (force_ > band_high_ ? QColor(235, 120, 60) : QColor(120, 170, 240));
  p.fillRect(QRectF(bar.left(), bar.top() + 7, x_of(force_) - bar.left(), 12), fill);
  if (press_ > 0) {
    p.setPen(QPen(QColor(250, 250, 250), 3));
    p.drawLine(QPointF(x_of(press_), bar.top() - 3),
               QPointF(x_of(press_), bar.bottom() + 3));
  }
  p.setPen(QColor(200, 200, 205));
  for (double n = 0; n <= kScaleN + 1e-9; n += 0.1) {
    p.drawLine(QPointF(x_of(n), bar.bottom()), QPointF(x_of(n), bar.bottom() + 4));
    const QString label = QString::number(n, 'f', 1);
    p.drawText(QPointF(x_of(n) - QFontMetricsF(p.font()).horizontalAdvance(label) / 2,
                       bar.bottom() + 16),
               label);
  }
  QFont big = p.font();
  big.setBold(true);
  p.setFont(big);
  p.drawText(
      QPointF(all.left(), all.top() + 14),
      QString("%1 %2 N%3%4")
          .arg(label_)
          .arg(force_, 0, 'f', 3)
          .arg(force_ > kScaleN ? "  (off scale)" : "")
          .arg(press_ > 0 ? QString("   press %1 N").arg(press_, 0, 'f', 2) : QString()));
  p.setFont(QFont());
}

}  // namespace sulcus::ui
