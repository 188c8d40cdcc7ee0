#include "ui/scene_view.h"

#include <vtkActorCollection.h>
#include <vtkCamera.h>
#include <vtkCylinderSource.h>
#include <vtkDoubleArray.h>
#include <vtkGlyph3D.h>
#include <vtkIdTypeArray.h>
#include <vtkMatrix4x4.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkSphereSource.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkTransform.h>
#include <vtkTransformPolyDataFilter.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/anatomy/arch.h"
#include "core/anatomy/findings.h"
#include "core/anatomy/soft_tissue.h"
#include "ui/mesh_view.h"

namespace sulcus::ui {
namespace {

struct Look {
  double r, g, b, opacity, specular;
};

Look LookOf(Tissue t) {
  switch (t) {
    case Tissue::kEnamel:
      return {0.95, 0.93, 0.86, 1.0, 0.5};
    case Tissue::kRoot:
      return {0.90, 0.84, 0.64, 1.0, 0.2};
    case Tissue::kGingiva:
      return {0.86, 0.48, 0.52, 1.0, 0.25};
    case Tissue::kBone:
      return {0.92, 0.87, 0.74, 1.0, 0.1};
    case Tissue::kTongue:
      return {0.80, 0.38, 0.42, 1.0, 0.3};
    case Tissue::kCheek:
      return {0.90, 0.60, 0.60, 0.35, 0.2};
    case Tissue::kPalate:
      return {0.86, 0.52, 0.56, 1.0, 0.25};
    case Tissue::kLip:
      return {0.80, 0.40, 0.45, 1.0, 0.3};
    case Tissue::kMucosa:
      return {0.88, 0.56, 0.58, 1.0, 0.25};
    case Tissue::kMetal:
      return {0.70, 0.72, 0.75, 1.0, 0.8};
    case Tissue::kCalculus:
      return {0.78, 0.70, 0.44, 1.0, 0.1};
  }
  return {0.8, 0.8, 0.8, 1.0, 0.2};
}

// Per-vertex colours: `base` blended toward the finding's colours by weight
// (0: untouched, 1: the finding's centre).
enum class Paint { kCaries, kCavity, kInflamed, kUlcer, kWhite, kRed };

// `cavity` (caries only): per vertex, the weight of the cavitated lesions among
// `weight`; where it is the larger, the vertex takes the cavity's colours.
// `skin` (a lip): per vertex, how far its base colour is the skin's.
void PaintVertices(vtkActor* actor, const std::vector<double>& weight, const Look& base,
                   Paint paint, const std::vector<double>* cavity = nullptr,
                   const std::vector<double>* skin = nullptr) {
  auto* mapper = vtkPolyDataMapper::SafeDownCast(actor->GetMapper());
  auto* poly = vtkPolyData::SafeDownCast(mapper->GetInput());
  // (a point of the polydata may be one of several made from a mesh vertex)
  auto* source =
      vtkIdTypeArray::SafeDownCast(poly->GetPointData()->GetArray(kSourceVertexArray));
  auto colours = vtkSmartPointer<vtkUnsignedCharArray>::New();
  colours->SetNumberOfComponents(3);
  colours->SetName("finding");
  colours->SetNumberOfTuples(poly->GetNumberOfPoints());
  const Vector3 base_colour(base.r, base.g, base.b);
  // Caries: a chalky white rim (demineralised enamel) around a brown centre.
  // Inflamed gingiva, erythroplakia: deep red. An ulcer: a yellow-grey fibrin
  // floor in a red halo. Leukoplakia: a white patch.
  // A cavitated lesion: the chalky rim, brown walls, a dark floor.
  const Vector3 rim(0.99, 0.98, 0.95), centre(0.36, 0.22, 0.12), floor(0.16, 0.09, 0.05),
      red(0.80, 0.16, 0.20);
  const Vector3 fibrin(0.90, 0.86, 0.66), white(0.96, 0.95, 0.92);
  auto blend = [](const Vector3& a, const Vector3& b, double t) {
    return Vector3(a + (b - a) * std::clamp(t, 0.0, 1.0));
  };
  const Vector3 skin_colour(0.88, 0.68, 0.58);
  std::vector<Vector3> colour(weight.size(), base_colour);
  for (std::size_t i = 0; i < weight.size(); ++i) {
    double w = weight[i];
    Paint p = paint;
    const Vector3 from = skin && i < skin->size()
                             ? blend(base_colour, skin_colour, (*skin)[i])
                             : base_colour;
    if (cavity && i < cavity->size() && (*cavity)[i] > 0 && (*cavity)[i] >= w) {
      w = (*cavity)[i];
      p = Paint::kCavity;
    }
    Vector3 c = from;
    switch (p) {
      case Paint::kCaries:
        c = w < 0.3 ? blend(from, rim, w / 0.3) : blend(rim, centre, (w - 0.3) / 0.7);
        break;
      case Paint::kCavity:
        c = w < 0.2   ? blend(from, rim, w / 0.2)
            : w < 0.5 ? blend(rim, centre, (w - 0.2) / 0.3)
                      : blend(centre, floor, (w - 0.5) / 0.3);
        break;
      case Paint::kInflamed:
      case Paint::kRed:
        c = blend(from, red, w);
        break;
      case Paint::kUlcer:
        c = w < 0.35 ? blend(from, red, w / 0.35) : blend(red, fibrin, (w - 0.35) / 0.25);
        break;
      case Paint::kWhite:
        c = blend(from, white, w / 0.3);
        break;
    }
    colour[i] = c;
  }
  for (vtkIdType p = 0; p < poly->GetNumberOfPoints(); ++p) {
    const vtkIdType v = source ? source->GetValue(p) : p;
    const Vector3 c = v < static_cast<vtkIdType>(colour.size())
                          ? colour[static_cast<std::size_t>(v)]
                          : base_colour;
    colours->SetTuple3(p, 255 * c.x(), 255 * c.y(), 255 * c.z());
  }
  poly->GetPointData()->SetScalars(colours);
  mapper->SetColorModeToDirectScalars();
  mapper->ScalarVisibilityOn();
}

vtkSmartPointer<vtkMatrix4x4> ToVtk(const RigidTransform& X) {
  auto m = vtkSmartPointer<vtkMatrix4x4>::New();
  const Matrix4 T = X.ToMatrix4();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m->SetElement(r, c, T(r, c));
  return m;
}

vtkSmartPointer<vtkActor> MeshActor(const TriangleMesh& mesh, const Look& look,
                                    const std::vector<Vector3>* normals = nullptr) {
  auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
  mapper->SetInputData(ToPolyData(mesh, kCreaseDeg, normals));
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(look.r, look.g, look.b);
  actor->GetProperty()->SetOpacity(look.opacity);
  actor->GetProperty()->SetSpecular(look.specular);
  actor->GetProperty()->SetSpecularPower(30);
  return actor;
}

// A sphere at every point of `poly`, of the radius in its point scalars.
vtkSmartPointer<vtkActor> SphereGlyphs(vtkPolyData* poly, int theta, int phi) {
  auto sphere = vtkSmartPointer<vtkSphereSource>::New();
  sphere->SetRadius(1.0);
  sphere->SetThetaResolution(theta);
  sphere->SetPhiResolution(phi);
  auto glyph = vtkSmartPointer<vtkGlyph3D>::New();
  glyph->SetInputData(poly);
  glyph->SetSourceConnection(sphere->GetOutputPort());
  glyph->SetScaleModeToScaleByScalar();
  glyph->SetScaleFactor(1.0);
  auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
  mapper->SetInputConnection(glyph->GetOutputPort());
  mapper->ScalarVisibilityOff();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  return actor;
}

}  // namespace

SceneView::SceneView(vtkRenderer* renderer) : renderer_(renderer) {
  renderer_->SetBackground(0.16, 0.17, 0.20);
  renderer_->SetBackground2(0.32, 0.34, 0.40);
  renderer_->GradientBackgroundOn();
}

void SceneView::AddToolActors(const ProbeModel& probe) {
  tool_haptic_ = MeshActor(probe.mesh, {0.30, 0.55, 1.0, 0.35, 0.2});
  renderer_->AddActor(tool_haptic_);
  tool_ghost_ = MeshActor(probe.mesh, {0.35, 0.85, 0.45, 0.45, 0.2});
  tool_ghost_->SetVisibility(false);
  renderer_->AddActor(tool_ghost_);
  tool_graphic_.push_back(MeshActor(probe.mesh, {0.97, 0.97, 0.97, 1.0, 0.8}));
  // The markings: dark rings (lines) and coloured bands around the working end.
  for (const ProbeMarking& m : probe.markings) {
    auto ring = vtkSmartPointer<vtkCylinderSource>::New();
    const double length = std::max(0.18, m.to_mm - m.from_mm);
    ring->SetRadius(0.56);
    ring->SetHeight(length);
    ring->SetResolution(24);
    auto place = vtkSmartPointer<vtkTransform>::New();  // cylinder along y -> along z,
                                                        // centred on the mark
    place->Translate(0, 0, 0.5 * (m.from_mm + m.to_mm));
    place->RotateX(90);
    auto moved = vtkSmartPointer<vtkTransformPolyDataFilter>::New();
    moved->SetInputConnection(ring->GetOutputPort());
    moved->SetTransform(place);
    auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
    mapper->SetInputConnection(moved->GetOutputPort());
    auto actor = vtkSmartPointer<vtkActor>::New();
    actor->SetMapper(mapper);
    if (m.band) {
      actor->GetProperty()->SetColor(0.10, 0.10, 0.12);
    } else {
      actor->GetProperty()->SetColor(0.15, 0.15, 0.15);
    }
    tool_graphic_.push_back(actor);
  }
  for (auto& a : tool_graphic_) renderer_->AddActor(a);
}

void SceneView::Load(const CompiledScene& scene, const SeenGingiva* seen) {
  renderer_->RemoveAllViewProps();
  objects_.clear();
  caps_.clear();
  gingiva_.clear();
  tool_graphic_.clear();
  spheres_.clear();
  scene_ = &scene;
  for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
    const ObjectSpec& o = scene.spec.objects[i];
    Look look = LookOf(o.tissue);
    // The jaws are bone under alveolar mucosa: drawn as the mucosa, a deeper
    // red than the attached gingiva.
    if (o.kind == ObjectSpec::Kind::kAnatomy && o.tissue == Tissue::kBone)
      look = {0.78, 0.40, 0.44, 1.0, 0.25};
    // A share of the gingiva drawn as the eye sees it (its sulcus closed round
    // the tooth, its papillae full), when the window has built that.
    const bool seen_here =
        seen && i < seen->meshes.size() && seen->meshes[i].num_faces() > 0;
    const TriangleMesh& mesh = seen_here ? seen->meshes[i] : scene.meshes[i];
    const std::vector<Vector3>* normals = seen_here                  ? &seen->normals[i]
                                          : i < scene.normals.size() ? &scene.normals[i]
                                                                     : nullptr;
    // (its flat caps, where it meets its neighbours' shares, an actor of their
    // own: drawn only while the gingiva is opaque, SyncCaps)
    const std::vector<char>* cap =
        seen_here && i < seen->caps.size() && seen->caps[i].size() == mesh.num_faces()
            ? &seen->caps[i]
            : nullptr;
    std::vector<TriangleMesh::Face> body_faces, cap_faces;
    if (cap)
      for (std::size_t f = 0; f < mesh.num_faces(); ++f)
        ((*cap)[f] ? cap_faces : body_faces).push_back(mesh.faces()[f]);
    const bool split = !cap_faces.empty() && !body_faces.empty();
    auto actor = split
                     ? MeshActor(TriangleMesh(mesh.vertices(), body_faces), look, normals)
                     : MeshActor(mesh, look, normals);
    if (split) {
      auto caps = MeshActor(TriangleMesh(mesh.vertices(), cap_faces), look, normals);
      caps->SetUserMatrix(ToVtk(o.X_WO));
      renderer_->AddActor(caps);
      caps_.push_back({i, caps});
    }
    // Findings drawn where the scene puts them: caries on its surface, inflamed
    // gingiva at its sites.
    const bool carious = std::any_of(o.caries_mm.begin(), o.caries_mm.end(),
                                     [](double r) { return r > 0; });
    const bool inflamed =
        std::any_of(o.inflamed.begin(), o.inflamed.end(), [](bool b) { return b; });
    if (o.kind == ObjectSpec::Kind::kTooth && carious) {
      // The lesions whose surface is intact, and the cavitated ones (darker, a floor).
      std::array<double, 5> intact = o.caries_mm, cavitated{};
      for (std::size_t k = 0; k < 5; ++k)
        if (o.cavity_mm[k] > 0) std::swap(intact[k], cavitated[k]);
      const ToothModel tooth = GenerateTooth(o.fdi);
      const std::vector<double> cavities = CariesCoverage(tooth, cavitated);
      PaintVertices(actor, CariesCoverage(tooth, intact), look, Paint::kCaries,
                    &cavities);
    } else if (o.kind == ObjectSpec::Kind::kGingiva && inflamed) {
      std::vector<Vector3> in_tooth_frame;
      for (const Vector3& v : mesh.vertices())
        in_tooth_frame.push_back(ArchMirror(o.mirrored, v));
      PaintVertices(actor, InflammationCoverage(in_tooth_frame, o.inflamed), look,
                    Paint::kInflamed);
    } else if (o.kind == ObjectSpec::Kind::kAnatomy) {
      // A lip: its skin beyond the vermilion border (and a lesion where the
      // scene puts one, on any soft tissue).
      const std::vector<double> skin =
          o.anatomy == "lip_upper" || o.anatomy == "lip_lower"
              ? LipSkinCoverage(scene.meshes[i])
              : std::vector<double>{};
      if (!o.lesion_kind.empty()) {
        const Vector3 at = LesionCentre(o.anatomy, o.lesion_region, scene.meshes[i]);
        const Paint paint = o.lesion_kind == "ulcer"         ? Paint::kUlcer
                            : o.lesion_kind == "leukoplakia" ? Paint::kWhite
                                                             : Paint::kRed;
        PaintVertices(actor, LesionCoverage(scene.meshes[i], at, o.lesion_mm), look,
                      paint, nullptr, &skin);
      } else if (!skin.empty()) {
        PaintVertices(actor, std::vector<double>(skin.size(), 0.0), look, Paint::kRed,
                      nullptr, &skin);
      }
    }
    actor->SetUserMatrix(ToVtk(o.X_WO));
    renderer_->AddActor(actor);
    objects_.push_back(actor);
    if (o.tissue == Tissue::kGingiva) gingiva_.push_back(actor);
  }
  SetLipsAndCheeksHidden(lips_hidden_);  // as the window's box says, for this scene too
  AddToolActors(MakeProbe(scene.spec.probe));
  contact_points_ = vtkSmartPointer<vtkPoints>::New();
  contact_radii_ = vtkSmartPointer<vtkDoubleArray>::New();
  contact_radii_->SetName("radius");
  contact_poly_ = vtkSmartPointer<vtkPolyData>::New();
  contact_poly_->SetPoints(contact_points_);
  contact_poly_->GetPointData()->SetScalars(contact_radii_);
  contact_actor_ = SphereGlyphs(contact_poly_, 12, 8);
  // Contacts in a pale blue: in a probing lesson red is the blood's alone.
  contact_actor_->GetProperty()->SetColor(0.35, 0.75, 1.0);
  contact_actor_->GetProperty()->SetOpacity(0.35);
  contact_actor_->SetVisibility(false);
  renderer_->AddActor(contact_actor_);
  // Blood at the margin: beads along it (ShowBlood), before the loupe is
  // filled so that the loupe shows it too.
  blood_points_ = vtkSmartPointer<vtkPoints>::New();
  blood_radii_ = vtkSmartPointer<vtkDoubleArray>::New();
  blood_radii_->SetName("radius");
  blood_poly_ = vtkSmartPointer<vtkPolyData>::New();
  blood_poly_->SetPoints(blood_points_);
  blood_poly_->GetPointData()->SetScalars(blood_radii_);
  blood_actor_ = SphereGlyphs(blood_poly_, 10, 8);
  blood_actor_->GetProperty()->SetColor(0.62, 0.02, 0.04);
  blood_actor_->GetProperty()->SetSpecular(0.6);
  blood_actor_->GetProperty()->SetSpecularPower(40);
  blood_actor_->SetVisibility(false);
  renderer_->AddActor(blood_actor_);
  blood_shown_ = 0;
  spheres_shown_ = -1;
  FillLoupe();
  ShowLoupe(std::nullopt, Vector3::UnitX(), Vector3::UnitZ(), 1);
  View(Side::kBuccal);
}

void SceneView::ShowBlood(const std::vector<std::pair<Vector3, double>>& beads) {
  if (!blood_actor_) return;
  blood_points_->Reset();
  blood_radii_->Reset();
  for (const auto& [p, r] : beads) {
    blood_points_->InsertNextPoint(p.x(), p.y(), p.z());
    blood_radii_->InsertNextValue(r);
  }
  blood_points_->Modified();
  blood_radii_->Modified();
  blood_poly_->Modified();
  blood_actor_->SetVisibility(!beads.empty());
  blood_shown_ = static_cast<int>(beads.size());
}

void SceneView::AttachLoupe(vtkRenderer* loupe, vtkRenderer* overlay) {
  loupe_ = loupe;
  overlay_ = overlay;
  loupe_->SetBackground(0.10, 0.10, 0.12);
  loupe_->SetDraw(false);
  overlay_->SetDraw(false);
  overlay_->SetActiveCamera(loupe_->GetActiveCamera());
  FillLoupe();
}

void SceneView::FillLoupe() {
  if (!loupe_ || !scene_) return;
  loupe_->RemoveAllViewProps();
  overlay_->RemoveAllViewProps();
  overlay_marks_.clear();
  // What the main view draws, from the loupe's camera.
  vtkActorCollection* actors = renderer_->GetActors();
  actors->InitTraversal();
  while (vtkActor* a = actors->GetNextActor()) loupe_->AddActor(a);
  // Over it: the probe as a faint outline and its markings solid, so that the
  // part inside the sulcus shows through the gingiva.
  for (std::size_t i = 0; i < tool_graphic_.size(); ++i) {
    auto a = vtkSmartPointer<vtkActor>::New();
    a->SetMapper(tool_graphic_[i]->GetMapper());
    if (i == 0) {
      a->GetProperty()->SetColor(0.95, 0.95, 0.95);
      a->GetProperty()->SetOpacity(0.25);
    } else {
      a->GetProperty()->SetColor(0.05, 0.05, 0.08);
      a->GetProperty()->SetOpacity(0.85);
    }
    a->SetUserMatrix(ToVtk(X_WG_));
    overlay_->AddActor(a);
    overlay_marks_.push_back(a);
  }
  loupe_caption_ = vtkSmartPointer<vtkTextActor>::New();
  loupe_caption_->GetTextProperty()->SetFontSize(13);
  loupe_caption_->GetTextProperty()->SetColor(0.95, 0.95, 0.95);
  loupe_caption_->SetPosition(6, 6);
  overlay_->AddActor2D(loupe_caption_);
}

void SceneView::ShowLoupe(const std::optional<Vector3>& focus, const Vector3& from_dir,
                          const Vector3& up, double width_mm) {
  loupe_shown_ = focus.has_value() && loupe_ != nullptr;
  if (!loupe_) return;
  loupe_->SetDraw(loupe_shown_);
  overlay_->SetDraw(loupe_shown_);
  if (!loupe_shown_) return;
  vtkCamera* c = loupe_->GetActiveCamera();
  constexpr double kAngleDeg = 20;
  const double distance =
      0.5 * width_mm / std::tan(0.5 * kAngleDeg * std::numbers::pi / 180);
  const Vector3 eye = *focus + distance * from_dir.normalized();
  c->SetViewAngle(kAngleDeg);
  c->SetFocalPoint(focus->x(), focus->y(), focus->z());
  c->SetPosition(eye.x(), eye.y(), eye.z());
  c->SetViewUp(up.x(), up.y(), up.z());
  c->SetClippingRange(0.2 * distance, 3 * distance);
  if (loupe_caption_) {
    char text[96];
    std::snprintf(text, sizeof text, "Loupe, %.0f mm across", width_mm);
    loupe_caption_->SetInput(text);
  }
}

void SceneView::ShowGhost(const std::optional<RigidTransform>& X_WG) {
  ghost_ = X_WG;
  if (!tool_ghost_) return;
  tool_ghost_->SetVisibility(X_WG.has_value());
  if (X_WG) tool_ghost_->SetUserMatrix(ToVtk(*X_WG));
}

void SceneView::Update(const HapticSnapshot& s) {
  X_WG_ = s.X_WG;
  if (tool_haptic_) tool_haptic_->SetUserMatrix(ToVtk(s.X_WH));
  const auto m = ToVtk(s.X_WG);
  for (auto& a : tool_graphic_) a->SetUserMatrix(m);
  for (auto& a : overlay_marks_) a->SetUserMatrix(m);
  // Contact spheres: the object leaves the tool touches, in red.
  if (!scene_ || !contact_actor_) return;
  if (!show_contacts_ || s.num_shown_pairs == 0) {
    contact_actor_->SetVisibility(false);
    return;
  }
  // The glyph pipeline is built once (Load); each frame only refills its points.
  contact_points_->Reset();
  contact_radii_->Reset();
  for (int i = 0; i < s.num_shown_pairs; ++i) {
    const Vector3& p = s.shown_centers_W[static_cast<std::size_t>(i)];
    contact_points_->InsertNextPoint(p.x(), p.y(), p.z());
    contact_radii_->InsertNextValue(s.shown_radii[static_cast<std::size_t>(i)]);
  }
  contact_points_->Modified();
  contact_radii_->Modified();
  contact_poly_->Modified();
  contact_actor_->SetVisibility(true);
}

void SceneView::ShowSpheres(int level) {
  for (auto& a : spheres_) renderer_->RemoveActor(a);
  spheres_.clear();
  spheres_shown_ = level;
  if (!scene_ || level < 0) return;
  for (std::size_t i = 0; i < scene_->trees.size(); ++i) {
    const SphereTree& t = scene_->trees[i];
    auto points = vtkSmartPointer<vtkPoints>::New();
    auto radii = vtkSmartPointer<vtkDoubleArray>::New();
    radii->SetName("radius");
    for (std::int32_t n : t.CutAtLevel(std::min(level, t.levels - 1))) {
      points->InsertNextPoint(t.x[n], t.y[n], t.z[n]);
      radii->InsertNextValue(t.r[n]);
    }
    auto poly = vtkSmartPointer<vtkPolyData>::New();
    poly->SetPoints(points);
    poly->GetPointData()->SetScalars(radii);
    auto actor = SphereGlyphs(poly, 14, 10);
    actor->SetUserMatrix(ToVtk(scene_->spec.objects[i].X_WO));
    const double hue = (i % 6) / 6.0;
    actor->GetProperty()->SetColor(0.55 + 0.4 * hue, 0.85 - 0.3 * hue,
                                   0.35 + 0.5 * (1 - hue));
    actor->GetProperty()->SetOpacity(0.45);
    renderer_->AddActor(actor);
    spheres_.push_back(actor);
  }
}

void SceneView::SetLipsAndCheeksHidden(bool hidden) {
  lips_hidden_ = hidden;
  if (!scene_) return;
  for (std::size_t i = 0; i < objects_.size() && i < scene_->spec.objects.size(); ++i) {
    const ObjectSpec& o = scene_->spec.objects[i];
    if (o.kind == ObjectSpec::Kind::kAnatomy &&
        (o.tissue == Tissue::kLip || o.tissue == Tissue::kCheek))
      objects_[i]->SetVisibility(!hidden);
  }
}

void SceneView::SetGingivaTranslucent(bool on) {
  gingiva_translucent_ = on;
  for (auto& a : gingiva_) a->GetProperty()->SetOpacity(on ? 0.45 : 1.0);
  SyncCaps();
}

void SceneView::SyncCaps() {
  for (const auto& [i, caps] : caps_) {
    const vtkSmartPointer<vtkActor>& body = objects_[i];
    caps->SetVisibility(body->GetVisibility() &&
                        body->GetProperty()->GetOpacity() > 0.99);
  }
}

void SceneView::Frame(const Vector3& focus, const Vector3& from_dir, double distance,
                      const Vector3& up) {
  vtkCamera* cam = renderer_->GetActiveCamera();
  const Vector3 eye = focus + distance * from_dir.normalized();
  cam->SetFocalPoint(focus.x(), focus.y(), focus.z());
  cam->SetPosition(eye.x(), eye.y(), eye.z());
  cam->SetViewUp(up.x(), up.y(), up.z());
  cam->SetViewAngle(30);
  // Soft tissues between the camera and what it looks at (a cheek in front of a
  // molar, the lips in front of the incisors) turn see-through, as a retracted
  // cheek would be; they come back when the view no longer passes through them.
  see_through_ = 0;
  if (scene_) {
    for (std::size_t i = 0; i < objects_.size() && i < scene_->spec.objects.size(); ++i) {
      const ObjectSpec& o = scene_->spec.objects[i];
      if (o.kind != ObjectSpec::Kind::kAnatomy || o.tissue == Tissue::kBone ||
          o.tissue == Tissue::kGingiva)
        continue;
      double b[6];
      objects_[i]->GetBounds(b);
      // Slab test of the segment eye -> focus against the actor's world box.
      double t0 = 0, t1 = 1;
      for (int a = 0; a < 3 && t0 <= t1; ++a) {
        const double d = focus[a] - eye[a];
        if (std::abs(d) < 1e-12) {
          if (eye[a] < b[2 * a] || eye[a] > b[2 * a + 1]) t1 = -1;
          continue;
        }
        double ta = (b[2 * a] - eye[a]) / d, tb = (b[2 * a + 1] - eye[a]) / d;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
      }
      const bool in_the_way = t0 <= t1;
      objects_[i]->GetProperty()->SetOpacity(in_the_way ? 0.18
                                                        : LookOf(o.tissue).opacity);
      see_through_ += in_the_way;
    }
    // The occlusal view of a full mouth looks at the lower arch: the upper one
    // (teeth, their gingiva, jaw, palate and upper lip) is faded out of the way;
    // the upper arch's occlusal view fades the lower arch, the tongue, the floor
    // and the lower lip.
    for (std::size_t i = 0; i < objects_.size() && i < scene_->spec.objects.size(); ++i) {
      const ObjectSpec& o = scene_->spec.objects[i];
      const bool tooth_or_gingiva =
          o.kind == ObjectSpec::Kind::kTooth || o.kind == ObjectSpec::Kind::kGingiva;
      const bool anatomy = o.kind == ObjectSpec::Kind::kAnatomy;
      const bool upper =
          (tooth_or_gingiva && (o.fdi / 10 == 1 || o.fdi / 10 == 2)) ||
          (anatomy && (o.anatomy == "jaw_upper" || o.anatomy == "palate" ||
                       o.anatomy == "soft_palate" || o.anatomy == "lip_upper"));
      const bool lower =
          (tooth_or_gingiva && (o.fdi / 10 == 3 || o.fdi / 10 == 4)) ||
          (anatomy && (o.anatomy == "jaw_lower" || o.anatomy == "tongue" ||
                       o.anatomy == "floor_of_mouth" || o.anatomy == "lip_lower"));
      const bool lip_or_cheek =
          anatomy && (o.tissue == Tissue::kLip || o.tissue == Tissue::kCheek);
      objects_[i]->SetVisibility(!(lips_hidden_ && lip_or_cheek));
      if (!upper && !lower) continue;
      if ((upper && fade_upper_) || (lower && fade_lower_)) {
        objects_[i]->GetProperty()->SetOpacity(0.08);
      } else if (!anatomy && !(o.tissue == Tissue::kGingiva && gingiva_translucent_)) {
        objects_[i]->GetProperty()->SetOpacity(LookOf(o.tissue).opacity);
      } else if (anatomy) {
        objects_[i]->GetProperty()->SetOpacity(LookOf(o.tissue).opacity);
      }
    }
  }
  SyncCaps();
  renderer_->ResetCameraClippingRange();
}

void SceneView::View(Side side) {
  if (!scene_) return;
  // The teeth's centre and mean buccal and occlusal directions frame the view.
  Vector3 centre = Vector3::Zero(), buccal = Vector3::Zero(), occlusal = Vector3::Zero();
  int teeth = 0;
  Vector3 lo = Vector3::Constant(1e9), hi = Vector3::Constant(-1e9);
  for (std::size_t i = 0; i < scene_->spec.objects.size(); ++i) {
    const ObjectSpec& o = scene_->spec.objects[i];
    if (o.kind != ObjectSpec::Kind::kTooth) continue;
    const Vector3 c = o.X_WO * Vector3(0, 0, 3);
    centre += c;
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
    buccal += o.X_WO.rotation().col(1);
    // "Up" out of the lower arch: a lower tooth's occlusal direction, an upper
    // tooth's reversed (both arches together would otherwise cancel out).
    const int quadrant = o.fdi / 10;
    occlusal += (quadrant == 1 || quadrant == 2 ? -1.0 : 1.0) * o.X_WO.rotation().col(2);
    ++teeth;
  }
  if (teeth == 0) {
    renderer_->ResetCamera();
    return;
  }
  centre /= teeth;
  if (buccal.norm() < 1e-6) buccal = Vector3::UnitY();
  if (occlusal.norm() < 1e-6) occlusal = Vector3::UnitZ();
  buccal.normalize();
  occlusal.normalize();
  const double extent = std::max(25.0, (hi - lo).norm() * 1.6);
  bool lower = false, upper = false;
  for (const ObjectSpec& o : scene_->spec.objects)
    if (o.kind == ObjectSpec::Kind::kTooth) (o.fdi / 10 <= 2 ? upper : lower) = true;
  fade_upper_ = side == Side::kOcclusal && lower && upper;
  fade_lower_ = side == Side::kUpperOcclusal && lower && upper;
  switch (side) {
    case Side::kBuccal:
      Frame(centre, buccal + 0.35 * occlusal, 1.6 * extent, occlusal);
      break;
    case Side::kLingual:
      Frame(centre, -buccal + 0.35 * occlusal, 1.6 * extent, occlusal);
      break;
    case Side::kOcclusal:
      Frame(centre, occlusal, 1.8 * extent, buccal);
      break;
    case Side::kUpperOcclusal:
      Frame(centre, -occlusal, 1.8 * extent, buccal);
      break;
    case Side::kFront: {
      // From in front of the patient, level with the mouth's opening: the
      // incisors in the middle of the picture, the patient's left on the right.
      const Vector3 front = Vector3::UnitY();
      const Vector3 at(centre.x(), std::max(hi.y(), lo.y()), centre.z());
      Frame(at, front, 1.5 * extent, Vector3::UnitZ());
      break;
    }
  }
}

SceneView::CameraPose SceneView::Camera() const {
  vtkCamera* c = renderer_->GetActiveCamera();
  double e[3], f[3], u[3];
  c->GetPosition(e);
  c->GetFocalPoint(f);
  c->GetViewUp(u);
  return {Vector3(e[0], e[1], e[2]), Vector3(f[0], f[1], f[2]), Vector3(u[0], u[1], u[2]),
          c->GetViewAngle()};
}

bool SceneView::LookAtTooth(int fdi, bool lingual) {
  if (!scene_) return false;
  for (const ObjectSpec& o : scene_->spec.objects) {
    if (o.kind != ObjectSpec::Kind::kTooth || o.fdi != fdi) continue;
    const Vector3 occlusal = o.X_WO.rotation().col(2);
    fade_upper_ = fade_lower_ = false;
    // The head upright, as the clinician faces the patient: an upper tooth's
    // crown points down on the screen, a lower one's up.
    const Vector3 up = occlusal.z() >= 0 ? occlusal : Vector3(-occlusal);
    const Vector3 buccal = o.X_WO.rotation().col(1);
    if (lingual)
      Frame(o.X_WO * Vector3(0, 0, 1), -buccal + 0.5 * occlusal, 26, up);
    else
      Frame(o.X_WO * Vector3(0, 0, 2), buccal + 0.4 * occlusal, 38, up);
    return true;
  }
  return false;
}

}  // namespace sulcus::ui
