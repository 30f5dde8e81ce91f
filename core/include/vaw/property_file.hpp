#pragma once
// The per-part property file of the paper (section 3): mass properties exported from CAD together with
// units, density, volume, surface area, surface finish and tolerance. Format: docs/property-file.md.
#include <filesystem>
#include <optional>
#include <string>

#include "vaw/mass_properties.hpp"

namespace vaw {

struct PropertyFile {
  MassProperties mass;                 // SI; density/volume/surfaceArea filled when given
  std::optional<double> volume;        // m^3, as written (converted)
  std::optional<double> density;       // kg/m^3
  std::optional<double> surfaceArea;   // m^2
  std::string surfaceFinish;           // free text, e.g. "Ra 0.8 um ground"
  std::optional<double> tolerance;     // m
};

// Throws InputError naming the file and field for anything missing or invalid.
PropertyFile readPropertyFile(const std::filesystem::path& file);

}  // namespace vaw
