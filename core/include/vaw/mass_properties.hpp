#pragma once
#include <Eigen/Core>
#include <optional>
#include <string>

#include "vaw/mesh.hpp"

namespace vaw {

// Mass properties of a rigid part in its own frame, SI units.
struct MassProperties {
  double mass = 0.0;                                       // kg
  double volume = 0.0;                                     // m^3
  double density = 0.0;                                    // kg/m^3 (0 if unknown)
  Eigen::Vector3d centerOfMass = Eigen::Vector3d::Zero();  // m, part frame
  Eigen::Matrix3d inertiaCm = Eigen::Matrix3d::Zero();     // kg m^2, about the CM, part-frame axes
  std::optional<double> surfaceArea;                       // m^2
};

// Volume integrals of a closed, outward-oriented triangle mesh by the divergence theorem
// (Mirtich 1996, in Eberly's formulation): exact for polyhedra up to round-off.
struct VolumeIntegrals {
  double volume = 0.0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertiaUnitDensity = Eigen::Matrix3d::Zero();  // about the centroid, density 1
  double surfaceArea = 0.0;
};
VolumeIntegrals integrateVolume(const TriMesh& mesh);

MassProperties massPropertiesFromMesh(const TriMesh& mesh, double density);

struct Principal {
  Eigen::Vector3d moments;  // ascending
  Eigen::Matrix3d axes;     // columns, right-handed
};
Principal principalMoments(const Eigen::Matrix3d& inertia);

// Physical validity of an inertia tensor about the CM: symmetric, positive definite, and the principal
// moments obey the triangle inequality. Returns an empty string when valid, else why not.
std::string inertiaProblem(const Eigen::Matrix3d& inertia, double relTol = 1e-9);

// Largest relative differences between two sets of properties (for "file vs. mesh" reports).
struct MassComparison {
  double massRel = 0.0;
  double volumeRel = 0.0;
  double comDistance = 0.0;  // m
  double comRel = 0.0;       // comDistance / characteristic length
  double inertiaRel = 0.0;   // max |dI| / max principal moment
  [[nodiscard]] double worst() const;
};
MassComparison compare(const MassProperties& a, const MassProperties& b, double characteristicLength);

}  // namespace vaw
