#pragma once
// Who can lift a part: one hand, two hands, or a tool (paper section 4; docs/categories.md).
// Thresholds are settings; the defaults and their sources are in docs/categories.md.
#include <string>
#include <string_view>

#include "vaw/mass_properties.hpp"
#include "vaw/mesh.hpp"

namespace vaw {

enum class Category { OneHand, TwoHand, Tool };
std::string_view name(Category c);

struct CategorySettings {
  std::string preset = "default";
  double oneHandMaxMass = 5.0;    // kg; a judgement (no standard gives a one-handed limit)
  double twoHandMaxMass = 23.0;   // kg; revised NIOSH lifting equation load constant
  double oneHandMaxExtent = 0.35; // m; a part longer than this needs two hands however light

  static CategorySettings defaults();
  static CategorySettings stricter();  // wider working population, see docs/categories.md
  static bool byName(std::string_view name, CategorySettings& out);
};

struct CategoryResult {
  Category category = Category::OneHand;
  std::string reason;
};

// `extent` is the part's largest dimension along its principal axes (see principalExtent).
CategoryResult categorize(double mass, double extent, const CategorySettings& settings);
double principalExtent(const TriMesh& mesh, const Eigen::Matrix3d& principalAxes);

}  // namespace vaw
