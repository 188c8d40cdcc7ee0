#include "ui/mesh_view.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkImageData.h>
#include <vtkLight.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <utility>

namespace sulcus::ui {

vtkSmartPointer<vtkPolyData> ToPolyData(const TriangleMesh& mesh, double crease_deg,
                                        const std::vector<Vector3>* normals) {
  // Area-weighted vertex normals for smooth shading. With a crease angle,
  // each corner of a face takes the normals of only those faces around its
  // vertex that lie within the angle of its own, and a vertex whose corners
  // disagree is split: a sharp edge (where a gingiva share is cut flat
  // against its neighbour's) stays sharp instead of bending the shading of
  // the surface beside it into a dark or bright line.
  const auto& verts = mesh.vertices();
  const auto& faces = mesh.faces();
  std::vector<Vector3> face_area_normal(faces.size());
  for (std::size_t f = 0; f < faces.size(); ++f)
    face_area_normal[f] = (verts[faces[f][1]] - verts[faces[f][0]])
                              .cross(verts[faces[f][2]] - verts[faces[f][0]]);
  std::vector<Vector3> out_points;
  std::vector<Vector3> out_normals;
  std::vector<vtkIdType> source;  // the mesh vertex each point was made from
  std::vector<std::array<vtkIdType, 3>> out_faces(faces.size());
  // A given normal counts where it is one (a zero one is none).
  const bool given = normals && normals->size() == verts.size();
  auto given_at = [&](int v) { return given && (*normals)[v].squaredNorm() > 0.5; };
  if (crease_deg <= 0) {
    out_points = verts;
    out_normals = mesh.VertexNormalSums();
    for (std::size_t i = 0; i < verts.size(); ++i)
      if (given_at(static_cast<int>(i))) out_normals[i] = (*normals)[i];
    source.resize(verts.size());
    for (std::size_t i = 0; i < verts.size(); ++i) source[i] = static_cast<vtkIdType>(i);
    for (std::size_t f = 0; f < faces.size(); ++f)
      out_faces[f] = {faces[f][0], faces[f][1], faces[f][2]};
  } else {
    const double cos_crease = std::cos(crease_deg * 3.14159265358979323846 / 180.0);
    std::vector<std::vector<int>> around(verts.size());
    for (std::size_t f = 0; f < faces.size(); ++f)
      for (int k = 0; k < 3; ++k) around[faces[f][k]].push_back(static_cast<int>(f));
    // Per vertex, the distinct normals its corners take (few: usually one).
    std::vector<std::vector<std::pair<Vector3, vtkIdType>>> made(verts.size());
    for (std::size_t f = 0; f < faces.size(); ++f) {
      const Vector3 nf = face_area_normal[f].normalized();
      for (int k = 0; k < 3; ++k) {
        const int v = faces[f][k];
        Vector3 n = Vector3::Zero();
        if (given_at(v) && (*normals)[v].dot(nf) >= cos_crease) {
          n = (*normals)[v];
        } else {
          for (const int g : around[v]) {
            const Vector3& ng = face_area_normal[g];
            if (ng.norm() > 0 && ng.normalized().dot(nf) >= cos_crease) n += ng;
          }
          if (n.norm() == 0) n = face_area_normal[f];
        }
        n.normalize();
        vtkIdType id = -1;
        for (const auto& [known, at] : made[v])
          if (known.dot(n) > 0.9999) id = at;
        if (id < 0) {
          id = static_cast<vtkIdType>(out_points.size());
          out_points.push_back(verts[v]);
          out_normals.push_back(n);
          source.push_back(v);
          made[v].emplace_back(n, id);
        }
        out_faces[f][k] = id;
      }
    }
  }
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(out_points.size()));
  for (std::size_t i = 0; i < out_points.size(); ++i)
    points->SetPoint(static_cast<vtkIdType>(i), out_points[i].x(), out_points[i].y(),
                     out_points[i].z());
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  for (const auto& f : out_faces) cells->InsertNextCell(3, f.data());
  auto normal_array = vtkSmartPointer<vtkDoubleArray>::New();
  normal_array->SetNumberOfComponents(3);
  normal_array->SetNumberOfTuples(static_cast<vtkIdType>(out_normals.size()));
  for (std::size_t i = 0; i < out_normals.size(); ++i) {
    const Vector3 n = out_normals[i].norm() > 0 ? Vector3(out_normals[i].normalized())
                                                : Vector3::UnitZ();
    normal_array->SetTuple3(static_cast<vtkIdType>(i), n.x(), n.y(), n.z());
  }
  auto vertex_array = vtkSmartPointer<vtkIdTypeArray>::New();
  vertex_array->SetName(kSourceVertexArray);
  vertex_array->SetNumberOfTuples(static_cast<vtkIdType>(source.size()));
  for (std::size_t i = 0; i < source.size(); ++i)
    vertex_array->SetValue(static_cast<vtkIdType>(i), source[i]);
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetPolys(cells);
  poly->GetPointData()->SetNormals(normal_array);
  poly->GetPointData()->AddArray(vertex_array);
  return poly;
}

double RenderToPng(const std::vector<ShadedMesh>& meshes,
                   const std::filesystem::path& png, int width, int height,
                   const std::string& title) {
  const double background[3] = {0.16, 0.18, 0.22};
  auto renderer = vtkSmartPointer<vtkRenderer>::New();
  renderer->SetBackground(background[0], background[1], background[2]);
  renderer->SetBackground2(0.32, 0.36, 0.42);
  renderer->GradientBackgroundOn();
  for (const ShadedMesh& m : meshes) {
    if (m.mesh == nullptr) continue;
    auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
    mapper->SetInputData(ToPolyData(*m.mesh, m.crease_deg, m.normals));
    auto actor = vtkSmartPointer<vtkActor>::New();
    actor->SetMapper(mapper);
    actor->GetProperty()->SetColor(m.color[0], m.color[1], m.color[2]);
    actor->GetProperty()->SetOpacity(m.opacity);
    actor->GetProperty()->SetSpecular(0.35);
    actor->GetProperty()->SetSpecularPower(30);
    actor->GetProperty()->SetDiffuse(0.8);
    actor->GetProperty()->SetAmbient(0.12);
    renderer->AddActor(actor);
  }
  if (!title.empty()) {
    auto text = vtkSmartPointer<vtkTextActor>::New();
    text->SetInput(title.c_str());
    text->GetTextProperty()->SetFontSize(18);
    text->GetTextProperty()->SetColor(0.95, 0.95, 0.95);
    text->SetPosition(12, 12);
    renderer->AddActor2D(text);
  }
  renderer->ResetCamera();
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->Elevation(25);
  camera->Azimuth(35);
  camera->OrthogonalizeViewUp();
  renderer->ResetCamera();
  camera->Zoom(1.2);

  auto window = vtkSmartPointer<vtkRenderWindow>::New();
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(8);
  window->SetSize(width, height);
  window->AddRenderer(renderer);
  window->Render();

  auto grab = vtkSmartPointer<vtkWindowToImageFilter>::New();
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->Update();
  auto writer = vtkSmartPointer<vtkPNGWriter>::New();
  writer->SetFileName(png.string().c_str());
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
  if (writer->GetErrorCode() != 0) {
    throw std::runtime_error(png.string() + ": could not write the PNG");
  }

  // Share of pixels that differ from the same view with nothing in it.
  auto drawn_image = vtkSmartPointer<vtkImageData>::New();
  drawn_image->DeepCopy(grab->GetOutput());
  renderer->RemoveAllViewProps();
  window->Render();
  grab->Modified();
  grab->Update();
  auto* with =
      vtkUnsignedCharArray::SafeDownCast(drawn_image->GetPointData()->GetScalars());
  auto* without =
      vtkUnsignedCharArray::SafeDownCast(grab->GetOutput()->GetPointData()->GetScalars());
  if (with == nullptr || without == nullptr ||
      with->GetNumberOfValues() != without->GetNumberOfValues()) {
    return 0.0;
  }
  const vtkIdType values = with->GetNumberOfValues();
  const int comps = with->GetNumberOfComponents();
  vtkIdType drawn = 0;
  for (vtkIdType i = 0; i < values; i += comps) {
    bool differs = false;
    for (int c = 0; c < 3; ++c)
      differs |= std::abs(int{with->GetValue(i + c)} - int{without->GetValue(i + c)}) > 8;
    drawn += differs;
  }
  return static_cast<double>(drawn) / static_cast<double>(values / comps);
}

}  // namespace sulcus::ui
