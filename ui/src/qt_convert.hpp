#pragma once
// Between the core's types (Eigen, view::Rgb) and Qt's, for the window's sources.
#include <Eigen/Core>
#include <QColor>
#include <QVector3D>
#include <algorithm>

#include "vaw/view/frame.hpp"

namespace vaw::ui {

inline QColor toQColor(const vaw::view::Rgb& c) {
  return QColor::fromRgbF(std::clamp(c.r, 0.0f, 1.0f), std::clamp(c.g, 0.0f, 1.0f), std::clamp(c.b, 0.0f, 1.0f));
}
inline QVector3D toQ(const Eigen::Vector3d& v) { return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())}; }
inline Eigen::Vector3d toEigen(const QVector3D& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace vaw::ui
