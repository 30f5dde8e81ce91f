#pragma once
// Everything inside vaw is SI (m, kg, s, rad). Files may declare other units; these convert on load.
#include <numbers>
#include <optional>
#include <string>
#include <string_view>

namespace vaw {

enum class LengthUnit { Metre, Millimetre, Inch };
enum class MassUnit { Kilogram, Gram, Pound };

std::optional<LengthUnit> parseLengthUnit(std::string_view s);  // "m", "mm", "inch"/"in"
std::optional<MassUnit> parseMassUnit(std::string_view s);      // "kg", "g", "lb"
double toMetres(LengthUnit u);                                  // metres per unit
double toKilograms(MassUnit u);                                 // kilograms per unit
std::string_view name(LengthUnit u);
std::string_view name(MassUnit u);

// Density written as a number (kg/m^3) or as "<value> <unit>" with unit kg/m^3, g/cm^3 or lb/in^3.
// Returns kg/m^3, or nothing if the text is not one of those forms.
std::optional<double> parseDensity(std::string_view text);

inline constexpr double kStandardGravity = 9.80665;  // m/s^2
inline constexpr double kDeg = std::numbers::pi / 180.0;  // rad in a degree, for angles that files and people give in degrees

}  // namespace vaw
