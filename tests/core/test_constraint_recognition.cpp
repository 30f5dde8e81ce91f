// Constraint recognition and the table layout on CAD solids built here by hand (exact faces, no CAD
// kernel), so the rules are checked without Open CASCADE; tests/step checks them on real STEP files.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "vaw/cad_assembly.hpp"
#include "vaw/constraint_recognition.hpp"

namespace {

using vaw::CadFace;
using vaw::CadSolid;

// A box [0, sx] x [0, sy] x [0, sz] with its six planar faces, two triangles each, outward.
std::shared_ptr<CadSolid> box(double sx, double sy, double sz, const std::string& name) {
  auto s = std::make_shared<CadSolid>();
  s->product = name;
  for (int i = 0; i < 8; ++i) s->mesh.vertices.emplace_back((i & 1) ? sx : 0.0, (i & 2) ? sy : 0.0, (i & 4) ? sz : 0.0);
  // Each face: four corners counter-clockwise seen from outside, and its outward normal.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  const Eigen::Vector3d normals[6] = {-Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitY(),
                                      Eigen::Vector3d::UnitY(),  -Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitX()};
  const double areas[6] = {sx * sy, sx * sy, sx * sz, sx * sz, sy * sz, sy * sz};
  for (int f = 0; f < 6; ++f) {
    CadFace face;
    face.surface = CadFace::Surface::Plane;
    face.point = s->mesh.vertices[static_cast<std::size_t>(quads[f][0])];
    face.direction = normals[f];
    face.area = areas[f];
    face.firstTriangle = s->mesh.triangles.size();
    face.triangleCount = 2;
    s->mesh.triangles.emplace_back(quads[f][0], quads[f][1], quads[f][2]);
    s->mesh.triangles.emplace_back(quads[f][0], quads[f][2], quads[f][3]);
    s->faces.push_back(face);
  }
  s->volume = sx * sy * sz;
  s->centroid = Eigen::Vector3d(sx, sy, sz) / 2.0;
  return s;
}

// A cylindrical face on the z axis from z0 to z1 (no triangles: inserts need only the exact surface),
// inside a box-shaped mesh for the bounds.
std::shared_ptr<CadSolid> cylinder(double r, double z0, double z1, bool convex, const std::string& name) {
  auto s = box(2 * r, 2 * r, z1 - z0, name);
  s->faces.clear();
  CadFace f;
  f.surface = CadFace::Surface::Cylinder;
  f.point = Eigen::Vector3d(r, r, 0.0);
  f.direction = Eigen::Vector3d::UnitZ();
  f.radius = r;
  f.convex = convex;
  f.axialMin = 0.0;
  f.axialMax = z1 - z0;
  s->faces.push_back(f);
  return s;
}

// A cone's face on the z axis, its apex at the origin of its box's centre line, widening upwards with the
// given half angle between z0 and z1 above the apex.
std::shared_ptr<CadSolid> cone(double halfAngle, double z0, double z1, bool convex, const std::string& name) {
  const double r = z1 * std::tan(halfAngle);
  auto s = box(2 * r, 2 * r, z1 - z0, name);
  s->faces.clear();
  CadFace f;
  f.surface = CadFace::Surface::Cone;
  f.point = Eigen::Vector3d(r, r, -z0);
  f.direction = Eigen::Vector3d::UnitZ();
  f.halfAngle = halfAngle;
  f.radius = r;
  f.convex = convex;
  f.axialMin = z0;
  f.axialMax = z1;
  s->faces.push_back(f);
  return s;
}

Eigen::Isometry3d at(double x, double y, double z) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() = Eigen::Vector3d(x, y, z);
  return p;
}

TEST(ConstraintRecognition, FaceToFaceBoxesMateOverTheirCommonArea) {
  // A 20 mm cube on a 40 x 40 mm plate, half of it overhanging the plate's edge.
  const auto plate = box(0.040, 0.040, 0.010, "plate"), cube = box(0.020, 0.020, 0.020, "cube");
  const auto found = vaw::recognizeConstraints({{plate, at(0, 0, 0)}, {cube, at(0.030, 0.010, 0.010)}});
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].type, vaw::Constraint::Type::Mate);
  EXPECT_EQ(found[0].a, 0u);
  EXPECT_EQ(found[0].b, 1u);
  // 10 mm of x (30..40) by 20 mm of y (10..30): 2e-4 m^2, exact for polygons up to round-off.
  EXPECT_NEAR(found[0].found.overlap, 0.010 * 0.020, 1e-15);
  EXPECT_TRUE(found[0].direction.isApprox(Eigen::Vector3d::UnitZ()));
}

TEST(ConstraintRecognition, BoxesTouchingAtAnEdgeOrWithAGapGiveNone) {
  const auto a = box(0.020, 0.020, 0.020, "a"), b = box(0.020, 0.020, 0.020, "b");
  // Along one edge: b's bottom face and a's top face share only the line x = 20 mm.
  EXPECT_TRUE(vaw::recognizeConstraints({{a, at(0, 0, 0)}, {b, at(0.020, 0, 0.020)}}).empty());
  // At a corner.
  EXPECT_TRUE(vaw::recognizeConstraints({{a, at(0, 0, 0)}, {b, at(0.020, 0.020, 0.020)}}).empty());
  // Side by side with a 0.1 mm gap: parallel faces, but not in one plane.
  EXPECT_TRUE(vaw::recognizeConstraints({{a, at(0, 0, 0)}, {b, at(0.0201, 0, 0)}}).empty());
}

TEST(ConstraintRecognition, ShaftInBoreIsAnInsertWithItsClearance) {
  const auto bore = cylinder(0.0065, 0.0, 0.008, false, "bracket");
  const auto shaft = cylinder(0.006, 0.0, 0.034, true, "stud");
  // Coaxial: the shaft's box is 0.5 mm narrower on each side, its axis at the same x, y.
  const auto found = vaw::recognizeConstraints({{bore, at(0, 0, 0.008)}, {shaft, at(0.0005, 0.0005, -0.008)}});
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].type, vaw::Constraint::Type::Insert);
  EXPECT_NEAR(found[0].found.clearance, 0.0005, 1e-12);
  EXPECT_NEAR(found[0].found.overlap, 0.008, 1e-12);
  EXPECT_DOUBLE_EQ(found[0].found.partRadius, 0.0065);  // face a's radius: the bore's
  EXPECT_DOUBLE_EQ(found[0].found.partnerRadius, 0.006);
}

TEST(ConstraintRecognition, OffAxisLooseDisjointOrBothBoresAreNoInsert) {
  const auto bore = cylinder(0.0065, 0.0, 0.008, false, "bore");
  // 1 mm off the axis.
  EXPECT_TRUE(vaw::recognizeConstraints({{bore, at(0, 0, 0)}, {cylinder(0.006, 0, 0.02, true, "s"), at(0.0015, 0.0005, 0)}}).empty());
  // A 4 mm radius in a 6.5 mm bore: 2.5 mm play is no fit.
  EXPECT_TRUE(vaw::recognizeConstraints({{bore, at(0, 0, 0)}, {cylinder(0.004, 0, 0.02, true, "s"), at(0.0025, 0.0025, 0)}}).empty());
  // On the axis but above the bore.
  EXPECT_TRUE(vaw::recognizeConstraints({{bore, at(0, 0, 0)}, {cylinder(0.006, 0, 0.02, true, "s"), at(0.0005, 0.0005, 0.010)}}).empty());
  // Two bores on one axis (a hole in a plate under a hole in a bracket).
  EXPECT_TRUE(vaw::recognizeConstraints({{bore, at(0, 0, 0)}, {cylinder(0.006, 0, 0.02, false, "h"), at(0.0005, 0.0005, 0)}}).empty());
}

TEST(ConstraintRecognition, AHeadsConeInACountersinkIsTheSeatOfAnInsertAlongItsAxis) {
  const double half = std::numbers::pi / 4;  // a 90 degree countersunk head
  // The countersink from 2 to 5 mm above its apex (radius 2..5 mm), the head's cone from 2.5 to 5 mm: one
  // surface where they overlap. Both boxes are centred on their axes.
  const auto sink = cone(half, 0.002, 0.005, false, "cover"), head = cone(half, 0.0025, 0.005, true, "screw");
  const auto found = vaw::recognizeConstraints({{sink, at(0, 0, 0.002)}, {head, at(0.0, 0.0, 0.0025)}});
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].type, vaw::Constraint::Type::Insert);
  EXPECT_EQ(found[0].found.seat, vaw::Constraint::Found::Seat::Countersink);
  EXPECT_NEAR(found[0].found.seatRadius, 0.005, 1e-12);
  EXPECT_NEAR(found[0].found.seatAngle, half, 1e-12);
  EXPECT_NEAR(found[0].found.overlap, 0.0025, 1e-12);
  EXPECT_TRUE(found[0].direction.isApprox(Eigen::Vector3d::UnitZ()));

  // A head of 82 degrees (an inch screw's) in a 90 degree countersink touches along a circle only; a head
  // standing 0.1 mm proud of its countersink is no seat either; each says why when chosen by hand.
  const auto inch = cone(41.0 * std::numbers::pi / 180.0, 0.0025, 0.005, true, "inch screw");
  const double centre = 0.005 - inch->faces[0].radius;  // its box is narrower: on the countersink's axis
  const std::vector<vaw::RecognitionPart> inchIn = {{sink, at(0, 0, 0.002)}, {inch, at(centre, centre, 0.0025)}};
  EXPECT_TRUE(vaw::recognizeConstraints(inchIn).empty());
  const std::vector<vaw::RecognitionPart> proud = {{sink, at(0, 0, 0.002)},
                                                   {head, at(0.0, 0.0, 0.0025 + 0.0002 / std::sin(half))}};
  EXPECT_TRUE(vaw::recognizeConstraints(proud).empty());
  const vaw::FacePairResult why = vaw::constraintFromFaces(proud, 0, 0, 1, 0);
  EXPECT_FALSE(why.found);
  EXPECT_EQ(why.why, "the cones stand 0.2 mm apart");
  const vaw::FacePairResult angles = vaw::constraintFromFaces(inchIn, 0, 0, 1, 0);
  EXPECT_EQ(angles.why, "the cones' half angles are 4.0 deg apart");
}

TEST(ConstraintRecognition, FaceAtPicksTheFaceUnderAPoint) {
  // 1 % of the box's size, as the Constraints panel asks.
  const auto b = box(0.040, 0.030, 0.010, "plate");
  const double tol = 0.0005;
  EXPECT_EQ(vaw::faceAt(*b, {0.020, 0.015, 0.010}, tol), std::optional<std::size_t>(1));  // top
  EXPECT_EQ(vaw::faceAt(*b, {0.020, 0.015, 0.0102}, tol), std::optional<std::size_t>(1));
  EXPECT_EQ(vaw::faceAt(*b, {0.020, 0.000, 0.005}, tol), std::optional<std::size_t>(2));  // -y side
  EXPECT_EQ(vaw::faceAt(*b, {0.040, 0.010, 0.005}, tol), std::optional<std::size_t>(5));  // +x side
  // Near an edge the face the point lies on wins over the one it is merely close to.
  EXPECT_EQ(vaw::faceAt(*b, {0.0398, 0.010, 0.010}, tol), std::optional<std::size_t>(1));
  // Inside the material, and on the top face's plane but past its edge: no face.
  EXPECT_FALSE(vaw::faceAt(*b, {0.020, 0.015, 0.005}, tol));
  EXPECT_FALSE(vaw::faceAt(*b, {0.060, 0.015, 0.010}, tol));

  const double r = 0.006;
  const auto c = cylinder(r, 0.0, 0.020, true, "stud");
  EXPECT_EQ(vaw::faceAt(*c, {2 * r, r, 0.010}, tol), std::optional<std::size_t>(0));
  EXPECT_EQ(vaw::faceAt(*c, {r + r * std::cos(1.0), r + r * std::sin(1.0), 0.0201}, tol), std::optional<std::size_t>(0));
  EXPECT_FALSE(vaw::faceAt(*c, {r, r, 0.010}, tol));      // on the axis
  EXPECT_FALSE(vaw::faceAt(*c, {2 * r, r, 0.025}, tol));  // past the face's end
}

TEST(ConstraintRecognition, TwoChosenCylindersAreTestedAsRecognitionTestsThem) {
  const auto bore = cylinder(0.0065, 0.0, 0.008, false, "bracket");
  const auto shaft = cylinder(0.006, 0.0, 0.034, true, "stud");
  const std::vector<vaw::RecognitionPart> parts{{bore, at(0, 0, 0.008)}, {shaft, at(0.0005, 0.0005, -0.008)}};
  // The shaft chosen first: it is face a, so the radii follow it.
  const auto r = vaw::constraintFromFaces(parts, 1, 0, 0, 0);
  ASSERT_TRUE(r.found.has_value()) << r.why;
  EXPECT_TRUE(r.why.empty());
  EXPECT_EQ(r.found->type, vaw::Constraint::Type::Insert);
  EXPECT_EQ(r.found->a, 1u);
  EXPECT_EQ(r.found->b, 0u);
  EXPECT_NEAR(r.found->found.clearance, 0.0005, 1e-12);
  EXPECT_NEAR(r.found->found.overlap, 0.008, 1e-12);
  EXPECT_DOUBLE_EQ(r.found->found.partRadius, 0.006);
  EXPECT_DOUBLE_EQ(r.found->found.partnerRadius, 0.0065);
  // What recognition finds for the pair, the other way round.
  const auto all = vaw::recognizeConstraints(parts);
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].found.overlap, r.found->found.overlap);
  EXPECT_TRUE(all[0].point.isApprox(r.found->point));
}

TEST(ConstraintRecognition, TwoChosenFacesThatAreNoConstraintSayWhy) {
  const auto bore = cylinder(0.0065, 0.0, 0.008, false, "bore");
  const auto why = [](const std::shared_ptr<CadSolid>& x, const Eigen::Isometry3d& px, const std::shared_ptr<CadSolid>& y,
                      const Eigen::Isometry3d& py, std::size_t fx = 0, std::size_t fy = 0) {
    const auto r = vaw::constraintFromFaces({{x, px}, {y, py}}, 0, fx, 1, fy);
    EXPECT_FALSE(r.found.has_value());
    return r.why;
  };
  // 1.4 mm off the axis: 1 mm in x, 1 mm in y.
  EXPECT_EQ(why(bore, at(0, 0, 0), cylinder(0.006, 0, 0.02, true, "s"), at(0.0015, 0.0015, 0)), "the axes are 1.4 mm apart");
  Eigen::Isometry3d tilted = at(0.0005, 0.0005, 0);
  tilted.linear() = Eigen::AngleAxisd(3.2 * std::numbers::pi / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  EXPECT_EQ(why(bore, at(0, 0, 0), cylinder(0.006, 0, 0.02, true, "s"), tilted), "the axes are 3.2 deg apart");
  // A 17.5 mm shaft in a 20 mm bore: the play allowed is 2 mm (15 % of the bore's radius would be 3 mm).
  EXPECT_EQ(why(cylinder(0.020, 0, 0.01, false, "b"), at(0, 0, 0), cylinder(0.0175, 0, 0.02, true, "s"), at(0.0025, 0.0025, 0)),
            "the bore is 2.5 mm larger in radius than the shaft: more play than 2.0 mm");
  EXPECT_EQ(why(bore, at(0, 0, 0), cylinder(0.006, 0, 0.02, false, "h"), at(0.0005, 0.0005, 0)), "both are holes");
  EXPECT_EQ(why(bore, at(0, 0, 0), cylinder(0.006, 0, 0.02, true, "s"), at(0.0005, 0.0005, 0.010)),
            "the faces do not overlap along the axis (2.0 mm between them)");

  const auto plate = box(0.040, 0.040, 0.010, "plate"), cube = box(0.020, 0.020, 0.020, "cube");
  // Both top faces (index 1).
  EXPECT_EQ(why(plate, at(0, 0, 0), cube, at(0.01, 0.01, 0.010), 1, 1), "the planes face the same way");
  // The cube's bottom (0) 4 mm above the plate's top (1).
  EXPECT_EQ(why(plate, at(0, 0, 0), cube, at(0.01, 0.01, 0.014), 1, 0), "the planes are 4.0 mm apart");
  // In one plane but side by side.
  EXPECT_EQ(why(plate, at(0, 0, 0), cube, at(0.05, 0.01, 0.010), 1, 0), "the faces share no area");
  EXPECT_EQ(why(plate, at(0, 0, 0), cube, at(0.01, 0.01, 0.010), 1, 2), "the planes are 90.0 deg from facing each other");
  EXPECT_EQ(why(plate, at(0, 0, 0), cylinder(0.006, 0, 0.02, true, "s"), at(0.01, 0.01, 0.010), 1, 0),
            "the two faces are not both cylinders, both cones or both planes");
  EXPECT_EQ(why(plate, at(0, 0, 0), plate, at(0, 0, 0.010), 1, 1), "the planes face the same way");
  // Face to face: a mate over the common area, a's normal its direction.
  const auto r = vaw::constraintFromFaces({{plate, at(0, 0, 0)}, {cube, at(0.030, 0.010, 0.010)}}, 1, 0, 0, 1);
  ASSERT_TRUE(r.found.has_value()) << r.why;
  EXPECT_EQ(r.found->type, vaw::Constraint::Type::Mate);
  EXPECT_NEAR(r.found->found.overlap, 0.010 * 0.020, 1e-15);
  EXPECT_TRUE(r.found->direction.isApprox(-Eigen::Vector3d::UnitZ()));
  EXPECT_EQ(vaw::constraintFromFaces({{plate, at(0, 0, 0)}}, 0, 1, 0, 0).why, "both faces are on the same part");
}

vaw::Part partOf(const std::shared_ptr<CadSolid>& s, vaw::PartId id, double mass) {
  vaw::Part p;
  p.id = id;
  p.name = s->product;
  p.cad = s;
  p.mesh = std::make_shared<const vaw::TriMesh>(s->mesh);
  p.mass.mass = mass;
  p.mass.centerOfMass = s->centroid;
  return p;
}

TEST(ConstraintRecognition, PartnersFollowTheAssemblyOrderFromTheBase) {
  // plate (base) <- block on it <- cap on the block: the cap's partner is the block, the block's the base.
  const auto plate = box(0.100, 0.100, 0.010, "plate"), block = box(0.020, 0.020, 0.020, "block"), cap = box(0.020, 0.020, 0.005, "cap");
  const std::vector<Eigen::Isometry3d> poses{at(0, 0, 0), at(0.04, 0.04, 0.010), at(0.04, 0.04, 0.030)};
  const std::vector<vaw::Part> parts{partOf(plate, 0, 2.0), partOf(block, 1, 0.5), partOf(cap, 2, 0.1)};
  const auto found = vaw::recognizeConstraints({{plate, poses[0]}, {block, poses[1]}, {cap, poses[2]}});
  ASSERT_EQ(found.size(), 2u);
  const auto cons = vaw::constraintsFromFound(found, parts, 0, poses);
  ASSERT_EQ(cons.size(), 2u);
  EXPECT_EQ(cons[0].part, 1u);
  EXPECT_FALSE(cons[0].partner.has_value());
  EXPECT_EQ(cons[1].part, 2u);
  ASSERT_TRUE(cons[1].partner.has_value());
  EXPECT_EQ(*cons[1].partner, 1u);
  EXPECT_EQ(cons[1].name, "mate cap on block");
  // Geometry in each one's own frame: the cap's bottom (z = 0, normal down), the block's top (z = 20 mm, up).
  EXPECT_NEAR(cons[1].partPlane.point.z(), 0.0, 1e-12);
  EXPECT_TRUE(cons[1].partPlane.normal.isApprox(-Eigen::Vector3d::UnitZ()));
  EXPECT_NEAR(cons[1].basePlane.point.z(), 0.020, 1e-12);
  EXPECT_TRUE(cons[1].basePlane.normal.isApprox(Eigen::Vector3d::UnitZ()));
  // It comes home from above, off the plane.
  EXPECT_TRUE(cons[1].homeDirection.isApprox(Eigen::Vector3d::UnitZ()));
}

TEST(ConstraintRecognition, AnInsertComesHomeFromTheSideOfItsCentreOfMass) {
  const auto plate = cylinder(0.006, 0.0, 0.008, false, "plate");
  auto stud = cylinder(0.006, 0.0, 0.034, true, "stud");
  const std::vector<Eigen::Isometry3d> poses{at(0, 0, 0.002), at(0, 0, 0.002)};
  const std::vector<vaw::Part> parts{partOf(plate, 0, 2.0), partOf(stud, 1, 0.1)};
  const auto found = vaw::recognizeConstraints({{plate, poses[0]}, {stud, poses[1]}});
  ASSERT_EQ(found.size(), 1u);
  const auto cons = vaw::constraintsFromFound(found, parts, 0, poses);
  ASSERT_EQ(cons.size(), 1u);
  EXPECT_EQ(cons[0].part, 1u);
  EXPECT_EQ(cons[0].found->clearance, 0.0);
  // The stud's centre of mass (17 mm up its 34 mm) lies above the hole's middle (4 mm): it comes from +z.
  EXPECT_TRUE(cons[0].homeDirection.isApprox(Eigen::Vector3d::UnitZ()));
}

TEST(CadLayout, PartsRestOnTheirLargestStableFaceAndNeverOverlap) {
  const auto base = box(0.200, 0.150, 0.020, "base");
  std::vector<vaw::Part> parts{partOf(base, 0, 5.0)};
  std::vector<Eigen::Matrix3d> orient{Eigen::Matrix3d::Identity()};
  // Tall thin bars would fall over: each must lie on a long face, 10 mm high.
  for (vaw::PartId id = 1; id <= 12; ++id) {
    auto bar = box(0.010, 0.020, 0.120, "bar" + std::to_string(id));
    parts.push_back(partOf(bar, id, 0.2));
    const vaw::Principal pr = vaw::principalMoments(Eigen::Vector3d(1.0, 2.0, 3.0).asDiagonal().toDenseMatrix());
    orient.push_back(vaw::restingOrientation(bar->mesh, bar->centroid, pr, bar.get()));
  }
  const auto poses = vaw::layOutBeside(parts, 0, orient, 0.0, 0.02);
  std::vector<Eigen::AlignedBox3d> boxes;
  for (vaw::PartId id = 0; id < parts.size(); ++id) {
    Eigen::AlignedBox3d b;
    for (const auto& v : parts[id].mesh->vertices) b.extend(poses[id] * v);
    if (id > 0) {
      EXPECT_NEAR(b.min().z(), 0.0, 1e-12) << id;
      EXPECT_NEAR(b.sizes().z(), 0.010, 1e-9) << "bar " << id << " stands on its smallest face";
    }
    boxes.push_back(b);
  }
  for (std::size_t i = 0; i < boxes.size(); ++i)
    for (std::size_t j = i + 1; j < boxes.size(); ++j) {
      const Eigen::AlignedBox3d common = boxes[i].intersection(boxes[j]);
      const bool overlap = !common.isEmpty() && (common.sizes().array() > 1e-9).all();
      EXPECT_FALSE(overlap) << i << " and " << j;
    }
}

}  // namespace
