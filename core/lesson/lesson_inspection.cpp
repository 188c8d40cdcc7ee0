// The inspection lesson's flow in LessonRun: the steps followed from the
// units the tip examines, findings recorded, the views sent, the submission, and
// what the current step still asks for (the probing flow is in lesson.cpp).
#include <algorithm>

#include "core/lesson/lesson.h"

namespace sulcus {

void LessonRun::FollowInspection(const TickRecord& r) {
  inspection_->OnTick(r, in_contact_);
  // Practice: the truth of a surface or region when it is first examined (only
  // where there is something to find; assessment says nothing).
  if (spec_.practice() && inspection_->tip_unit() >= 0) {
    const InspectionUnit& unit =
        inspection_->units()[static_cast<std::size_t>(inspection_->tip_unit())];
    if (unit.touched && unit.first_tick == r.tick) {
      if (!unit.region.empty()) {
        const auto it = truth_.lesions.find(unit.region);
        if (it != truth_.lesions.end())
          feedback_.push_back(RegionLabel(unit.region) + ": there is " + it->second +
                              " here");
      } else if (const ToothRecord* t = truth_.Find(unit.fdi)) {
        if (t->caries[static_cast<std::size_t>(unit.surface)])
          feedback_.push_back(unit.Name() +
                              ": a carious lesion here (softer, it may catch the tip)");
        const bool side = unit.surface == ToothSurface::kBuccal ||
                          unit.surface == ToothSurface::kLingual;
        if (side && t->calculus)
          feedback_.push_back(std::to_string(unit.fdi) + ": calculus on this tooth");
        if (side && t->inflamed)
          feedback_.push_back(std::to_string(unit.fdi) + ": its gingiva is inflamed");
      }
    }
  }
  // The student has moved on when half the units of the next step (at least
  // one) are examined: this step ends as skipped, with what it missed. (A
  // tooth touched on the way to a cheek does not move the lesson on.)
  const int u = inspection_->tip_unit();
  if (u < 0 || done()) return;
  const auto& units = inspection_->units();
  if (!units[static_cast<std::size_t>(u)].touched ||
      units[static_cast<std::size_t>(u)].first_tick != r.tick)
    return;
  const int n = static_cast<int>(spec_.steps.size());
  auto in_step = [&](int k, int unit) {
    const auto& us = step_units_[static_cast<std::size_t>(k)];
    return std::find(us.begin(), us.end(), unit) != us.end();
  };
  for (int k = 0; k <= step_; ++k)
    if (in_step(k, u)) return;
  // Only the next step: a region brushed on the way to another does not carry
  // the lesson past several steps.
  const int next = step_ + 1;
  if (next >= n || !in_step(next, u)) return;
  int examined = 0;
  for (int m : step_units_[static_cast<std::size_t>(next)])
    examined += units[static_cast<std::size_t>(m)].touched;
  if (2 * examined < static_cast<int>(step_units_[static_cast<std::size_t>(next)].size()))
    return;
  LeaveStepsUntil(next, r.tick);
}

void LessonRun::LeaveStepsUntil(int later, std::uint64_t tick) {
  const auto& units = inspection_->units();
  while (step_ < later && step_ < static_cast<int>(spec_.steps.size())) {
    StepResult& res = step_results_[static_cast<std::size_t>(step_)];
    res.skipped = true;
    res.ended_tick = std::max(tick, res.started_tick);
    for (int m : step_units_[static_cast<std::size_t>(step_)])
      if (!units[static_cast<std::size_t>(m)].touched)
        res.missed.push_back(units[static_cast<std::size_t>(m)].Name());
    if (later < static_cast<int>(spec_.steps.size()))
      feedback_.push_back("step '" + res.id + "' left for '" +
                          spec_.steps[static_cast<std::size_t>(later)].id +
                          "' before it was done");
    ++step_;
    if (step_ < static_cast<int>(spec_.steps.size()))
      step_results_[static_cast<std::size_t>(step_)].started_tick = tick;
  }
}

void LessonRun::Record(const Finding& f) {
  findings_.push_back(f);
  odontogram_.Apply(f);
  Advance(f.tick == kAfterReading ? last_tick_ : f.tick);
}

void LessonRun::View(const ViewSample& v) {
  views_.push_back(v);
  if (inspection_) inspection_->OnView(v);
}

void LessonRun::Submit(std::uint64_t tick) {
  submitted_ = tick == kAfterReading ? last_tick_ : tick;
  // Submitting says the examination is over: the steps still open before the
  // recording step are left, with what they missed.
  if (inspection_ && !done()) {
    int record = -1;
    for (int k = step_; k < static_cast<int>(spec_.steps.size()) && record < 0; ++k)
      if (spec_.steps[static_cast<std::size_t>(k)].complete ==
          StepSpec::Complete::kRecorded)
        record = k;
    if (record > step_ && !StepComplete(spec_.steps[static_cast<std::size_t>(step_)]))
      LeaveStepsUntil(record, *submitted_);
  }
  Advance(*submitted_);
}

std::vector<std::string> LessonRun::pending() const {
  std::vector<std::string> out;
  if (!inspection_ || done()) return out;
  for (int u : step_units_[static_cast<std::size_t>(step_)]) {
    const InspectionUnit& unit = inspection_->units()[static_cast<std::size_t>(u)];
    if (!unit.touched) out.push_back(unit.Name());
  }
  return out;
}

}  // namespace sulcus
