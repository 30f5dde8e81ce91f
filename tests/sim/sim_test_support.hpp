#pragma once
// Helpers for the simulation-world scenario tests: bundled scenes (through the build tree's assimp
// plugin), poses, and running a world over a scripted input function.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "bundled.hpp"
#include "files.hpp"
#include "vaw/assembly.hpp"
#include "vaw/importer.hpp"
#include "vaw/sim/world.hpp"

namespace vaw::simtest {

using vaw::test::importers;
using vaw::test::loadBundled;
using vaw::test::resources;

inline Eigen::Isometry3d at(double x, double y, double z) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() = Eigen::Vector3d(x, y, z);
  return p;
}
inline Eigen::Isometry3d rotAbout(const Eigen::Vector3d& axis, double rad, const Eigen::Vector3d& pivot) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = Eigen::AngleAxisd(rad, axis.normalized()).toRotationMatrix();
  p.translation() = pivot - p.linear() * pivot;
  return p;
}

// The sequence of (part, from, to, event) names, for readable assertions.
std::vector<std::string> transitionNames(const sim::World& w, PartId part);
std::string join(const std::vector<std::string>& v);
// A number for RecordProperty, with all its significant digits.
std::string num(double v);

// A hand input that holds `grab` at `pose`.
inline sim::HandInput hand(const Eigen::Isometry3d& pose, bool grab) { return sim::HandInput{pose, grab, std::nullopt}; }

}  // namespace vaw::simtest
