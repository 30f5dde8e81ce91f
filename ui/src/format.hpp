#pragma once
// Display formatting shared by the panels. vaw is SI inside; panels show lengths in mm, masses in kg.
#include <Eigen/Core>
#include <QString>
#include <string>
#include <string_view>

#include "vaw/collision/collision_world.hpp"

namespace vaw::ui::format {

inline QString str(std::string_view s) { return QString::fromUtf8(s.data(), static_cast<qsizetype>(s.size())); }
// A number with `digits` significant digits, no exponent for everyday magnitudes.
QString number(double value, int digits = 4);
QString mass(double kg);             // "1.234 kg" / "12.3 g"
QString lengthMm(double metres);     // "12.5 mm"
QString vectorMm(const Eigen::Vector3d& metres);  // "(1, 2, 3) mm"
QString volume(double cubicMetres);  // "123.4 cm³"
QString percent(double fraction);    // "1.23 %"

// How an object collides, e.g. "mesh, 512 tri", "box", "simplified, 1.2k tri, 0.3 mm off".
QString collision(const vaw::collision::ObjectInfo& info);

}  // namespace vaw::ui::format
