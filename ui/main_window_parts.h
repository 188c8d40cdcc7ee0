#pragma once
// What the window's source files share (ui/main_window*.cpp, one concept each:
// the window and its sessions; the probe by hand; the lesson; replay,
// progress and the instructor): not for use outside the window.

#include <QProxyStyle>
#include <QScrollArea>
#include <QString>
#include <algorithm>
#include <string>

namespace sulcus::ui {

inline QString Q(const std::string& s) { return QString::fromStdString(s); }

class JumpSliderStyle final : public QProxyStyle {
 public:
  using QProxyStyle::QProxyStyle;
  int styleHint(StyleHint hint, const QStyleOption* option, const QWidget* widget,
                QStyleHintReturn* returned) const override {
    if (hint == QStyle::SH_Slider_AbsoluteSetButtons)
      return Qt::LeftButton | Qt::MiddleButton;
    return QProxyStyle::styleHint(hint, option, widget, returned);
  }
};

constexpr int kPanelWidth = 380;  // px: the side docks', so the 3D view keeps 60 %
// A side panel that scrolls when the screen is short (a 1366 x 768 laptop)
// instead of holding the window taller than the screen.
inline QScrollArea* Scrolling(QWidget* panel) {
  auto* scroll = new QScrollArea;
  scroll->setWidget(panel);
  scroll->setWidgetResizable(true);
  scroll->setFrameShape(QFrame::NoFrame);
  scroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAsNeeded);
  // The 3D view comes first: a panel is at most kPanelWidth wide (its chart
  // and odontogram scale to fit).
  scroll->setMinimumWidth(std::min(panel->sizeHint().width() + 16, kPanelWidth));
  scroll->setMaximumWidth(std::max(kPanelWidth, 300));
  return scroll;
}

}  // namespace sulcus::ui
