#pragma once
// The odontogram for inspection lessons: every tooth of the lesson in the FDI
// layout (upper 18-11 | 21-28 over lower 48-41 | 31-38), each drawn as the
// five-surface diagram clinicians chart on (occlusal in the middle, buccal
// toward the lips and cheeks, lingual toward the tongue, mesial toward the
// midline), with its WHO status code, calculus (Ca) and inflamed gingiva (G)
// under it; then the soft-tissue regions with the lesion recorded on each.
//
// With the mouse: click a surface to mark or clear caries, click Ca or G, right
// click a tooth for its status code, click a region for its lesion. With the
// keyboard: arrows choose the tooth, M D B L O mark a surface, C calculus, G
// gingiva, 0-9 the status code. Surfaces the tip has examined are shaded, so a
// student sees what is left. Every change goes to `on_finding`.

#include <QWidget>
#include <functional>
#include <string>
#include <vector>

#include "core/lesson/inspection.h"

namespace sulcus::ui {

class OdontogramWidget : public QWidget {
 public:
  explicit OdontogramWidget(QWidget* parent = nullptr);

  /// The lesson's teeth and regions; clears what was recorded.
  void SetLesson(const std::vector<int>& teeth, const std::vector<std::string>& regions);
  /// What the tip has examined (InspectionUnit::Name: "36 B", "cheek_left"), and
  /// prefixed "seen:" what the view has shown but the tip has not examined.
  void SetExamined(const std::vector<std::string>& units);
  /// The tooth the tip is on, highlighted (0: none).
  void SetTouching(int fdi) {
    touching_ = fdi;
    update();
  }
  void SetEnabled(bool on) {
    enabled_ = on;
    update();
  }
  /// Shows what the lesson holds as recorded (findings may come from elsewhere:
  /// a scripted inspector, an answers file).
  void Show(const Odontogram& o) {
    odontogram_ = o;
    update();
  }
  /// Records a finding as if the student had clicked it (also from the keyboard).
  void Apply(const Finding& f);

  std::function<void(const Finding&)> on_finding;

  const Odontogram& odontogram() const { return odontogram_; }
  int selected() const { return selected_; }
  QSize sizeHint() const override;
  QSize minimumSizeHint() const override { return sizeHint(); }

 protected:
  void paintEvent(QPaintEvent* e) override;
  void keyPressEvent(QKeyEvent* e) override;
  void mousePressEvent(QMouseEvent* e) override;
  void resizeEvent(QResizeEvent*) override { Layout(); }

 private:
  struct Cell {
    int fdi;
    QRect box;  // the five-surface diagram
    QRect ca, g, status;
  };
  void Layout();
  int SideColumns() const;  // teeth a quadrant shows: 8 with third molars, else 7
  // The surface of a tooth's diagram at a point, -1 outside.
  int SurfaceAt(const Cell& c, const QPoint& p) const;
  void Toggle(int fdi, Finding::Kind kind, ToothSurface s = ToothSurface::kOcclusal);
  void AskStatus(int fdi, const QPoint& where);
  void AskLesion(const std::string& region, const QPoint& where);

  std::vector<int> teeth_;
  std::vector<std::string> regions_;
  std::vector<Cell> cells_;
  std::vector<std::pair<std::string, QRect>> region_rects_;
  std::vector<std::string> examined_;
  Odontogram odontogram_;
  int selected_ = 0, touching_ = 0;
  bool enabled_ = true;
};

}  // namespace sulcus::ui
