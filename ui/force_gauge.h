#pragma once
// The live force: a bar with the lesson's scoring band marked (by default the
// rubric's 0.15 to 0.30 N), and the press the keys set (mouse and keyboard).
// (The last seconds are plotted by ForcePlot, a VTK chart.)

#include <QString>
#include <QWidget>

namespace sulcus::ui {

class ForceGauge : public QWidget {
 public:
  explicit ForceGauge(QWidget* parent = nullptr);
  /// The force now (N).
  void SetForce(double force_n);
  double force() const { return force_; }
  /// What the force is: "Force" (the tool's whole force), "Probing force" (along the
  /// probe).
  void SetLabel(const QString& label);
  void Clear() { SetForce(0); }
  /// The band of full credit the lesson scores against (N).
  void SetBand(double low_n, double high_n);
  double band_low() const { return band_low_; }
  double band_high() const { return band_high_; }
  /// The force the keyboard's press pushes with (0: none; drawn as a marker).
  void SetPress(double n);
  bool InBand() const { return force_ >= band_low_ && force_ <= band_high_; }
  static constexpr double kScaleN = 0.6;

 protected:
  void paintEvent(QPaintEvent*) override;

 private:
  double force_ = 0, press_ = 0, band_low_ = 0.15, band_high_ = 0.30;
  QString label_ = "Force";
};

}  // namespace sulcus::ui
