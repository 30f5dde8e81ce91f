#include "vaw/mass_properties.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>

namespace vaw {

namespace {

// Polynomial subexpressions of the divergence-theorem integrals over one triangle
// (D. Eberly, "Polyhedral Mass Properties (Revisited)", a simplification of Mirtich 1996).
struct Sub {
  double f1, f2, f3, g0, g1, g2;
};
Sub subexpressions(double w0, double w1, double w2) {
  const double t0 = w0 + w1;
  const double f1 = t0 + w2;
  const double t1 = w0 * w0;
  const double t2 = t1 + w1 * t0;
  const double f2 = t2 + w2 * f1;
  const double f3 = w0 * t1 + w1 * t2 + w2 * f2;
  return {f1, f2, f3, f2 + w0 * (f1 + w0), f2 + w1 * (f1 + w1), f2 + w2 * (f1 + w2)};
}

}  // namespace

VolumeIntegrals integrateVolume(const TriMesh& mesh) {
  VolumeIntegrals out;
  if (mesh.vertices.empty()) return out;
  // Integrate about a point inside the bounds: the integrals are exact, but cubic terms of far-away
  // coordinates would cancel catastrophically.
  const Eigen::Vector3d ref = mesh.bounds().center();
  double in[10] = {};
  double area = 0.0;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d p0 = mesh.vertices[static_cast<std::size_t>(t[0])] - ref;
    const Eigen::Vector3d p1 = mesh.vertices[static_cast<std::size_t>(t[1])] - ref;
    const Eigen::Vector3d p2 = mesh.vertices[static_cast<std::size_t>(t[2])] - ref;
    const Eigen::Vector3d d = (p1 - p0).cross(p2 - p0);
    area += 0.5 * d.norm();
    const Sub x = subexpressions(p0.x(), p1.x(), p2.x());
    const Sub y = subexpressions(p0.y(), p1.y(), p2.y());
    const Sub z = subexpressions(p0.z(), p1.z(), p2.z());
    in[0] += d.x() * x.f1;
    in[1] += d.x() * x.f2;
    in[2] += d.y() * y.f2;
    in[3] += d.z() * z.f2;
    in[4] += d.x() * x.f3;
    in[5] += d.y() * y.f3;
    in[6] += d.z() * z.f3;
    in[7] += d.x() * (p0.y() * x.g0 + p1.y() * x.g1 + p2.y() * x.g2);
    in[8] += d.y() * (p0.z() * y.g0 + p1.z() * y.g1 + p2.z() * y.g2);
    in[9] += d.z() * (p0.x() * z.g0 + p1.x() * z.g1 + p2.x() * z.g2);
  }
  static constexpr double mult[10] = {1.0 / 6, 1.0 / 24, 1.0 / 24, 1.0 / 24, 1.0 / 60,
                                      1.0 / 60, 1.0 / 60, 1.0 / 120, 1.0 / 120, 1.0 / 120};
  for (int i = 0; i < 10; ++i) in[i] *= mult[i];

  const double v = in[0];
  out.volume = v;
  out.surfaceArea = area;
  if (v == 0.0) return out;
  const Eigen::Vector3d c(in[1] / v, in[2] / v, in[3] / v);
  Eigen::Matrix3d I;
  I(0, 0) = in[5] + in[6] - v * (c.y() * c.y() + c.z() * c.z());
  I(1, 1) = in[4] + in[6] - v * (c.z() * c.z() + c.x() * c.x());
  I(2, 2) = in[4] + in[5] - v * (c.x() * c.x() + c.y() * c.y());
  I(0, 1) = I(1, 0) = -(in[7] - v * c.x() * c.y());
  I(1, 2) = I(2, 1) = -(in[8] - v * c.y() * c.z());
  I(0, 2) = I(2, 0) = -(in[9] - v * c.z() * c.x());
  out.centroid = c + ref;
  out.inertiaUnitDensity = I;
  return out;
}

MassProperties massPropertiesFromMesh(const TriMesh& mesh, double density) {
  const VolumeIntegrals vi = integrateVolume(mesh);
  MassProperties mp;
  mp.volume = vi.volume;
  mp.density = density;
  mp.mass = density * vi.volume;
  mp.centerOfMass = vi.centroid;
  mp.inertiaCm = density * vi.inertiaUnitDensity;
  mp.surfaceArea = vi.surfaceArea;
  return mp;
}

Principal principalMoments(const Eigen::Matrix3d& inertia) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(inertia);
  Principal p;
  p.moments = es.eigenvalues();
  p.axes = es.eigenvectors();
  if (p.axes.determinant() < 0.0) p.axes.col(2) *= -1.0;
  return p;
}

std::string inertiaProblem(const Eigen::Matrix3d& I, double relTol) {
  if (!I.allFinite()) return "non-finite entries";
  const double scale = I.cwiseAbs().maxCoeff();
  if (scale == 0.0) return "all entries zero";
  const double asym = (I - I.transpose()).cwiseAbs().maxCoeff();
  if (asym > relTol * scale) {
    std::ostringstream s;
    s << "not symmetric (largest |I - I^T| = " << asym << ")";
    return s.str();
  }
  const Eigen::Vector3d m = principalMoments(0.5 * (I + I.transpose())).moments;
  if (m[0] <= relTol * scale) {
    std::ostringstream s;
    s << "not positive definite (principal moments " << m.transpose() << ")";
    return s.str();
  }
  if (m[0] + m[1] < m[2] * (1.0 - relTol)) {
    std::ostringstream s;
    s << "principal moments " << m.transpose() << " violate the triangle inequality I1 + I2 >= I3";
    return s.str();
  }
  return {};
}

double MassComparison::worst() const { return std::max({massRel, volumeRel, comRel, inertiaRel}); }

MassComparison compare(const MassProperties& a, const MassProperties& b, double characteristicLength) {
  auto rel = [](double x, double y) {
    const double s = std::max(std::abs(x), std::abs(y));
    return s == 0.0 ? 0.0 : std::abs(x - y) / s;
  };
  MassComparison c;
  c.massRel = rel(a.mass, b.mass);
  c.volumeRel = (a.volume > 0.0 && b.volume > 0.0) ? rel(a.volume, b.volume) : 0.0;
  c.comDistance = (a.centerOfMass - b.centerOfMass).norm();
  c.comRel = characteristicLength > 0.0 ? c.comDistance / characteristicLength : 0.0;
  const double iScale = std::max(a.inertiaCm.cwiseAbs().maxCoeff(), b.inertiaCm.cwiseAbs().maxCoeff());
  c.inertiaRel = iScale > 0.0 ? (a.inertiaCm - b.inertiaCm).cwiseAbs().maxCoeff() / iScale : 0.0;
  return c;
}

}  // namespace vaw
