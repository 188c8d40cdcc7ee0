#pragma once
// Sequences of QP instances in the benchmark file format, and a
// generator of contact-like sets (slot, wedge, plane, cluster, random).
//
// Format (little-endian): int32 n, m, S, T; float64 G_diag[n]; then S sequences
// of T frames, each float64 q_h[n], A[m*n] row-major, b[m]. Each problem is
// min 1/2 (q - q_h)^T G (q - q_h) s.t. A q >= b; row i keeps its identity along
// a sequence (the warm start matches rows by index).

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace sulcus {

struct QpInstances {
  int n = 6, m = 0, sequences = 0, frames = 0;
  std::vector<double> g;     // n
  std::vector<double> data;  // per frame: q_h[n], A[m*n], b[m]

  std::size_t FrameStride() const { return static_cast<std::size_t>(n) * (1 + m) + m; }
  const double* Frame(int s, int t) const {
    return data.data() + (static_cast<std::size_t>(s) * frames + t) * FrameStride();
  }
  const double* QH(int s, int t) const { return Frame(s, t); }
  const double* A(int s, int t) const { return Frame(s, t) + n; }
  const double* B(int s, int t) const {
    return Frame(s, t) + n + static_cast<std::size_t>(n) * m;
  }
};

class QpFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Reads and checks a file (sizes positive, file length exact, values finite).
QpInstances ReadQpInstances(const std::filesystem::path& path);
void WriteQpInstances(const QpInstances& qp, const std::filesystem::path& path);

/// Contact-like sequences for n = 6 (translation, rotation increment):
/// rows [normal, lever x normal] >= -gap, with the device pressing in and moving.
/// kind: slot (opposing walls), wedge (two inclined faces), plane (a flat face on a
/// plane: parallel normals), cluster (near-duplicate normals and levers),
/// random. Throws std::invalid_argument for an unknown kind.
QpInstances GenerateQpInstances(const std::string& kind, int m, int sequences, int frames,
                                std::uint64_t seed);

}  // namespace sulcus
