#pragma once
// Small mesh files written by tests.

#include <array>
#include <filesystem>
#include <fstream>

namespace sulcus::test {

/// A closed ASCII STL tetrahedron with its right-angle corner at the origin and
/// legs `size_mm` long along x, y and z.
inline void WriteTetrahedronStl(const std::filesystem::path& file, double size_mm) {
  std::ofstream stl(file);
  stl << "solid tetrahedron\n";
  const double v[4][3] = {{0, 0, 0}, {size_mm, 0, 0}, {0, size_mm, 0}, {0, 0, size_mm}};
  for (const auto& f : {std::array{0, 2, 1}, std::array{0, 1, 3}, std::array{0, 3, 2},
                        std::array{1, 2, 3}}) {
    stl << "facet normal 0 0 0\nouter loop\n";
    for (int i : f)
      stl << "vertex " << v[i][0] << " " << v[i][1] << " " << v[i][2] << "\n";
    stl << "endloop\nendfacet\n";
  }
  stl << "endsolid tetrahedron\n";
}

}  // namespace sulcus::test
