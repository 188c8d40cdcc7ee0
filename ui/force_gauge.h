#pragma once
// The live force: a bar with the clinical probing band (0.20 to 0.25 N) marked.
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
  bool InBand() const { return force_ >= kBandLow && force_ <= kBandHigh; }
  static constexpr double kBandLow = 0.20, kBandHigh = 0.25, kScaleN = 0.6;

 protected:
  void paintEvent(QPaintEvent*) override;

 private:
  double force_ = 0;
  QString label_ = "Force";
};

}  // namespace sulcus::ui
