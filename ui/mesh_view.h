#pragma once
// Turning engine meshes into VTK data, and saving pictures of them.

#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include <filesystem>
#include <string>
#include <vector>

#include "core/geometry/mesh.h"

namespace sulcus::ui {

/// Copies a mesh into polydata with per-point normals for smooth shading.
/// With `crease_deg` > 0, edges sharper than that keep their crease (their
/// vertices are split); the point array kSourceVertexArray names the mesh
/// vertex each point came from. With `normals` (one per mesh vertex, as a
/// share of the gingiva has from its field), a vertex takes its given normal;
/// with a crease angle, only at the corners of faces within that angle of it
/// (the others take the normal from the faces). A zero normal counts as none.
vtkSmartPointer<vtkPolyData> ToPolyData(const TriangleMesh& mesh, double crease_deg = 0,
                                        const std::vector<Vector3>* normals = nullptr);
inline constexpr const char* kSourceVertexArray = "source_vertex";
// Edges sharper than this are drawn sharp (a share of the gingiva cut flat
// against its neighbour's, a jaw's cut end); gentler ones are shaded smooth.
inline constexpr double kCreaseDeg = 60;

/// One mesh in a picture, with an RGB colour in [0, 1] and an opacity.
struct ShadedMesh {
  const TriangleMesh* mesh = nullptr;
  double color[3] = {0.93, 0.91, 0.84};  // enamel
  double opacity = 1.0;
  // As ToPolyData takes them: the normals to draw with (a gingiva share's, as
  // the scene view draws it) and the crease angle (0: smooth everywhere).
  const std::vector<Vector3>* normals = nullptr;
  double crease_deg = 0;
};

/// Renders the meshes offscreen (needs an X display, e.g. Xvfb) from an oblique
/// view that frames them all, and writes a PNG. Returns the share of pixels that
/// differ from the background, so callers can check that something was drawn.
double RenderToPng(const std::vector<ShadedMesh>& meshes,
                   const std::filesystem::path& png, int width = 800, int height = 600,
                   const std::string& title = "");

}  // namespace sulcus::ui
