#pragma once
// Eigen aliases used across core/. Units: mm, s, N, N*mm, rad (docs/architecture.md).

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace sulcus {

using Vector3 = Eigen::Vector3d;
using Matrix3 = Eigen::Matrix3d;
using Matrix4 = Eigen::Matrix4d;
using Vector6 = Eigen::Matrix<double, 6, 1>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Quaternion = Eigen::Quaterniond;

}  // namespace sulcus
