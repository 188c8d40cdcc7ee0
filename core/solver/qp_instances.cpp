#include "core/solver/qp_instances.h"

#include <cmath>
#include <fstream>
#include <random>

#include "core/geometry/types.h"

namespace sulcus {

QpInstances ReadQpInstances(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw QpFileError(name + ": cannot be opened");
  std::int32_t head[4];
  if (!in.read(reinterpret_cast<char*>(head), sizeof head)) {
    throw QpFileError(name + ": truncated: no header (expected int32 n, m, S, T)");
  }
  QpInstances qp;
  qp.n = head[0];
  qp.m = head[1];
  qp.sequences = head[2];
  qp.frames = head[3];
  if (qp.n <= 0 || qp.m < 0 || qp.sequences <= 0 || qp.frames <= 0 || qp.n > 64 ||
      qp.m > 1'000'000) {
    throw QpFileError(name + ": header n=" + std::to_string(qp.n) + " m=" +
                      std::to_string(qp.m) + " S=" + std::to_string(qp.sequences) +
                      " T=" + std::to_string(qp.frames) + " is out of range");
  }
  const std::uintmax_t expected =
      16 + 8 * (qp.n +
                static_cast<std::uintmax_t>(qp.sequences) * qp.frames * qp.FrameStride());
  const std::uintmax_t size = std::filesystem::file_size(path);
  if (size != expected) {
    throw QpFileError(name + ": " + std::to_string(size) + " bytes, expected " +
                      std::to_string(expected) +
                      " for that header (truncated or wrong format)");
  }
  qp.g.resize(qp.n);
  in.read(reinterpret_cast<char*>(qp.g.data()), 8 * qp.n);
  qp.data.resize(static_cast<std::size_t>(qp.sequences) * qp.frames * qp.FrameStride());
  in.read(reinterpret_cast<char*>(qp.data.data()),
          static_cast<std::streamsize>(8 * qp.data.size()));
  if (!in) throw QpFileError(name + ": read failed");
  for (double v : qp.g) {
    if (!(v > 0) || !std::isfinite(v))
      throw QpFileError(name + ": G_diag must be positive and finite");
  }
  for (std::size_t i = 0; i < qp.data.size(); ++i) {
    if (!std::isfinite(qp.data[i]))
      throw QpFileError(name + ": non-finite value at number " + std::to_string(i));
  }
  return qp;
}

void WriteQpInstances(const QpInstances& qp, const std::filesystem::path& path) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw QpFileError(path.string() + ": cannot be opened for writing");
  const std::int32_t head[4] = {qp.n, qp.m, qp.sequences, qp.frames};
  out.write(reinterpret_cast<const char*>(head), sizeof head);
  out.write(reinterpret_cast<const char*>(qp.g.data()),
            static_cast<std::streamsize>(8 * qp.g.size()));
  out.write(reinterpret_cast<const char*>(qp.data.data()),
            static_cast<std::streamsize>(8 * qp.data.size()));
  if (!out) throw QpFileError(path.string() + ": write failed");
}

QpInstances GenerateQpInstances(const std::string& kind, int m, int sequences, int frames,
                                std::uint64_t seed) {
  if (kind != "slot" && kind != "wedge" && kind != "plane" && kind != "cluster" &&
      kind != "random") {
    throw std::invalid_argument("unknown kind '" + kind +
                                "' (expected slot, wedge, plane, cluster or random)");
  }
  if (m < 1 || sequences < 1 || frames < 1)
    throw std::invalid_argument("m, sequences and frames must be >= 1");
  QpInstances qp;
  qp.n = 6;
  qp.m = m;
  qp.sequences = sequences;
  qp.frames = frames;
  qp.g = {1, 1, 1, 1000, 1000, 1000};  // the paper's k_t and k_r
  qp.data.resize(static_cast<std::size_t>(sequences) * frames * qp.FrameStride());
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0, 1);
  std::uniform_real_distribution<double> uni(0, 1);
  for (int s = 0; s < sequences; ++s) {
    // Contact points (levers from the tool origin) and normals of this sequence.
    std::vector<Vector3> lever(m), normal(m);
    std::vector<double> gap(m);
    for (int i = 0; i < m; ++i) {
      const double side = (i % 2) ? 1.0 : -1.0;
      if (kind == "slot") {
        normal[i] = Vector3(side, 0, 0);
        lever[i] = Vector3(-side * 0.25, 0.1 * gauss(rng), 10 * uni(rng));
      } else if (kind == "wedge") {
        const double a = 35 * M_PI / 180;
        normal[i] = Vector3(side * std::sin(a), 0, std::cos(a));
        lever[i] = Vector3(0.3 * gauss(rng), 3 * gauss(rng), -0.25);
      } else if (kind == "plane") {
        normal[i] = Vector3::UnitZ();
        lever[i] = Vector3(3 * gauss(rng), 3 * gauss(rng), 0);
      } else if (kind == "cluster") {
        normal[i] =
            (Vector3::UnitZ() + 0.02 * Vector3(gauss(rng), gauss(rng), 0)).normalized();
        lever[i] = 0.2 * Vector3(gauss(rng), gauss(rng), gauss(rng));
      } else {
        normal[i] = Vector3(gauss(rng), gauss(rng), gauss(rng)).normalized();
        lever[i] = 5 * Vector3(gauss(rng), gauss(rng), gauss(rng));
      }
      gap[i] = 0.02 * uni(rng);  // q = 0 is feasible: the graphic pose is out of contact
    }
    const double phase = 6.28 * uni(rng);
    for (int t = 0; t < frames; ++t) {
      double* frame =
          qp.data.data() + (static_cast<std::size_t>(s) * frames + t) * qp.FrameStride();
      const double tt = 0.002 * t + phase;
      // The device: pressing into the contacts (-normal mean), moving and turning.
      Vector3 press = Vector3::Zero();
      for (int i = 0; i < std::min(m, 16); ++i) press -= normal[i];
      press =
          press.norm() > 1e-9 ? Vector3(press.normalized()) : Vector3(-Vector3::UnitZ());
      const Vector3 dp = 0.5 * press + 0.3 * Vector3(std::sin(tt), std::cos(1.3 * tt),
                                                     0.5 * std::sin(0.7 * tt));
      const Vector3 dth =
          0.01 * Vector3(std::sin(0.9 * tt), std::cos(1.1 * tt), std::sin(1.7 * tt));
      for (int k = 0; k < 3; ++k) {
        frame[k] = dp[k];
        frame[3 + k] = dth[k];
      }
      // Rows drift a little from frame to frame, as re-linearised contacts do.
      const Matrix3 turn =
          Eigen::AngleAxisd(1e-3 * std::sin(tt), Vector3(0.3, 0.5, 0.8).normalized())
              .toRotationMatrix();
      for (int i = 0; i < m; ++i) {
        const Vector3 n = turn * normal[i];
        const Vector3 r = turn * lever[i];
        double* row = frame + 6 + 6 * i;
        const Vector3 moment = r.cross(n);
        for (int k = 0; k < 3; ++k) {
          row[k] = n[k];
          row[3 + k] = moment[k];
        }
        frame[6 + 6 * m + i] = -gap[i] * (1 + 0.1 * std::sin(tt + i));
      }
    }
  }
  return qp;
}

}  // namespace sulcus
