#include "format.hpp"

#include <algorithm>
#include <cmath>

namespace vaw::ui::format {

QString number(double value, int digits) {
  if (value == 0.0) return QStringLiteral("0");
  const double magnitude = std::abs(value);
  if (magnitude >= 1e-3 && magnitude < 1e6) {
    // Fixed notation with `digits` significant digits.
    const int decimals = std::max(0, digits - 1 - static_cast<int>(std::floor(std::log10(magnitude))));
    return QString::number(value, 'f', decimals);
  }
  return QString::number(value, 'g', digits);
}

QString mass(double kg) {
  if (std::abs(kg) < 1.0 && kg != 0.0) return QStringLiteral("%1 g").arg(number(kg * 1e3));
  return QStringLiteral("%1 kg").arg(number(kg));
}

QString lengthMm(double metres) {
  return QStringLiteral("%1 mm").arg(number(std::abs(metres) < 1e-12 ? 0.0 : metres * 1e3));
}

QString vectorMm(const Eigen::Vector3d& metres) {
  // Round-off residue (1e-17 m) is shown as 0, not as an exponent.
  const auto mm = [](double m) { return number(std::abs(m) < 1e-12 ? 0.0 : m * 1e3); };
  return QStringLiteral("(%1, %2, %3) mm").arg(mm(metres.x()), mm(metres.y()), mm(metres.z()));
}

QString volume(double cubicMetres) { return QStringLiteral("%1 cm³").arg(number(cubicMetres * 1e6)); }

QString percent(double fraction) { return QStringLiteral("%1 %").arg(number(fraction * 100.0, 3)); }

QString collision(const vaw::collision::ObjectInfo& info) {
  using K = vaw::collision::ProxyKind;
  QString text = str(std::string(vaw::collision::name(info.proxy)));
  if (info.proxy == K::Mesh || info.proxy == K::SimplifiedMesh) text += QStringLiteral(", %1 tri").arg(info.triangles);
  if (info.proxy != K::Mesh && info.proxy != K::None && info.deviation > 0.0)
    text += QStringLiteral(", %1 mm off").arg(info.deviation * 1000.0, 0, 'g', 2);
  return text;
}

}  // namespace vaw::ui::format
