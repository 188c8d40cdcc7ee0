#include "core/anatomy/probe.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/geometry/primitives.h"

namespace sulcus {

ProbeModel MakeProbe(const std::string& name) {
  ProbeModel p;
  p.name = name;
  if (name == "williams") {
    for (double mm : {1.0, 2.0, 3.0, 5.0, 7.0, 8.0, 9.0, 10.0})
      p.markings.push_back({mm, mm, false});
    p.tip_radius_mm = 0.25;
    p.working_length_mm = 13;
  } else if (name == "unc15") {
    for (int mm = 1; mm <= 15; ++mm)
      p.markings.push_back({double(mm), double(mm), false});
    for (double from : {4.0, 9.0, 14.0}) p.markings.push_back({from, from + 1, true});
    p.tip_radius_mm = 0.25;
    p.working_length_mm = 17;
  } else if (name == "who") {
    p.markings = {{3.5, 5.5, true}, {8.5, 8.5, false}, {11.5, 11.5, false}};
    p.tip_radius_mm = 0.25;  // the 0.5 mm ball
    p.ball_tip = true;
    p.working_length_mm = 13;
  } else if (name == "explorer23" || name == "explorer1112") {
    p.tip_radius_mm = 0.1;  // sharp: the explorer's point
    p.explorer = true;
    p.working_length_mm = name == "explorer23" ? 2.0 : 5.0;
  } else {
    throw std::invalid_argument(
        "unknown instrument '" + name +
        "' (expected williams, unc15, who, explorer23 or explorer1112)");
  }
  // Centreline: from the tip up the working end, a turn of 70 degrees (the working
  // end at 110 degrees to the handle) of radius 4 mm in the x-z plane, then the
  // shank and the handle straight on.
  std::vector<Vector3> path;
  std::vector<double> radii;
  const double r_tip = p.tip_radius_mm;
  auto add = [&](const Vector3& c, double r) {
    path.push_back(c);
    radii.push_back(r);
  };
  add({0, 0, 0}, 0.0);  // pole at the tip's end
  if (p.ball_tip) {
    // A 0.5 mm ball on a thinner neck (0.2 mm radius).
    for (int i = 1; i <= 6; ++i) {
      const double a = std::numbers::pi * i / 7;  // around the ball
      add({0, 0, r_tip * (1 - std::cos(a))}, r_tip * std::sin(a));
    }
    add({0, 0, 2 * r_tip + 0.05}, 0.2);
  } else {
    for (int i = 1; i <= 4; ++i) {
      const double a = std::numbers::pi / 2 * i / 4;  // rounded end
      add({0, 0, r_tip * (1 - std::cos(a))}, r_tip * std::sin(a));
    }
  }
  if (p.explorer) {
    // The explorer: a fine point tapering to 0.4 mm, then (No. 23, the
    // shepherd's hook) a hook curling 160 degrees over and back to run along
    // rise away up and to -x, or (11/12) two bends like a probe's.
    struct Turtle {
      Vector3 at;
      double phi = 0;  // heading in the x-z plane, from +z toward -x
      Vector3 heading() const { return Vector3(-std::sin(phi), 0, std::cos(phi)); }
    } t{path.back()};
    for (double z = 0.5; z <= p.working_length_mm + 1e-9; z += 0.5) {
      t.at = Vector3(0, 0, z);
      add(t.at, r_tip + (0.4 - r_tip) * z / p.working_length_mm);
    }
    auto turn = [&](double radius, double degrees) {
      const double d = degrees * std::numbers::pi / 180;
      const int steps = std::max(4, static_cast<int>(std::abs(degrees) / 8));
      for (int i = 0; i < steps; ++i) {
        t.at += radius * (std::abs(d) / steps) * t.heading();
        t.phi += d / steps;
        add(t.at, 0.45);
      }
    };
    if (name == "explorer23") {
      turn(2.5, 160);
      turn(3.0, -100);
    } else {
      turn(3.0, 60);
      t.at += 4.0 * t.heading();
      add(t.at, 0.5);
      turn(3.0, -20);
    }
    std::vector<Vector3> cpath = path;
    std::vector<double> cradii = radii;
    for (double s = 1; s <= 8; s += 1) {
      cpath.push_back(t.at + s * t.heading());
      cradii.push_back(0.55);
    }
    cpath.push_back(t.at + 8.5 * t.heading());
    cradii.push_back(0.0);
    p.collision_mesh = MakeSweep(cpath, cradii, 16);
    for (double s = 1; s <= 12; s += 1)
      add(t.at + s * t.heading(), 0.55 + (s >= 10 ? 1.45 * (s - 9) / 3 : 0));
    for (double s = 14; s <= 90; s += 4) add(t.at + s * t.heading(), 2.0);
    add(t.at + 91 * t.heading(), 0.0);
    p.mesh = MakeSweep(path, radii, 16);
    return p;
  }
  // Working end: tapering from the tip radius to 0.5 mm.
  const double z0 = path.back().z();
  for (double z = std::ceil(z0 + 0.5); z <= p.working_length_mm; z += 1.0) {
    add({0, 0, z}, r_tip + (0.5 - r_tip) * (z / p.working_length_mm));
  }
  const double bend_r = 4.0, bend = 70 * std::numbers::pi / 180;
  const Vector3 bend_centre(-bend_r, 0, p.working_length_mm);
  for (int i = 1; i <= 12; ++i) {
    const double a = bend * i / 12;
    add(bend_centre + bend_r * Vector3(std::cos(a), 0, std::sin(a)), 0.5 + 0.1 * i / 12);
  }
  const Vector3 end_bend = path.back();
  const Vector3 dir = Vector3(-std::sin(bend), 0, std::cos(bend)).normalized();
  // What can touch the mouth: the working end, the bend and 8 mm of shank.
  {
    std::vector<Vector3> cpath = path;
    std::vector<double> cradii = radii;
    for (double s = 1; s <= 8; s += 1) {
      cpath.push_back(end_bend + s * dir);
      cradii.push_back(0.6);
    }
    cpath.push_back(end_bend + 8.5 * dir);
    cradii.push_back(0.0);
    p.collision_mesh = MakeSweep(cpath, cradii, 16);
  }
  for (double s = 1; s <= 12; s += 1)
    add(end_bend + s * dir, 0.6 + (s >= 10 ? 1.4 * (s - 9) / 3 : 0));
  for (double s = 14; s <= 90; s += 4) add(end_bend + s * dir, 2.0);  // handle
  add(end_bend + 91 * dir, 0.0);  // pole at the handle's end
  p.mesh = MakeSweep(path, radii, 16);
  return p;
}

}  // namespace sulcus
