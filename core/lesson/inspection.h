#pragma once
// Inspection lessons: what an oral examination covers (the regions of the
// mouth, the five surfaces of every tooth), what the student records on an
// odontogram (per tooth its WHO status, carious surfaces, calculus, inflamed
// gingiva; per region a soft-tissue lesion), the scene's truth in the same
// form, and the tracker that follows the instrument's tip over the tick stream:
// which region or surface it examined and when, and which lesion it pressed
// how hard.

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/anatomy/findings.h"
#include "core/lesson/lesson_spec.h"
#include "core/scene/scene.h"

namespace sulcus {

struct TickRecord;

/// The regions an inspection lesson can name, in the order of an oral
/// examination: lip_upper, lip_lower, cheek_right, cheek_left, gingiva_upper,
/// gingiva_lower, tongue_dorsum, tongue_lateral_border_right,
/// tongue_lateral_border_left, tongue_ventral, floor_of_mouth, palate,
/// soft_palate.
const std::vector<std::string>& InspectionRegionNames();
/// In words: "the upper lip", "the right buccal mucosa", "the tongue's left lateral
/// border".
std::string RegionLabel(const std::string& region);
/// The regions a scene has: its anatomy objects' (the tongue's four parts)
/// and the gingiva of each arch that has gingiva or a jaw.
std::vector<std::string> SceneRegions(const SceneSpec& scene);
/// The region a scene's soft-tissue lesion is on ("tongue", "lateral_border_left"
/// -> "tongue_lateral_border_left"; "cheek_left", "centre" -> "cheek_left").
std::string LesionRegion(const std::string& anatomy, const std::string& lesion_region);

/// Surface codes M, D, B, L, O (B is also labial, L palatal, O incisal).
const char* SurfaceCode(ToothSurface s);
std::optional<ToothSurface> SurfaceFromCode(const std::string& code);

/// WHO oral health survey tooth status codes: 0 sound, 1 decayed, 2 filled with
/// decay, 3 filled, 4 missing (caries), 5 missing (other), 6 sealant, 7 crown
/// or implant, 8 unerupted, 9 not recorded.
const char* WhoStatusName(int code);

/// One thing the student recorded, at a tick. A finding that is `present:
/// false` withdraws an earlier one.
struct Finding {
  enum class Kind { kStatus, kCaries, kCalculus, kInflamed, kLesion };
  std::uint64_t tick = kAfterReading;
  Kind kind = Kind::kCaries;
  int fdi = 0;                                     // teeth
  ToothSurface surface = ToothSurface::kOcclusal;  // kCaries
  int status = 0;                                  // kStatus: WHO code
  std::string region, lesion;  // kLesion: where and which kind (ulcer, ...)
  bool present = true;
  std::string ToString()
      const;  // "caries 36 O", "lesion ulcer on tongue_lateral_border_left"
};
const char* ToString(Finding::Kind k);

struct ToothRecord {
  int fdi = 0;
  std::optional<int>
      status;  // as recorded; empty: not recorded (1 when caries is, else 0)
  std::array<bool, 5> caries{};
  bool calculus = false, inflamed = false;
  int Status() const;  // the recorded status, or the one the caries marks imply
};

/// The odontogram: per tooth and per region, what is recorded.
struct Odontogram {
  std::vector<ToothRecord> teeth;
  std::map<std::string, std::string> lesions;  // region -> kind
  ToothRecord* Find(int fdi);
  const ToothRecord* Find(int fdi) const;
  /// Applies a finding (teeth not on it are ignored, false returned).
  bool Apply(const Finding& f);
};
/// An empty odontogram over these teeth.
Odontogram EmptyOdontogram(const std::vector<int>& teeth);
/// The scene's truth over the lesson's teeth and regions: carious surfaces,
/// calculus (any deposit), inflamed gingiva (any site), status 1 for a tooth
/// with caries and 0 otherwise (scenes have no fillings yet), the lesions.
Odontogram TrueOdontogram(const SceneSpec& scene, const std::vector<int>& teeth,
                          const std::vector<std::string>& regions);

/// What an inspection covers: a region, or one surface of one tooth.
struct InspectionUnit {
  std::string region;  // empty for a tooth surface
  int fdi = 0;
  ToothSurface surface = ToothSurface::kOcclusal;
  std::string Name() const;  // "cheek_left", "36 L"
  bool touched = false;
  std::uint64_t first_tick = 0;  // when the tip had dwelt on it long enough
  double dwell_s = 0;
  bool seen = false;  // in a recorded view (window attempts)
  std::uint64_t seen_tick = 0;
};

/// The window's camera at a tick: where it is, what it looks at, its up and its
/// vertical view angle. A unit is seen when its surface point lies inside the
/// view's cone (the vertical angle, and the same across), within 150 mm, faces
/// the camera, and, for a tooth's surface, nothing of its arch lies between (a
/// neighbour, the tooth itself, the gingiva, the jaw: the line of sight, up to
/// kViewClearMm off the surface, meets no sphere of their trees). The lips,
/// cheeks and tongue do not hide: the window shows them see-through when they
/// are in the way, as a mirror retracts them; nor does the other arch, which
/// the window's occlusal views fade.
struct ViewSample {
  std::uint64_t tick = 0;
  Vector3 eye = Vector3::Zero(), focal = -Vector3::UnitY(), up = Vector3::UnitZ();
  double view_angle_deg = 30;
};

/// Where an instrument examines a unit from (world frame): a point on its
/// surface and the surface's outward normal there, the tool's axis while there
/// (the way out of the mouth), where its shank leans, and where the tip starts
/// its way in (zero: off the surface and up the axis). Empty when the scene
/// lacks the unit's object.
struct UnitApproach {
  Vector3 p = Vector3::Zero(), n = Vector3::UnitZ(), axis = Vector3::UnitZ(),
          shank = Vector3::Zero();
  Vector3 pre = Vector3::Zero();
  bool region = false;
};
std::optional<UnitApproach> ApproachOf(const CompiledScene& scene,
                                       const InspectionUnit& unit,
                                       const std::vector<int>& teeth);
/// Other spots on a tooth's mesial or distal surface than ApproachOf's (nearer
/// the buccal, nearer the contact, and from the lingual side), for a hand whose
/// way to the first is blocked by the neighbour. Empty for other surfaces.
std::vector<UnitApproach> ProximalSpots(const CompiledScene& scene, int fdi,
                                        ToothSurface s);

/// A lesion pressed harder than the lesson's limit: one episode, at its peak.
struct LesionPress {
  std::string where;  // "36 O", "tongue_lateral_border_left"
  double force_n = 0;
  std::uint64_t tick = 0;
};

/// Follows the tip over the tick stream: a region or surface is examined when
/// the tip rests on it (its object in contact, the tip's centre within its
/// radius and 0.5 mm of the object's sphere-tree: the point or the side of its
/// last half millimetre, as an explorer is laid on a surface) for the rubric's
/// dwell without a break;
/// the surface of a tooth from the side the tip is on (occlusal where the
/// surface faces the crown's top or within 1 mm of it); the tongue's part from
/// the way its surface faces there.
class InspectionTracker {
 public:
  InspectionTracker(const LessonSpec& spec, const CompiledScene& scene);
  /// `in_contact` per scene object, as the contact events left it.
  void OnTick(const TickRecord& r, const std::vector<std::uint8_t>& in_contact);
  /// A view of the window's camera: the units it shows are seen (from its tick on).
  void OnView(const ViewSample& v);
  const std::vector<InspectionUnit>& units() const { return units_; }
  /// The unit index of a region or tooth surface, -1 when the lesson does not cover it.
  int UnitOf(const std::string& region) const;
  int UnitOf(int fdi, ToothSurface s) const;
  /// The units a step examines (indices into units()).
  std::vector<int> StepUnits(const StepSpec& step) const;
  /// The unit the tip was on at the last tick (-1: none).
  int tip_unit() const { return tip_unit_; }
  /// Episodes still open are closed at their peak.
  std::vector<LesionPress> presses() const;
  double tip_radius_mm() const { return tip_radius_; }

  /// How far off a unit's surface its line of sight is checked from (the
  /// spheres of its own object and its neighbours cover the surface from outside).
  static constexpr double kViewClearMm = 1.0;

 private:
  // Whether anything of tooth fdi's arch lies between the eye and the spot (world).
  bool Hidden(int fdi, const Vector3& eye_W, const Vector3& spot_W) const;
  struct Lesion {
    std::string where;
    int object = -1;
    Vector3 centre_W, normal_W;
    double radius_mm = 0;
    bool pressing = false;
    double peak = 0;
    std::uint64_t peak_tick = 0;
  };
  // What an object stands for: a tooth (its teeth index), a region, the tongue (split),
  // nothing.
  struct ObjectRole {
    int tooth = -1;
    int unit = -1;
    bool tongue = false;
    double top_z =
        0;  // a tooth's crown top (its frame): within 1 mm of it is occlusal (incisal)
  };
  const LessonSpec& spec_;
  const CompiledScene& scene_;
  std::vector<InspectionUnit> units_;
  std::vector<std::optional<UnitApproach>> spots_;  // per unit, where it is (for views)
  std::vector<int>
      teeth_;  // the lesson's, in units_ order (5 units each after the regions)
  int first_tooth_unit_ = 0;
  std::vector<ObjectRole> roles_;
  std::vector<RigidTransform> X_OW_;
  std::vector<std::uint64_t> dwell_ticks_;
  std::vector<Lesion> lesions_;
  std::vector<LesionPress> presses_;
  double tip_radius_ = 0.25, rate_hz_ = 1000;
  std::uint64_t dwell_needed_ = 50;
  int tip_unit_ = -1, run_unit_ = -1;
  std::uint64_t run_ = 0;
};

}  // namespace sulcus
