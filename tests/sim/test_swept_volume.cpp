// The swept volume of a path (docs/swept-volume.md) against closed forms. What the voxels guarantee:
// every point of the true swept volume lies in an occupied voxel (conservative), and an occupied voxel's
// box, grown by at most a quarter voxel where the part turns, meets the part somewhere on its way, so the
// surface lies within sqrt(3) + 1/4 voxels of the true one (1.25 voxels along each axis on a straight path;
// docs/swept-volume.md has every source of the bound). Each test checks (a) points of the exact solid are inside, (b) every
// surface vertex lies outside the exact solid's interior and within the bound beyond it, (c) the volume
// lies between the exact one and that of the exact solid grown by the bound.
#include <gtest/gtest.h>
#include <regex>

#include <cmath>
#include <fstream>
#include <map>
#include <numbers>

#include "sim_test_support.hpp"
#include "vaw/atomic_file.hpp"
#include "vaw/error.hpp"
#include "vaw/mesh_export.hpp"
#include "vaw/primitives.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/sim/scene.hpp"
#include "vaw/sim/swept_volume.hpp"

using namespace vaw;
using namespace vaw::sim;
using simtest::at;

namespace {

constexpr double kPi = std::numbers::pi;

Eigen::Isometry3d turned(double angle, const Eigen::Vector3d& axis, const Eigen::Vector3d& position = Eigen::Vector3d::Zero()) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  p.translation() = position;
  return p;
}

// The signed volume the mesh encloses (divergence theorem): equals the voxels' when the surface is closed
// and faces outward.
double enclosed(const TriMesh& m) {
  double v = 0.0;
  for (const auto& t : m.triangles) v += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]])) / 6.0;
  return v;
}

// Distance from p to the polyline's segments.
double toPolyline(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& line) {
  double best = 1e9;
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    const Eigen::Vector3d d = line[i + 1] - line[i];
    const double s = std::clamp((p - line[i]).dot(d) / d.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (p - line[i] - s * d).norm());
  }
  return best;
}

// A closed 2-manifold facing outwards: every edge in two triangles, once each way; the triangles round
// every corner one fan; and the volume it encloses is the voxels'.
void expectClosedAndWhole(const SweptVolume& sv) {
  const TriMesh& m = sv.mesh;
  std::map<std::pair<int, int>, int> edges;
  std::vector<std::map<int, int>> fan(m.vertices.size());  // around a corner: from one neighbour to the next
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      ++edges[{t[k], t[(k + 1) % 3]}];
      ASSERT_TRUE(fan[t[k]].emplace(t[(k + 1) % 3], t[(k + 2) % 3]).second) << "two triangles turn the same way at a corner";
    }
  for (const auto& [e, n] : edges) {
    ASSERT_EQ(n, 1) << "edge " << e.first << "-" << e.second;
    ASSERT_EQ(edges.count({e.second, e.first}), 1U) << "edge " << e.first << "-" << e.second << " has one side only";
  }
  for (std::size_t v = 0; v < fan.size(); ++v) {
    if (fan[v].empty()) continue;
    std::size_t steps = 0;
    int at = fan[v].begin()->first;
    do {
      at = fan[v].at(at);
      ++steps;
    } while (at != fan[v].begin()->first && steps <= fan[v].size());
    ASSERT_EQ(steps, fan[v].size()) << "two sheets meet at corner " << v << ": " << m.vertices[v].transpose();
  }
  EXPECT_NEAR(enclosed(m), sv.volume, 1e-9 * sv.volume + 1e-15);
}

}  // namespace

TEST(SweptVolume, ABoxTranslatedAlongALineFillsItsPrism) {
  // A 20 x 10 x 10 mm box moved 50 mm along x, off the grid's alignment: the prism 70 x 10 x 10 mm.
  const double h = 0.001, grow = 1.25 * h;
  const TriMesh box = primitives::box({0.020, 0.010, 0.010});
  const Eigen::Vector3d start(0.00013, 0.00041, -0.00027);
  const SweptVolume sv = sweep(box, {{at(start.x(), start.y(), start.z()), at(start.x() + 0.050, start.y(), start.z())}}, h);
  const Eigen::AlignedBox3d prism(start + Eigen::Vector3d(-0.010, -0.005, -0.005), start + Eigen::Vector3d(0.060, 0.005, 0.005));
  const double exact = prism.volume();
  EXPECT_GE(sv.volume, exact);
  EXPECT_LE(sv.volume, Eigen::AlignedBox3d(prism.min().array() - grow, prism.max().array() + grow).volume());
  for (double x = 0.0; x <= 1.0; x += 0.05)
    for (double y = 0.0; y <= 1.0; y += 0.1)
      for (double z = 0.0; z <= 1.0; z += 0.1) {
        const Eigen::Vector3d p = prism.min() + Eigen::Vector3d(x, y, z).cwiseProduct(prism.sizes());
        ASSERT_TRUE(sv.contains(p)) << p.transpose();
      }
  const Eigen::AlignedBox3d inner(prism.min().array() + 1e-9, prism.max().array() - 1e-9);
  const Eigen::AlignedBox3d outer(prism.min().array() - grow - 1e-9, prism.max().array() + grow + 1e-9);
  for (const Eigen::Vector3d& v : sv.mesh.vertices) {
    ASSERT_FALSE(inner.contains(v)) << v.transpose();
    ASSERT_TRUE(outer.contains(v)) << v.transpose();
  }
  expectClosedAndWhole(sv);
  EXPECT_EQ(sv.moves, 1U);  // a straight move, swept whole
}

TEST(SweptVolume, ATessellationsSagGrowsTheVolumeAllRound) {
  // The box of the test above as a CAD part whose true surface may lie 0.3 mm outside its facets: every
  // point within 0.3 mm of the prism is inside, and the surface stays within the bound plus 0.3 mm.
  const double h = 0.001, sag = 0.0003, grow = 1.25 * h + sag;
  const TriMesh box = primitives::box({0.020, 0.010, 0.010});
  const Eigen::Vector3d start(0.00013, 0.00041, -0.00027);
  const SweptVolume plain = sweep(box, {{at(start.x(), start.y(), start.z()), at(start.x() + 0.050, start.y(), start.z())}}, h);
  const SweptVolume sv = sweep(box, {{at(start.x(), start.y(), start.z()), at(start.x() + 0.050, start.y(), start.z())}}, h, kMaxSweepVoxels, sag);
  const Eigen::AlignedBox3d prism(start + Eigen::Vector3d(-0.010, -0.005, -0.005), start + Eigen::Vector3d(0.060, 0.005, 0.005));
  const Eigen::AlignedBox3d sagged(prism.min().array() - sag, prism.max().array() + sag);
  for (double x = 0.0; x <= 1.0; x += 0.05)
    for (double y = 0.0; y <= 1.0; y += 0.1)
      for (double z = 0.0; z <= 1.0; z += 0.1) {
        const Eigen::Vector3d p = sagged.min() + Eigen::Vector3d(x, y, z).cwiseProduct(sagged.sizes());
        ASSERT_TRUE(sv.contains(p)) << p.transpose();
      }
  EXPECT_GT(sv.volume, plain.volume);
  const Eigen::AlignedBox3d outer(prism.min().array() - grow - 1e-9, prism.max().array() + grow + 1e-9);
  for (const Eigen::Vector3d& v : sv.mesh.vertices) ASSERT_TRUE(outer.contains(v)) << v.transpose();
  expectClosedAndWhole(sv);
  EXPECT_THROW(sweep(box, {{at(0, 0, 0)}}, h, kMaxSweepVoxels, -1e-3), std::invalid_argument);
}

TEST(SweptVolume, ACylinderTurnedAboutItsOwnAxisSweepsItself) {
  // 64 sides of radius 10 mm, 20 mm high, turned a whole turn about its axis (tilted, off the origin): the
  // round cylinder through its corners.
  const double h = 0.0005, r = 0.010, height = 0.020;
  const TriMesh cyl = primitives::cylinder(r, height, 64);
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, -0.2, 1.0).normalized(), at0(0.0011, -0.0023, 0.0007);
  std::vector<Eigen::Isometry3d> run;
  for (int k = 0; k <= 8; ++k) run.push_back(turned(k * kPi / 4.0, axis, at0));
  // Its own axis is its frame's z: turn the frame so z lies along `axis`.
  const Eigen::Quaterniond toAxis = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis);
  for (int k = 0; k <= 8; ++k) run[k].linear() = run[k].linear() * toAxis.toRotationMatrix();
  const SweptVolume sv = sweep(cyl, {run}, h);

  const double bound = (std::sqrt(3.0) + 0.25) * h;  // a voxel's diagonal and the stray
  const double exact = kPi * r * r * height;
  EXPECT_GE(sv.volume, exact);
  EXPECT_LE(sv.volume, kPi * (r + bound) * (r + bound) * (height + 2 * bound));
  const auto radial = [&](const Eigen::Vector3d& p, double& along) {
    const Eigen::Vector3d q = p - at0;
    along = q.dot(axis);
    return (q - along * axis).norm();
  };
  for (double f = 0.0; f <= 1.0; f += 0.1)
    for (double a = 0.0; a < 2 * kPi; a += kPi / 12)
      for (double z = -0.5; z <= 0.5; z += 0.1) {
        const Eigen::Vector3d radialDir = toAxis * Eigen::Vector3d(std::cos(a), std::sin(a), 0.0);
        const Eigen::Vector3d p = at0 + z * height * axis + f * r * radialDir;
        ASSERT_TRUE(sv.contains(p)) << p.transpose();
      }
  for (const Eigen::Vector3d& v : sv.mesh.vertices) {
    double along = 0.0;
    const double rr = radial(v, along);
    ASSERT_FALSE(rr < r * std::cos(kPi / 64) - 1e-9 && std::abs(along) < 0.5 * height - 1e-9) << v.transpose();
    ASSERT_LE(rr, r + bound + 1e-9);
    ASSERT_LE(std::abs(along), 0.5 * height + bound + 1e-9);
  }
  expectClosedAndWhole(sv);
}

TEST(SweptVolume, ASphereAlongAPolylineIsAChainOfCapsules) {
  // A sphere of radius 5 mm along two 40 mm legs at a right angle. The chain of capsules' volume:
  // pi r^2 (L1 + L2) for the cylinders, less their overlap at the corner (a quarter of the Steinmetz
  // solid, 4 r^3 / 3), plus the ball's quarter outside both at the corner and a half ball at each end.
  const double h = 0.001, r = 0.005, leg = 0.040;
  const int segments = 32, rings = 16;
  const TriMesh ball = primitives::sphere(r, segments, rings);
  const std::vector<Eigen::Vector3d> line = {{0.0003, 0.0002, 0.0001}, {0.0403, 0.0002, 0.0001}, {0.0403, 0.0402, 0.0001}};
  std::vector<Eigen::Isometry3d> run;
  for (const auto& p : line) run.push_back(at(p.x(), p.y(), p.z()));
  const SweptVolume sv = sweep(ball, {run}, h);

  const auto chain = [&](double radius) {
    return kPi * radius * radius * 2 * leg - 4.0 * std::pow(radius, 3) / 3.0 + kPi * std::pow(radius, 3) / 3.0 + 4.0 * kPi * std::pow(radius, 3) / 3.0;
  };
  // The mesh lies between the sphere through its corners and a sphere within its faces.
  const double inside = r * std::cos(kPi / segments) * std::cos(kPi / rings);
  const double bound = (std::sqrt(3.0) + 0.25) * h;
  EXPECT_GE(sv.volume, chain(inside));
  EXPECT_LE(sv.volume, chain(r + bound));
  for (double s = 0.0; s <= 1.0; s += 0.02)
    for (const Eigen::Vector3d& d : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(1, 0, 0)}) {
      const Eigen::Vector3d c = s < 0.5 ? line[0] + 2 * s * (line[1] - line[0]) : line[1] + (2 * s - 1) * (line[2] - line[1]);
      ASSERT_TRUE(sv.contains(c + 0.97 * inside * d)) << c.transpose();
    }
  for (const Eigen::Vector3d& v : sv.mesh.vertices) {
    const double d = toPolyline(v, line);
    ASSERT_GE(d, inside - 1e-9) << v.transpose();
    ASSERT_LE(d, r + bound + 1e-9) << v.transpose();
  }
  expectClosedAndWhole(sv);
}

TEST(SweptVolume, VoxelsMeetingAlongAnEdgeOrAtACornerGiveAManifold) {
  // Three 2 mm cubes each in the middle of a 10 mm voxel: the first two in voxels that share only an
  // edge, the third in one that shares only a corner with the second. The surface of those three voxels
  // alone would have an edge of four faces and a corner where two sheets touch; voxels are added until
  // neither is left (and the three stay in).
  TriMesh m = primitives::box({0.002, 0.002, 0.002});
  TriMesh three;
  three.append(m, at(0.005, 0.005, 0.005));
  three.append(m, at(0.015, 0.015, 0.005));
  three.append(m, at(0.025, 0.025, 0.015));
  const SweptVolume sv = sweep(three, {{Eigen::Isometry3d::Identity()}}, 0.010);
  for (const Eigen::Vector3d& c : {Eigen::Vector3d(0.005, 0.005, 0.005), Eigen::Vector3d(0.015, 0.015, 0.005), Eigen::Vector3d(0.025, 0.025, 0.015)})
    EXPECT_TRUE(sv.contains(c));
  EXPECT_GT(sv.voxels, 3U);
  EXPECT_LE(sv.voxels, 3U + 2 * 8U);
  expectClosedAndWhole(sv);
}

TEST(SweptVolume, TheStlExportReadsBackAsOneSolidOfTheSameVolume) {
  // The sphere's chain of capsules written in millimetres, read back through the workbench's own mesh
  // reader (which refuses anything that is not a closed manifold solid).
  const TriMesh ball = primitives::sphere(0.005, 32, 16);
  const SweptVolume sv = sweep(ball, {{at(0, 0, 0), at(0.040, 0, 0), at(0.040, 0.040, 0.010)}}, 0.001);
  const std::filesystem::path file = vaw::test::tempDir() / "swept.stl";
  writeFileAtomically(file, binaryStl(sv.mesh, 1000.0, "vaw swept volume, mm"));
  EXPECT_EQ(std::filesystem::file_size(file), 84 + 50 * sv.mesh.triangles.size());
  const Assembly back = loadAny(file, vaw::test::importers());
  ASSERT_EQ(back.parts.size(), 1U);
  EXPECT_EQ(back.units, LengthUnit::Millimetre);
  EXPECT_NEAR(enclosed(*back.parts[0].mesh), sv.volume, 1e-6 * sv.volume);
  EXPECT_NEAR((back.parts[0].pose * back.parts[0].mesh->bounds().min() - sv.mesh.bounds().min()).norm(), 0.0, 1e-6);
}

// The surface is each plane's voxel faces merged into rectangles: it covers exactly the faces between
// occupied and empty voxels (its area is theirs), in well under the two triangles a face would take, and
// is still closed without T-junctions (a corner inside another triangle's edge would leave that edge with
// one side only, which expectClosedAndWhole refuses).
TEST(SweptVolume, TheSurfaceMergesEachPlanesFacesWithoutTJunctions) {
  const double h = 0.001;
  const SweptVolume sv = sweep(primitives::sphere(0.005, 32, 16), {{at(0, 0, 0), at(0.040, 0, 0), at(0.040, 0.040, 0.010)}}, h);
  const std::size_t rowWords = (static_cast<std::size_t>(sv.dims.x()) + 63) / 64;
  const auto filled = [&](int x, int y, int z) {
    if (x < 0 || y < 0 || z < 0 || x >= sv.dims.x() || y >= sv.dims.y() || z >= sv.dims.z()) return false;
    return ((sv.occupied[(static_cast<std::size_t>(z) * sv.dims.y() + y) * rowWords + x / 64] >> (x % 64)) & 1U) != 0;
  };
  std::size_t faces = 0;
  for (int z = 0; z < sv.dims.z(); ++z)
    for (int y = 0; y < sv.dims.y(); ++y)
      for (int x = 0; x < sv.dims.x(); ++x)
        if (filled(x, y, z))
          faces += !filled(x + 1, y, z) + !filled(x - 1, y, z) + !filled(x, y + 1, z) + !filled(x, y - 1, z) + !filled(x, y, z + 1) + !filled(x, y, z - 1);
  double area = 0.0;
  for (const auto& t : sv.mesh.triangles)
    area += 0.5 * (sv.mesh.vertices[t[1]] - sv.mesh.vertices[t[0]]).cross(sv.mesh.vertices[t[2]] - sv.mesh.vertices[t[0]]).norm();
  EXPECT_NEAR(area, static_cast<double>(faces) * h * h, 1e-9 * area);
  EXPECT_LT(sv.mesh.triangles.size(), faces / 2) << "fewer than a quarter of two triangles a voxel face";
  expectClosedAndWhole(sv);
  // The same grid gives the same surface.
  const TriMesh again = sv.surface();
  EXPECT_EQ(again.triangles, sv.mesh.triangles);
}

TEST(SweptVolume, BadInputIsRefusedWithWhatWasExpected) {
  const TriMesh box = primitives::box({0.01, 0.01, 0.01});
  EXPECT_THROW(sweep(box, {{at(0, 0, 0)}}, 0.0), std::invalid_argument);
  EXPECT_THROW(sweep(box, {{at(0, 0, 0)}}, std::nan("")), std::invalid_argument);
  EXPECT_THROW(sweep(box, {}, 0.001), std::invalid_argument);
  EXPECT_THROW(sweep(box, {{at(0, 0, std::nan(""))}}, 0.001), std::invalid_argument);
  // 100 m at 1 micrometre: far beyond what a grid may hold; the message says what fits.
  try {
    (void)sweep(box, {{at(0, 0, 0), at(100, 0, 0)}}, 1e-6);
    FAIL() << "a grid of that size was accepted";
  } catch (const std::invalid_argument& e) {
    // 100 m by a 1 cm box at 1 um: (1e8 x 1e4 x 1e4 / 2^32)^(1/3) = 0.13 mm per voxel at the least, a few
    // voxels more at the border.
    const std::string what = e.what();
    std::smatch m;
    ASSERT_TRUE(std::regex_search(what, m, std::regex(R"(a larger voxel \(([0-9.]+) mm or more\))"))) << what;
    const double suggested = std::stod(m[1].str());
    EXPECT_GE(suggested, 0.14) << e.what();
    EXPECT_LE(suggested, 0.2) << e.what();
  }
  // A grid within the limit but not within the memory a sweep may use: refused before anything is allocated,
  // with the voxel that fits that memory, which then sweeps.
  const std::uint64_t inOneMB = sweepVoxelsInMemory(1.0);
  EXPECT_EQ(inOneMB, 1048576u * 8 / 3);
  EXPECT_EQ(sweepVoxelsInMemory(1e9), kMaxSweepVoxels);
  const std::vector<std::vector<Eigen::Isometry3d>> path = {{at(0, 0, 0), at(0.2, 0, 0)}};
  try {
    (void)sweep(box, path, 0.0001, inOneMB);
    FAIL() << "a grid of more than a megabyte was accepted";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("in the memory a sweep may use"), std::string::npos) << what;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(what, m, std::regex(R"(a larger voxel \(([0-9.]+) mm or more\))"))) << what;
    const SweptVolume fitted = sweep(box, path, 1e-3 * std::stod(m[1].str()), inOneMB);
    EXPECT_GT(fitted.voxels, 0u);
    EXPECT_LE(static_cast<std::uint64_t>(fitted.dims.cast<double>().prod()), inOneMB);
  }
}

namespace {

// A round plate (the base, turning about its axis at the origin) and a ball of radius 5 mm held 60 mm
// from the axis while the base turns a quarter turn beneath it.
std::shared_ptr<const Scene> turntable(std::filesystem::path& file) {
  file = vaw::test::tempDir() / "turntable.vaw.json";
  std::ofstream(file) << R"({
    "format": "vaw-scene", "version": 1, "name": "Ball over a turning plate", "units": "mm",
    "materials": {"steel": {"density": 7850, "friction": {"static": 0.3, "kinetic": 0.2, "rotational": 0.0005}}},
    "parts": [
      {"name": "plate", "primitive": {"type": "cylinder", "radius": 150, "height": 20, "segments": 64}, "material": "steel", "pose": {"position": [0, 0, 10]}},
      {"name": "ball", "primitive": {"type": "sphere", "radius": 5, "segments": 32, "rings": 16}, "material": "steel", "pose": {"position": [60, 0, 100]}}
    ],
    "base": "plate",
    "environment": [{"name": "table", "kind": "table", "primitive": {"type": "box", "size": [2400, 1200, 40]}, "pose": {"position": [0, 0, -20]}}]
  })";
  return Scene::build(loadAny(file, vaw::test::importers()));
}

}  // namespace

TEST(SweptVolume, RelativeToATurningBaseTheHeldPartSweepsAnArcOnIt) {
  std::filesystem::path file;
  const auto scene = turntable(file);
  const PartId ball = *scene->assembly().findPart("ball");
  Session s;
  s.scene = file.string();
  const int steps = 90;
  for (int i = 0; i <= steps + 1; ++i) {
    Input in;
    in.right = simtest::hand(at(0.060, 0.0, 0.100), i <= steps);
    in.base = turned(0.5 * kPi * std::min(i, steps) / steps, Eigen::Vector3d::UnitZ(), Eigen::Vector3d(0, 0, 0.010));
    s.inputs.push_back(in);
  }
  SweptVolumeOptions o;
  o.voxel = 0.001;
  const SweptVolume still = sweptVolume(scene, s, ball, o);
  o.relativeToBase = true;
  const SweptVolume onBase = sweptVolume(scene, s, ball, o);

  const double r = 0.005, rho = 0.060, inside = r * std::cos(kPi / 32) * std::cos(kPi / 16);
  const double bound = (std::sqrt(3.0) + 0.25) * o.voxel;
  const auto ballVolume = [](double radius) { return 4.0 / 3.0 * kPi * std::pow(radius, 3); };
  // Held still in the world: the ball itself.
  EXPECT_GE(still.volume, ballVolume(inside));
  EXPECT_LE(still.volume, ballVolume(r + bound));
  // On the base: a quarter of a torus of tube radius r about the base's axis (Pappus: angle x rho x pi r^2)
  // with a half ball at each end, placed where the base was at the first step.
  // The hold's first step or two may come before the grab takes: the angle carried is within two steps
  // of the quarter turn.
  const auto arc = [&](double angle, double radius) { return angle * rho * kPi * radius * radius + ballVolume(radius); };
  EXPECT_GE(onBase.volume, arc(0.5 * kPi * (steps - 2) / steps, inside));
  EXPECT_LE(onBase.volume, arc(0.5 * kPi, r + bound));
  EXPECT_TRUE(onBase.relativeToBase);
  for (const Eigen::Vector3d& v : onBase.mesh.vertices) {
    // In the base's frame at the first step: the ball's centre turns from there backwards, about z.
    const Eigen::Vector3d q = onBase.frame.inverse() * v;
    const double rr = std::hypot(q.x(), q.y());
    ASSERT_LE(std::hypot(rr - rho, q.z() - 0.090), r + bound + 1e-9) << q.transpose();
  }
  expectClosedAndWhole(onBase);
  // Made again from the grid (as for a volume kept without its mesh): the same mesh, in the same frame.
  const TriMesh again = onBase.surface();
  EXPECT_EQ(again.triangles, onBase.mesh.triangles);
  EXPECT_EQ(again.vertices, onBase.mesh.vertices);

  // Asked of a scene's base itself, or of a span without steps: refused, naming the field.
  o.relativeToBase = true;
  try {
    (void)sweptVolume(scene, s, *scene->assembly().findPart("plate"), o);
    FAIL() << "the base swept relative to itself";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("relative-to-base"), std::string::npos) << e.what();
  }
  o.relativeToBase = false;
  o.from = 100.0;
  EXPECT_THROW((void)sweptVolume(scene, s, ball, o), InputError);
}

// The volume and the clearance in one replay are the two measured in a replay each, bit for bit.
TEST(SweptVolume, OneReplayGivesWhatTwoReplaysGive) {
  std::filesystem::path file;
  const auto scene = turntable(file);
  const PartId ball = *scene->assembly().findPart("ball");
  Session s;
  s.scene = file.string();
  for (int i = 0; i <= 40; ++i) {
    Input in;
    in.right = simtest::hand(at(0.060 - 0.001 * i, 0.0, 0.100 - 0.002 * i), i < 40);
    s.inputs.push_back(in);
  }
  SweptVolumeOptions so;
  so.voxel = 0.002;
  ClearanceOptions co;
  co.threshold = 0.030;
  const SweptPathAndClearance both = sweptVolumeAndClearance(scene, s, ball, so, co);
  const SweptVolume swept = sweptVolume(scene, s, ball, so);
  const ClearanceReport clearance = clearanceAlong(scene, s, ball, co);
  EXPECT_GT(swept.voxels, 0U);
  EXPECT_EQ(both.swept.occupied, swept.occupied);
  EXPECT_EQ(both.swept.dims, swept.dims);
  EXPECT_EQ(both.swept.from, swept.from);
  EXPECT_EQ(both.swept.to, swept.to);
  ASSERT_EQ(both.clearance.steps.size(), clearance.steps.size());
  ASSERT_FALSE(clearance.steps.empty());
  for (std::size_t i = 0; i < clearance.steps.size(); ++i) {
    EXPECT_EQ(both.clearance.steps[i].t, clearance.steps[i].t);
    EXPECT_EQ(both.clearance.steps[i].distance, clearance.steps[i].distance);
  }
  EXPECT_EQ(both.clearance.spans.size(), clearance.spans.size());
  EXPECT_EQ(both.clearance.objects.size(), clearance.objects.size());
  // A part never carried: refused by whichever measure finishes first, naming the part.
  try {
    (void)sweptVolumeAndClearance(scene, s, *scene->assembly().findPart("plate"), so, co);
    FAIL() << "the plate is never carried";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("plate is never carried"), std::string::npos) << e.what();
  }
}
