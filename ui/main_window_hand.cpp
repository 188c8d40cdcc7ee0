// The window: the probe moved by hand without a device (keys and mouse as the
// screen shows them), where it is held back, the loupe and the blood at the
// site, and which site the probe goes to next.
#include <QVTKOpenGLNativeWidget.h>
#include <vtkCamera.h>

#include <QAbstractSpinBox>
#include <QCheckBox>
#include <QKeyEvent>
#include <QLineEdit>
#include <QMouseEvent>
#include <QStatusBar>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>

#include "core/haptics/probe_keys.h"
#include "ui/chart_widget.h"
#include "ui/force_gauge.h"
#include "ui/main_window.h"
#include "ui/main_window_parts.h"
#include "ui/mouse_device.h"
#include "ui/scene_view.h"
#include "ui/start_dialog.h"

namespace sulcus::ui {

MainWindow::ViewAxes MainWindow::CameraAxes() const {
  vtkCamera* cam = renderer_->GetActiveCamera();
  double pos[3], focal[3], up[3];
  cam->GetPosition(pos);
  cam->GetFocalPoint(focal);
  cam->GetViewUp(up);
  const Vector3 eye(pos[0], pos[1], pos[2]), at(focal[0], focal[1], focal[2]);
  ViewAxes v;
  v.into = (at - eye).normalized();
  const Vector3 u(up[0], up[1], up[2]);
  v.up = (u - u.dot(v.into) * v.into).normalized();
  v.right = v.into.cross(v.up);
  v.eye = eye;
  return v;
}

QString MainWindow::HeldBackText() const {
  // The hand far from the probe it holds: say so, and why.
  const double gap = (snapshot_.X_WH.translation() - snapshot_.X_WG.translation()).norm();
  if (gap <= kHeldBackMm) return {};
  return QString(
             "<br><span style='color:#c86400'>Your hand is <b>%1 mm</b> from the "
             "probe: a tooth or the tissue holds the probe back. Move back toward "
             "it, or press Reset tool.</span>")
      .arg(gap, 0, 'f', 1);
}

const ProbingSite* MainWindow::SceneSite(const SiteRef& s) const {
  if (!scene_) return nullptr;
  for (const ProbingSite& p : scene_->effects.sites)
    if (p.fdi == s.fdi && p.site == s.site) return &p;
  return nullptr;
}

bool MainWindow::loupe_shown() const { return view_->loupe_shown(); }

void MainWindow::UpdateLoupe(const std::optional<SiteRef>& tip) {
  const ProbingSite* site = tip ? SceneSite(*tip) : nullptr;
  if (!site || !loupe_box_->isChecked()) {
    view_->ShowLoupe(std::nullopt, Vector3::UnitX(), Vector3::UnitZ(), 1);
    return;
  }
  // Centred where the margin meets the probe, seen square to the probe from
  // outside the tooth: 8 mm across (the Williams probe's first three bands).
  const RigidTransform& X_WG = view_->graphic_pose();
  const Vector3 tip_W = X_WG.translation();
  const Vector3 axis_W = X_WG.rotation() * Vector3::UnitZ();
  const Vector3 focus_W = tip_W + axis_W * axis_W.dot(site->margin_W - tip_W);
  Vector3 out_W = site->margin_W - site->origin_W;
  out_W -= site->axis_W * out_W.dot(site->axis_W);
  out_W -= axis_W * out_W.dot(axis_W);
  if (out_W.norm() < 1e-6) out_W = axis_W.unitOrthogonal();
  // Oriented as the view: the probe's handle up on the screen when it is up
  // in the view (a lower tooth), down when it is down (an upper one).
  const Vector3 up_W = axis_W.dot(CameraAxes().up) >= 0 ? axis_W : Vector3(-axis_W);
  view_->ShowLoupe(focus_W, out_W.normalized(), up_W, 8.0);
}

bool MainWindow::PlaceProbeAt(const SiteRef& site, double above_margin_mm) {
  const ProbingSite* p = SceneSite(site);
  if (!mouse_ || !p) return false;
  // In the site's own sulcus at its angle round the tooth, along the long
  // axis, the tip above the margin (probe_keys.h: the scripted keys too).
  mouse_->Set(PoseOverSite(*p, above_margin_mm));
  // The tool goes there too, whatever stood between (a crown, the other arch):
  // the probe is never left held back behind a tooth.
  if (session_) session_->loop().Send({HapticCommand::Kind::kResetTool});
  statusBar()->showMessage(
      QString("The probe is over %1, %2 mm above the margin: press R to push it down")
          .arg(Q(site.ToString()))
          .arg(above_margin_mm, 0, 'f', 1),
      6000);
  return true;
}

void MainWindow::ShowBlood(const std::vector<BloodMark>& marks) {
  // Each mark: beads along the margin centred on the site's angle, a drop at
  // first that runs along the margin into a line 3.4 mm long.
  std::vector<std::pair<Vector3, double>> beads;
  for (const BloodMark& m : marks) {
    const ProbingSite* p = SceneSite(m.site);
    if (!p || !p->ring) continue;
    const SulcusRing& r = *p->ring;
    Vector3 at = r.ToRing(p->margin_W);
    const double phi = std::atan2(at.y(), at.x());
    const double radius = std::max(0.5, std::hypot(at.x(), at.y()));
    const double half_mm = 0.1 + 1.6 * m.grown;
    const int n = std::max(1, static_cast<int>(half_mm / 0.08));
    for (int i = -n; i <= n; ++i) {
      const double along = half_mm * i / n;
      const double fall = 1.0 - std::abs(along) / (half_mm + 0.3);
      // On the gingiva's rim just outside the sulcus, thickest at the site.
      beads.push_back({r.PointAt(phi + along / radius, -0.12, 0.35), 0.12 + 0.16 * fall});
    }
  }
  view_->ShowBlood(beads);
}

std::optional<SiteRef> MainWindow::ProbeTarget() const {
  if (!lesson_ || !lesson_spec_ || lesson_spec_->inspection()) return std::nullopt;
  if (const std::optional<SiteRef> c = chart_->cursor()) {
    for (const SiteResult& s : lesson_->sites())
      if (s.site == *c && !(s.entry && s.entry->pd_mm)) return c;
  }
  return lesson_->next_site();
}

void MainWindow::keyPressEvent(QKeyEvent* e) {
  if (!mouse_) {
    QMainWindow::keyPressEvent(e);
    return;
  }
  // Moves relative to the view (right, up, into the screen, whatever the
  // camera), mm and rad per press; turns about the tip. With Alt, fine: 0.02 mm
  // is 0.04 N at the pocket floor (2 N/mm).
  const bool fine = e->modifiers() & Qt::AltModifier;
  const double step = fine ? 0.02 : 0.1, turn = fine ? 0.01 : 0.05;
  const ViewAxes v = CameraAxes();
  Vector3 d = Vector3::Zero();
  switch (e->key()) {
    case Qt::Key_D:
      d = v.right;
      break;
    case Qt::Key_A:
      d = -v.right;
      break;
    case Qt::Key_W:
      d = v.up;
      break;
    case Qt::Key_S:
      d = -v.up;
      break;
    case Qt::Key_Q:
      d = v.into;
      break;
    case Qt::Key_E:
      d = -v.into;
      break;
    case Qt::Key_R:
    case Qt::Key_F: {
      // The press: the force the hand pushes with along the probe, 0.02 N a key.
      const double press = std::clamp(
          mouse_->press() + (e->key() == Qt::Key_R ? kPressStepN : -kPressStepN), 0.0,
          MouseKeyboardDevice::kPressMaxN);
      mouse_->SetPress(press < 1e-9 ? 0.0 : press);
      gauge_->SetPress(mouse_->press());
      lesson_gauge_->SetPress(mouse_->press());
      return;
    }
    case Qt::Key_X:  // let go: no press
      mouse_->SetPress(0);
      gauge_->SetPress(0);
      lesson_gauge_->SetPress(0);
      return;
    case Qt::Key_Comma:
    case Qt::Key_Period: {
      // The walking stroke: along the sulcus' own curve round the tooth the
      // tip is in, 0.4 mm a press, lifted 1 mm and pressed back to the floor
      // (an up-and-down stroke a press).
      const std::optional<SiteRef> at = lesson_ ? lesson_->tip_site() : std::nullopt;
      const ProbingSite* p = at ? SceneSite(*at) : nullptr;
      if (!p || !p->ring) {
        statusBar()->showMessage(
            "Walking needs the tip in a sulcus: press N to place the probe at the "
            "next site, then R to push it down",
            6000);
        return;
      }
      const RigidTransform tip = mouse_->tip_pose();
      // Comma walks to the screen's left, period to its right.
      const double right = SulcusTangent(*p->ring, tip.translation()).dot(v.right);
      const double sign = (e->key() == Qt::Key_Period) == (right >= 0) ? 1.0 : -1.0;
      if (const auto to = WalkAlongSulcus(*p, tip, sign * kWalkStepMm)) {
        mouse_->PlaceTip(*to);
        mouse_->Lift(kWalkLiftMm);
      }
      return;
    }
    case Qt::Key_T: {
      // Into the col: at an interdental site the tip goes along the sulcus
      // under the contact point and the handle leans 20 degrees away from the
      // contact (probe_keys.h); T again stands it back along the tooth.
      const std::optional<SiteRef> at = lesson_ ? lesson_->tip_site() : std::nullopt;
      if (!at || !IsInterdental(at->site)) {
        statusBar()->showMessage(
            "Tilting into the col needs the tip at an interdental site (MB, DB, ML, "
            "DL): walk to the tooth's corner with comma or period first",
            6000);
        return;
      }
      const ProbingSite* p = SceneSite(*at);
      if (!p || !p->ring) return;
      const RigidTransform tip = mouse_->tip_pose();
      const Vector3 z = tip.rotation() * Vector3::UnitZ();
      const bool tilted = z.dot(p->ring->AxisW()) < std::cos(10.0 * M_PI / 180);
      if (tilted) {
        mouse_->PlaceTip(
            RigidTransform(Quaternion::FromTwoVectors(Vector3::UnitZ(), p->ring->AxisW()),
                           tip.translation()));
      } else if (const auto to = TiltIntoCol(*p, tip)) {
        mouse_->PlaceTip(*to);
      }
      statusBar()->showMessage(tilted ? "The probe stands along the tooth again"
                                      : "The tip goes along the sulcus under the "
                                        "contact point and the probe leans 20 degrees "
                                        "away from it: the col (T again stands it back)",
                               5000);
      return;
    }
    case Qt::Key_N: {
      const std::optional<SiteRef> next = ProbeTarget();
      if (!next) {
        statusBar()->showMessage("No site is next in this lesson", 4000);
      } else if (aids_locked_) {
        statusBar()->showMessage(
            "An assessment places nothing for you: move the probe to the site", 5000);
      } else {
        PlaceProbeAt(*next, 1.0);
      }
      return;
    }
    default:
      QMainWindow::keyPressEvent(e);
      return;
  }
  if (e->modifiers() & Qt::ShiftModifier) {
    mouse_->Nudge(Vector3::Zero(), turn * d);
  } else {
    mouse_->Nudge(step * d, Vector3::Zero());
  }
}

bool MainWindow::eventFilter(QObject* watched, QEvent* e) {
  // Ctrl + drag moves the tool in the view plane, Ctrl + Shift + drag turns it,
  // Ctrl + wheel moves it along the view; without Ctrl the camera moves.
  if (watched == vtk_widget_ && mouse_ &&
      (e->type() == QEvent::MouseButtonPress || e->type() == QEvent::MouseMove ||
       e->type() == QEvent::MouseButtonRelease || e->type() == QEvent::Wheel)) {
    vtkCamera* cam = renderer_->GetActiveCamera();
    const ViewAxes axes = CameraAxes();
    const Vector3 &eye = axes.eye, &view = axes.into, &v_up = axes.up,
                  &right = axes.right;
    // Millimetres per pixel at the tool's distance from the camera.
    const double depth = std::max(1.0, (mouse_->pose().translation() - eye).dot(view));
    const double mm_per_px = 2 * depth *
                             std::tan(cam->GetViewAngle() * 0.5 * M_PI / 180) /
                             std::max(1, vtk_widget_->height());
    if (e->type() == QEvent::Wheel) {
      auto* w = static_cast<QWheelEvent*>(e);
      if (!(w->modifiers() & Qt::ControlModifier))
        return QMainWindow::eventFilter(watched, e);
      const double per_notch =
          (w->modifiers() & Qt::AltModifier) ? 0.02 : 0.2;  // mm; Alt: fine
      mouse_->Nudge(-per_notch * (w->angleDelta().y() / 120.0) * view, Vector3::Zero());
      return true;
    }
    auto* m = static_cast<QMouseEvent*>(e);
    if (e->type() == QEvent::MouseButtonPress && (m->modifiers() & Qt::ControlModifier)) {
      dragging_ = true;
      drag_from_ = m->pos();
      return true;
    }
    if (e->type() == QEvent::MouseButtonRelease && dragging_) {
      dragging_ = false;
      return true;
    }
    if (e->type() == QEvent::MouseMove && dragging_) {
      const QPoint d = m->pos() - drag_from_;
      drag_from_ = m->pos();
      if (m->modifiers() & Qt::ShiftModifier) {
        mouse_->Nudge(Vector3::Zero(), 0.01 * (d.x() * v_up + d.y() * right));
      } else {
        mouse_->Nudge(mm_per_px * (d.x() * right - d.y() * v_up), Vector3::Zero());
      }
      return true;
    }
  }
  // The probe's keys reach the probe from wherever the focus is in this window
  // (the 3D view, the chart, the feedback list, a button), except a field the
  // student types text in.
  auto* widget = qobject_cast<QWidget*>(watched);
  const bool ours =
      widget && (widget == vtk_widget_ || (lesson_ && widget->window() == this &&
                                           !qobject_cast<QLineEdit*>(widget) &&
                                           !qobject_cast<QAbstractSpinBox*>(widget)));
  if (ours && e->type() == QEvent::KeyPress && mouse_) {
    auto* k = static_cast<QKeyEvent*>(e);
    switch (k->key()) {
      case Qt::Key_W:
      case Qt::Key_A:
      case Qt::Key_S:
      case Qt::Key_D:
      case Qt::Key_Q:
      case Qt::Key_E:
      case Qt::Key_R:
      case Qt::Key_F:
      case Qt::Key_X:
      case Qt::Key_N:
      case Qt::Key_T:
      case Qt::Key_Comma:
      case Qt::Key_Period:
        keyPressEvent(k);
        return true;
      default:
        break;
    }
  }
  return QMainWindow::eventFilter(watched, e);
}

}  // namespace sulcus::ui
