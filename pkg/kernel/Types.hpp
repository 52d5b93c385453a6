// yade-flex kernel: plain numerics on Eigen types, no YADE include (GPL-2.0-or-later)
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace flex {
using Vec3 = Eigen::Matrix<double, 3, 1>;
using Mat3 = Eigen::Matrix<double, 3, 3>;
using Quat = Eigen::Quaternion<double>;
} // namespace flex
