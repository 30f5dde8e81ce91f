#include "vaw/property_file.hpp"

#include <cmath>
#include <sstream>

#include "../base/json_node.hpp"
#include "vaw/limits.hpp"
#include "vaw/units.hpp"

namespace vaw {

using detail::Node;

PropertyFile readPropertyFile(const std::filesystem::path& path) {
  const std::string file = path.string();
  const detail::Json j = detail::readJsonFile(path);
  const Node root(j, "", file);
  root.requireFormat("vaw-properties");
  root.allowOnly({"format", "version", "part", "units", "mass", "center_of_mass", "inertia_cm", "density", "volume",
                  "surface_area", "surface_finish", "tolerance"});
  const Node version = root.get("version");
  if (version.integer() != 1) version.fail("version 1");

  const Node units = root.get("units");
  units.allowOnly({"length", "mass"});
  const Node lu = units.get("length");
  const auto length = parseLengthUnit(lu.string());
  if (!length) lu.fail("a length unit: \"m\", \"mm\" or \"inch\"");
  const Node mu = units.get("mass");
  const auto massUnit = parseMassUnit(mu.string());
  if (!massUnit) mu.fail("a mass unit: \"kg\", \"g\" or \"lb\"");
  const double L = toMetres(*length), M = toKilograms(*massUnit);

  PropertyFile pf;
  const Node massNode = root.get("mass");
  pf.mass.mass = massNode.positive() * M;
  if (!(pf.mass.mass >= limits::kMinMass && pf.mass.mass <= limits::kMaxMass)) {
    std::ostringstream range;
    range << "a mass from " << limits::kMinMass << " to " << limits::kMaxMass << " kg";
    massNode.failWith(range.str(), std::to_string(pf.mass.mass) + " kg");
  }
  pf.mass.centerOfMass = root.get("center_of_mass").position(L);

  const Node inertia = root.get("inertia_cm");
  if (!inertia.json().is_array() || inertia.size() != 3) inertia.fail("a 3x3 array of numbers (rows)");
  Eigen::Matrix3d I;
  for (std::size_t r = 0; r < 3; ++r) I.row(static_cast<Eigen::Index>(r)) = inertia.at(r).vec3().transpose();
  I *= M * L * L;
  if (const std::string problem = inertiaProblem(I, 1e-6); !problem.empty())
    inertia.failWith("a symmetric, positive-definite inertia tensor whose principal moments obey I1 + I2 >= I3", problem);
  pf.mass.inertiaCm = I;

  if (auto d = root.opt("density")) {
    std::optional<double> rho;
    if (d->json().is_number()) rho = d->positive();
    else if (d->json().is_string()) rho = parseDensity(d->string());
    if (!rho || !(*rho >= limits::kMinDensity && *rho <= limits::kMaxDensity)) {
      std::ostringstream range;
      range << "a density from " << limits::kMinDensity << " to " << limits::kMaxDensity
            << " kg/m^3: a number in kg/m^3 or \"<value> kg/m^3|g/cm^3|lb/in^3\"";
      d->fail(range.str());
    }
    pf.density = rho;
    pf.mass.density = *rho;
  }
  if (auto v = root.opt("volume")) {
    pf.volume = v->positive() * L * L * L;
    pf.mass.volume = *pf.volume;
  }
  if (pf.density && pf.volume) {
    const double implied = *pf.density * *pf.volume;
    if (std::abs(implied - pf.mass.mass) > 0.01 * pf.mass.mass)
      root.get("mass").failWith("mass = density * volume within 1 % (" + std::to_string(implied) + " kg)",
                                std::to_string(pf.mass.mass) + " kg");
  }
  if (auto a = root.opt("surface_area")) {
    pf.surfaceArea = a->positive() * L * L;
    pf.mass.surfaceArea = pf.surfaceArea;
  }
  if (auto s = root.opt("surface_finish")) pf.surfaceFinish = s->string();
  if (auto t = root.opt("tolerance")) pf.tolerance = t->nonNegative() * L;
  return pf;
}

}  // namespace vaw
