#include "vaw/evaluation/dfa.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <unordered_map>

#include "vaw/collision/surface_patches.hpp"

namespace vaw::eval {

namespace {

// Manual handling, one hand, no tools, parts that neither nest nor tangle nor need care (the chart's first
// four rows): seconds by alpha + beta (row) and size and thickness (column).
constexpr double kHandling[4][5] = {
    {1.13, 1.43, 1.88, 1.69, 2.18},  // alpha + beta < 360
    {1.50, 1.80, 2.25, 2.06, 2.55},  // 360 <= alpha + beta < 540
    {1.80, 2.10, 2.55, 2.36, 2.85},  // 540 <= alpha + beta < 720
    {1.95, 2.25, 2.70, 2.51, 3.00},  // alpha + beta = 720
};
// Manual insertion, part added but not secured, no holding down, no access or vision restriction (row 0):
// easy or not easy to align and position, with or without resistance to insertion.
constexpr double kInsertion[4] = {1.5, 2.5, 2.5, 3.5};

// The vertices as a hash grid, to ask whether a moved vertex lands on one of them.
class VertexSet {
 public:
  VertexSet(const std::vector<Eigen::Vector3d>& v, double tol) : v_(v), tol_(tol), cell_(4.0 * tol) {
    for (std::size_t i = 0; i < v.size(); ++i) grid_[key(cellOf(v[i]))].push_back(i);
  }
  [[nodiscard]] bool mapsOnto(const Eigen::Matrix3d& R, const Eigen::Vector3d& centre) const {
    for (const auto& p : v_) {
      const Eigen::Vector3d q = R * (p - centre) + centre;
      if (!contains(q)) return false;
    }
    return true;
  }

 private:
  [[nodiscard]] Eigen::Vector3i cellOf(const Eigen::Vector3d& p) const { return (p / cell_).array().floor().cast<int>(); }
  static std::uint64_t key(const Eigen::Vector3i& c) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(c.x()) & 0x1fffff) << 42) |
           (static_cast<std::uint64_t>(static_cast<std::uint32_t>(c.y()) & 0x1fffff) << 21) |
           (static_cast<std::uint64_t>(static_cast<std::uint32_t>(c.z()) & 0x1fffff));
  }
  [[nodiscard]] bool contains(const Eigen::Vector3d& q) const {
    const Eigen::Vector3i c = cellOf(q);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = grid_.find(key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == grid_.end()) continue;
          for (const std::size_t i : it->second)
            if ((v_[i] - q).norm() <= tol_) return true;
        }
    return false;
  }
  const std::vector<Eigen::Vector3d>& v_;
  double tol_, cell_;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> grid_;
};

// Round about the axis: every face a cylinder on the axis or a plane across it.
bool roundAbout(const TriMesh& mesh, const Eigen::Vector3d& axis, const Eigen::Vector3d& centre, double tol) {
  const collision::SurfacePatches patches = collision::classifySurfaces(mesh);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (const int c = patches.cylinderOf[t]; c >= 0) {
      const auto& cyl = patches.cylinders[static_cast<std::size_t>(c)];
      Eigen::Vector3d off = cyl.point - centre;
      off -= axis * axis.dot(off);
      if (std::abs(std::abs(cyl.direction.dot(axis)) - 1.0) > 1e-6 || off.norm() > tol) return false;
    } else if (const int p = patches.planeOf[t]; p >= 0) {
      if (std::abs(std::abs(patches.planes[static_cast<std::size_t>(p)].normal.dot(axis)) - 1.0) > 1e-6) return false;
    } else {
      return false;
    }
  }
  return true;
}

std::string mm(double m) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f mm", 1e3 * m);
  return buf;
}

}  // namespace

DfaEstimate estimateDfa(const Assembly& assembly, PartId part, const Eigen::Vector3d& outAxis, const Constraint* how) {
  const Part& p = assembly.parts[part];
  DfaEstimate e;
  e.mass_kg = p.mass.mass;
  const Eigen::Isometry3d home = p.finalPose.value_or(p.pose);
  const Eigen::Vector3d axis = (home.linear().transpose() * outAxis).normalized();
  const Eigen::Vector3d centre = p.mass.centerOfMass;
  const TriMesh& mesh = *p.mesh;

  // Size and thickness: the part's box along its principal axes.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& v : mesh.vertices) {
    const Eigen::Vector3d q = p.principal.axes.transpose() * (v - centre);
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  const Eigen::Vector3d sides = hi - lo;
  e.size_m = sides.maxCoeff();
  e.thickness_m = sides.minCoeff();

  // Symmetry, on the tessellated mesh: a symmetry its tessellation breaks is not found, which errs toward
  // the longer time.
  const double tol = std::max(1e-7, 1e-5 * sides.norm());
  const VertexSet set(mesh.vertices, tol);
  if (roundAbout(mesh, axis, centre, tol)) {
    e.alpha_deg = 0.0;
  } else {
    for (const double deg : {180.0, 120.0, 90.0, 72.0, 60.0}) {
      if (set.mapsOnto(Eigen::AngleAxisd(deg * std::numbers::pi / 180.0, axis).toRotationMatrix(), centre)) e.alpha_deg = deg;
    }
  }
  // Across: a half turn about a principal axis square to the insertion axis (or, for a round part, any).
  for (int k = 0; k < 3 && e.beta_deg > 180.0; ++k) {
    Eigen::Vector3d across = p.principal.axes.col(k);
    across -= axis * axis.dot(across);
    if (across.norm() < 0.5) continue;
    if (set.mapsOnto(Eigen::AngleAxisd(std::numbers::pi, across.normalized()).toRotationMatrix(), centre)) e.beta_deg = 180.0;
  }
  const double sum = e.alpha_deg + e.beta_deg;
  const int row = sum < 360.0 ? 0 : sum < 540.0 ? 1 : sum < 720.0 ? 2 : 3;
  const bool thick = e.thickness_m > 0.002;
  const int col = thick ? (e.size_m > 0.015 ? 0 : e.size_m >= 0.006 ? 1 : 2) : (e.size_m > 0.006 ? 3 : 4);
  e.handlingCode = std::to_string(row) + std::to_string(col);
  e.handling_s = kHandling[row][col];
  e.lowerBound = p.category.category != Category::OneHand;

  // Insertion: a mate is easy to align and meets no resistance; an insert is hard to align without 0.1 mm
  // of clearance and resists when it has none.
  bool easy = true, resists = false;
  std::string insertion = "no constraint: placed, assumed easy";
  if (how && how->type == Constraint::Type::Insert) {
    if (how->found) {
      easy = how->found->clearance >= 1e-4;
      resists = how->found->clearance < 5e-6;
      insertion = "insert with " + mm(how->found->clearance) + " clearance";
    } else {
      insertion = "insert typed by hand (clearance not measured): assumed easy";
    }
  } else if (how) {
    insertion = std::string(name(how->type)) + " onto a face";
  }
  const int icol = (easy ? 0 : 1) + (resists ? 2 : 0);
  e.insertionCode = "0" + std::to_string(icol);
  e.insertion_s = kInsertion[icol];

  char buf[400];
  std::snprintf(buf, sizeof buf,
                "alpha %.0f, beta %.0f (row %d); %s long, %s thick (column %d): handling %s, %.2f s%s; %s%s%s: insertion %s, %.2f s",
                e.alpha_deg, e.beta_deg, row, mm(e.size_m).c_str(), mm(e.thickness_m).c_str(), col, e.handlingCode.c_str(),
                e.handling_s, e.lowerBound ? " (one-hand row: a lower bound for this part)" : "", insertion.c_str(),
                easy ? "" : ", not easy to align", resists ? ", resists" : "", e.insertionCode.c_str(), e.insertion_s);
  e.why = buf;
  return e;
}

}  // namespace vaw::eval
