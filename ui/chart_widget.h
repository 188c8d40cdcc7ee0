#pragma once
// The periodontal chart as clinicians know it (after Open Dental's perio chart):
// four bands (upper buccal, upper palatal, lower lingual, lower buccal), three
// cells a tooth (distal, middle, mesial, mirrored by quadrant), rows for the
// probing depth, recession, CAL and bleeding, values of 4 mm and over in red.
// Filled from the keyboard, without the mouse: a digit enters the depth of the
// site under the cursor and advances along the lesson's path (Shift + digit for
// 10 and over), B or Space marks bleeding on the site just entered, Backspace
// steps back and clears. The site being probed is highlighted. Every entry goes
// to `on_entry` (the window stamps it with the tick and hands it to the lesson).

#include <QWidget>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "core/lesson/lesson.h"

namespace sulcus::ui {

class ChartWidget : public QWidget {
 public:
  explicit ChartWidget(QWidget* parent = nullptr);

  /// The lesson's teeth and path; clears the entries. `recession_mm` (per site,
  /// clinical) is shown and used for CAL: the lesson gives it. `missing` teeth
  /// keep their columns, marked missing, with nothing to enter.
  void SetLesson(const std::vector<int>& teeth, const std::vector<SiteRef>& path,
                 const std::map<std::pair<int, int>, double>& recession_mm,
                 const std::vector<int>& missing = {});
  void SetProbing(std::optional<SiteRef> site);  // highlighted: the site the tip is in
  void SetTruth(const std::map<std::pair<int, int>, int>&
                    truth);  // practice: shown in a row once a site is entered
  void SetEnabled(bool on);
  /// The sites with a reading: practice shows the true PD only there.
  void SetProbed(const std::set<std::pair<int, int>>& probed);
  /// A depth over this asks for Enter before it is charted.
  static constexpr int kConfirmAboveMm = 12;
  /// Waiting for Enter on this depth (over kConfirmAboveMm).
  std::optional<int> pending() const { return pending_; }
  /// "0" alone was the last key: no depth is 0 mm, so nothing was entered.
  bool zero_refused() const { return zero_refused_; }
  /// Shows a whole chart, read only (an instructor's preview of a case's truth).
  void ShowChart(const PerioChart& chart);

  std::function<void(const ChartEntry&)> on_entry;

  std::optional<SiteRef> cursor() const;
  /// Puts the cursor on a site of the path, as a click on its cell does
  /// (false: not on the path).
  bool SelectSite(const SiteRef& s);
  std::optional<int> depth(const SiteRef& s) const;
  bool bleeding(const SiteRef& s) const;
  int entered() const { return static_cast<int>(pd_.size()); }
  bool shows_truth() const { return !truth_.empty(); }
  /// Each arch's row split at the midline (the patient's right above the left),
  /// as the chart is when the whole mouth would otherwise be too small to read.
  bool wrapped() const { return wrap_; }
  QSize sizeHint() const override;
  QSize minimumSizeHint() const override;
  bool hasHeightForWidth() const override;
  int heightForWidth(int w) const override;

 protected:
  void paintEvent(QPaintEvent* e) override;
  void keyPressEvent(QKeyEvent* e) override;
  void mousePressEvent(QMouseEvent* e) override;

 private:
  struct Band {
    bool upper, buccal;
    std::vector<int> teeth;
    const char* half = "";  // wrapped: the patient's "right" or "left"
  };
  void Enter(int value);
  // Scrolls the panel the chart is in (a QScrollArea above it, if any) so
  // that the site's cells are in view: the whole mouth's chart is taller than
  // the panel.
  void ScrollTo(const SiteRef& site);
  void resizeEvent(QResizeEvent* e) override;
  // The bands for the teeth, whole arches or (wrap) split at the midline.
  std::vector<Band> MakeBands(bool wrap) const;
  QSize NaturalSize(const std::vector<Band>& bands) const;
  bool WrapFor(int width) const;
  void Layout();
  double Scale() const;  // painted at this scale to fit the width
  QRect CellRect(int band, int tooth_index, int cell, int row) const;
  int rows() const;  // the true PD row only when there is truth to show (practice)

  std::vector<int> teeth_;  // present and missing, in the lesson's order
  std::set<int> missing_;
  bool wrap_ = false;
  std::vector<Band> bands_;
  std::vector<SiteRef> path_;
  std::size_t cursor_ = 0;
  std::optional<std::size_t> last_entered_;
  std::map<std::pair<int, int>, int> pd_;
  std::map<std::pair<int, int>, bool> bleeding_;
  std::map<std::pair<int, int>, double> recession_;
  std::map<std::pair<int, int>, int> truth_;
  std::set<std::pair<int, int>> probed_;
  bool tens_ = false;           // "+" pressed: the next digit is 10 + digit
  std::optional<int> pending_;  // a depth over kConfirmAboveMm, waiting for Enter
  bool zero_refused_ = false;   // "0" alone was pressed: said, nothing entered
  std::optional<SiteRef> probing_;
  bool enabled_ = true, read_only_ = false;
};

}  // namespace sulcus::ui
