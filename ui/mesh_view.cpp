#include "ui/mesh_view.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
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
#include <vtkImageData.h>

#include <cstdlib>
#include <stdexcept>

namespace sulcus::ui {

vtkSmartPointer<vtkPolyData> ToPolyData(const TriangleMesh& mesh) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(mesh.num_vertices()));
  for (std::size_t i = 0; i < mesh.num_vertices(); ++i) {
    const Vector3& v = mesh.vertices()[i];
    points->SetPoint(static_cast<vtkIdType>(i), v.x(), v.y(), v.z());
  }
  // Area-weighted vertex normals: smooth shading without VTK's normal filter,
  // which would split vertices at sharp edges.
  const std::vector<Vector3> normals = mesh.VertexNormalSums();
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  for (const auto& f : mesh.faces()) {
    const vtkIdType ids[3] = {f[0], f[1], f[2]};
    cells->InsertNextCell(3, ids);
  }
  auto normal_array = vtkSmartPointer<vtkDoubleArray>::New();
  normal_array->SetNumberOfComponents(3);
  normal_array->SetNumberOfTuples(static_cast<vtkIdType>(normals.size()));
  for (std::size_t i = 0; i < normals.size(); ++i) {
    const Vector3 n = normals[i].norm() > 0 ? Vector3(normals[i].normalized()) : Vector3::UnitZ();
    normal_array->SetTuple3(static_cast<vtkIdType>(i), n.x(), n.y(), n.z());
  }
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetPolys(cells);
  poly->GetPointData()->SetNormals(normal_array);
  return poly;
}

double RenderToPng(const std::vector<ShadedMesh>& meshes, const std::filesystem::path& png,
                   int width, int height, const std::string& title) {
  const double background[3] = {0.16, 0.18, 0.22};
  auto renderer = vtkSmartPointer<vtkRenderer>::New();
  renderer->SetBackground(background[0], background[1], background[2]);
  renderer->SetBackground2(0.32, 0.36, 0.42);
  renderer->GradientBackgroundOn();
  for (const ShadedMesh& m : meshes) {
    if (m.mesh == nullptr) continue;
    auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
    mapper->SetInputData(ToPolyData(*m.mesh));
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
  auto* with = vtkUnsignedCharArray::SafeDownCast(drawn_image->GetPointData()->GetScalars());
  auto* without = vtkUnsignedCharArray::SafeDownCast(grab->GetOutput()->GetPointData()->GetScalars());
  if (with == nullptr || without == nullptr ||
      with->GetNumberOfValues() != without->GetNumberOfValues()) {
    return 0.0;
  }
  const vtkIdType values = with->GetNumberOfValues();
  const int comps = with->GetNumberOfComponents();
  vtkIdType drawn = 0;
  for (vtkIdType i = 0; i < values; i += comps) {
    bool differs = false;
    for (int c = 0; c < 3; ++c) differs |= std::abs(int{with->GetValue(i + c)} - int{without->GetValue(i + c)}) > 8;
    drawn += differs;
  }
  return static_cast<double>(drawn) / static_cast<double>(values / comps);
}

}  // namespace sulcus::ui
