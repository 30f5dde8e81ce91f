#include "vaw/categories.hpp"

#include <cstdio>
#include <string>

namespace vaw {

std::string_view name(Category c) {
  switch (c) {
    case Category::OneHand: return "one-hand";
    case Category::TwoHand: return "two-hand";
    case Category::Tool: return "tool-lifted";
  }
  return "?";
}

CategorySettings CategorySettings::defaults() { return {}; }

CategorySettings CategorySettings::stricter() {
  CategorySettings s;
  s.preset = "stricter";
  s.oneHandMaxMass = 3.0;   // HSE guideline filter, women, arm's length
  s.twoHandMaxMass = 16.0;  // HSE guideline filter, women, close to the body at waist height
  return s;
}

bool CategorySettings::byName(std::string_view presetName, CategorySettings& out) {
  if (presetName == "default") { out = defaults(); return true; }
  if (presetName == "stricter") { out = stricter(); return true; }
  return false;
}

namespace {
std::string fmt(const char* f, double a, double b) {
  char buf[160];
  std::snprintf(buf, sizeof buf, f, a, b);
  return buf;
}
}  // namespace

CategoryResult categorize(double mass, double extent, const CategorySettings& s) {
  if (mass > s.twoHandMaxMass)
    return {Category::Tool, fmt("%.3g kg exceeds the two-hand limit of %.3g kg", mass, s.twoHandMaxMass)};
  if (mass > s.oneHandMaxMass)
    return {Category::TwoHand, fmt("%.3g kg exceeds the one-hand limit of %.3g kg", mass, s.oneHandMaxMass)};
  if (extent > s.oneHandMaxExtent)
    return {Category::TwoHand, fmt("%.3g m long, more than one hand controls (%.3g m)", extent, s.oneHandMaxExtent)};
  return {Category::OneHand, fmt("%.3g kg within the one-hand limit of %.3g kg", mass, s.oneHandMaxMass) +
                                 fmt(", %.3g m within %.3g m", extent, s.oneHandMaxExtent)};
}

double principalExtent(const TriMesh& mesh, const Eigen::Matrix3d& axes) {
  if (mesh.vertices.empty()) return 0.0;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = Eigen::Vector3d::Constant(-1e300);
  for (const auto& v : mesh.vertices) {
    const Eigen::Vector3d p = axes.transpose() * v;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return (hi - lo).maxCoeff();
}

}  // namespace vaw
