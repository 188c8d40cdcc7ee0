#pragma once
// The 3D view of a compiled scene: every object with a material that reads as
// its tissue, the device ("haptic") tool in translucent blue and the rendered
// ("graphic") tool in white with the probe's markings, contact spheres, and the
// sphere-trees at any level. Reads snapshots only (docs/architecture.md).

#include <vtkActor.h>
#include <vtkDoubleArray.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTextActor.h>

#include <optional>
#include <vector>

#include "core/anatomy/probe.h"
#include "core/haptics/haptic_loop.h"
#include "core/scene/scene.h"

namespace sulcus::ui {

class SceneView {
 public:
  explicit SceneView(vtkRenderer* renderer);

  /// Replaces what is shown by the scene (which must outlive the view's use of it).
  /// `seen`: the shares of the gingiva as the eye sees them (CompiledScene::seen),
  /// drawn instead of the engine's meshes; null: everything as the engine has it.
  void Load(const CompiledScene& scene, const SeenGingiva* seen = nullptr);
  /// Moves the tools and highlights contacts from the latest snapshot.
  void Update(const HapticSnapshot& s);
  /// A demonstration's probe beside the live one (green, translucent); empty hides it.
  void ShowGhost(const std::optional<RigidTransform>& X_WG);
  const std::optional<RigidTransform>& ghost() const { return ghost_; }

  /// Blood at the gingival margin: beads (world point, radius mm); empty hides it.
  void ShowBlood(const std::vector<std::pair<Vector3, double>>& beads);
  int blood_beads() const { return blood_shown_; }
  /// Shows the spheres of every object's tree cut at `level` (0 root); -1 hides them.
  void ShowSpheres(int level);
  int spheres_shown() const { return spheres_shown_; }
  void ShowContacts(bool on) { show_contacts_ = on; }
  void SetGingivaTranslucent(bool on);

  /// Hides the lips and cheeks from the picture (as a retractor would hold them
  /// out of the view); the instrument still meets them.
  void SetLipsAndCheeksHidden(bool hidden);
  bool lips_and_cheeks_hidden() const { return lips_hidden_; }

  enum class Side { kBuccal, kLingual, kOcclusal, kFront, kUpperOcclusal };
  void View(Side side);
  /// The camera at `focus` + `distance` * `from_dir`, looking at `focus`.
  void LookAt(const Vector3& focus, const Vector3& from_dir, double distance,
              const Vector3& up) {
    Frame(focus, from_dir, distance, up);
  }
  /// Frames one tooth from its buccal side (or its lingual or palatal side,
  /// from inside the arch, close enough that the other side's teeth do not
  /// hide it), the head upright; false if the scene has no such tooth.
  bool LookAtTooth(int fdi, bool lingual = false);

  /// A magnified inset over a corner of the same window: `loupe` draws what
  /// the main view draws; `overlay` (a renderer on the window's upper layer with
  /// the loupe's viewport) draws the probe's markings over whatever hides them,
  /// so that where the gingival margin crosses them can be read. Both are
  /// hidden until ShowLoupe.
  void AttachLoupe(vtkRenderer* loupe, vtkRenderer* overlay);
  /// Points the loupe at `focus` from `from_dir` (unit), `up` on screen, with
  /// `width_mm` across; no focus hides it.
  void ShowLoupe(const std::optional<Vector3>& focus, const Vector3& from_dir,
                 const Vector3& up, double width_mm);
  bool loupe_shown() const { return loupe_shown_; }

  const RigidTransform& graphic_pose() const { return X_WG_; }
  /// The camera now: position, focal point, up and vertical view angle (degrees).
  struct CameraPose {
    Vector3 eye, focal, up;
    double view_angle_deg = 30;
  };
  CameraPose Camera() const;
  /// How many soft tissues the current view looks through (shown see-through).
  int see_through() const { return see_through_; }

 private:
  void AddToolActors(const ProbeModel& probe);
  void Frame(const Vector3& focus, const Vector3& from_dir, double distance,
             const Vector3& up);

  vtkRenderer* renderer_;
  vtkRenderer* loupe_ = nullptr;
  vtkRenderer* overlay_ = nullptr;
  std::vector<vtkSmartPointer<vtkActor>> overlay_marks_;  // moved with the tool
  vtkSmartPointer<vtkTextActor> loupe_caption_;
  bool loupe_shown_ = false;
  void FillLoupe();
  const CompiledScene* scene_ = nullptr;
  std::vector<vtkSmartPointer<vtkActor>> objects_, gingiva_, tool_graphic_, spheres_,
      contacts_;
  vtkSmartPointer<vtkActor> tool_haptic_, tool_ghost_, contact_actor_;
  std::optional<RigidTransform> ghost_;
  vtkSmartPointer<vtkPoints> contact_points_;
  vtkSmartPointer<vtkDoubleArray> contact_radii_;
  vtkSmartPointer<vtkPolyData> contact_poly_;
  vtkSmartPointer<vtkActor> blood_actor_;
  vtkSmartPointer<vtkPoints> blood_points_;
  vtkSmartPointer<vtkDoubleArray> blood_radii_;
  vtkSmartPointer<vtkPolyData> blood_poly_;
  int blood_shown_ = 0;
  RigidTransform X_WG_;
  int spheres_shown_ = -1;
  int see_through_ = 0;
  bool fade_upper_ = false, fade_lower_ = false, gingiva_translucent_ = false,
       lips_hidden_ = false;
  // The seen gingiva's flat caps between shares (object index, actor): shown
  // only while their share is drawn opaque.
  std::vector<std::pair<std::size_t, vtkSmartPointer<vtkActor>>> caps_;
  void SyncCaps();
  bool show_contacts_ = true;
};

}  // namespace sulcus::ui
