#pragma once
// What a periodontal chart does not hold and the 2017 classification needs for
// stage IV and the grade: the patient's history and what a radiograph shows. A
// scene's `patient:` (scenes/README.md); the bone loss is measured on the
// scene's anatomy, as a radiograph would show it.

#include <optional>
#include <string>

namespace sulcus {

struct PatientFacts {
  bool given = false;  // the scene names a patient
  std::optional<int> age_years;
  int cigarettes_per_day = 0;
  std::optional<double> hba1c_pct;  // given: the patient has diabetes, with this HbA1c
  int teeth_lost_to_periodontitis = 0;
  bool drifting_flaring = false;  // pathological migration, flaring of the front teeth
  bool bite_collapse = false;     // masticatory dysfunction, a collapsed bite
  std::optional<int> opposing_pairs;  // occluding pairs of teeth left
  // Radiographic bone loss at the worst site, % of the root below a healthy
  // crest (set from the anatomy: TrueChart).
  std::optional<double> bone_loss_pct;
};

/// A tooth the scene's `missing:` lists: why it was lost (periodontitis,
/// caries, trauma, orthodontic, congenital or unknown) and where it was given.
struct MissingTooth {
  std::string reason;
  int line = 0, column = 0;
};

}  // namespace sulcus
