#include "vaw/units.hpp"

#include <charconv>
#include <cmath>

namespace vaw {

std::optional<LengthUnit> parseLengthUnit(std::string_view s) {
  if (s == "m") return LengthUnit::Metre;
  if (s == "mm") return LengthUnit::Millimetre;
  if (s == "inch" || s == "in") return LengthUnit::Inch;
  return std::nullopt;
}

std::optional<MassUnit> parseMassUnit(std::string_view s) {
  if (s == "kg") return MassUnit::Kilogram;
  if (s == "g") return MassUnit::Gram;
  if (s == "lb") return MassUnit::Pound;
  return std::nullopt;
}

double toMetres(LengthUnit u) {
  switch (u) {
    case LengthUnit::Metre: return 1.0;
    case LengthUnit::Millimetre: return 1e-3;
    case LengthUnit::Inch: return 0.0254;
  }
  return 1.0;
}

double toKilograms(MassUnit u) {
  switch (u) {
    case MassUnit::Kilogram: return 1.0;
    case MassUnit::Gram: return 1e-3;
    case MassUnit::Pound: return 0.45359237;
  }
  return 1.0;
}

std::string_view name(LengthUnit u) {
  switch (u) {
    case LengthUnit::Metre: return "m";
    case LengthUnit::Millimetre: return "mm";
    case LengthUnit::Inch: return "inch";
  }
  return "?";
}

std::string_view name(MassUnit u) {
  switch (u) {
    case MassUnit::Kilogram: return "kg";
    case MassUnit::Gram: return "g";
    case MassUnit::Pound: return "lb";
  }
  return "?";
}

std::optional<double> parseDensity(std::string_view text) {
  while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
  double value = 0.0;
  auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || !std::isfinite(value)) return std::nullopt;
  std::string_view unit(end, static_cast<std::size_t>(text.data() + text.size() - end));
  while (!unit.empty() && unit.front() == ' ') unit.remove_prefix(1);
  while (!unit.empty() && unit.back() == ' ') unit.remove_suffix(1);
  if (unit.empty() || unit == "kg/m^3") return value;
  if (unit == "g/cm^3") return value * 1000.0;
  if (unit == "lb/in^3") return value * 0.45359237 / (0.0254 * 0.0254 * 0.0254);
  return std::nullopt;
}

}  // namespace vaw
