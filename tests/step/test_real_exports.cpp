// Assemblies as CAD systems write them (docs/step.md, "Files as CAD systems write them"), built with Open
// CASCADE in each test: cylinders divided into two or four faces, analytic or B-spline, headed bolts whose
// head clamps the bracket they pass through, products named but instances not, inches, Y up. Each must give
// one constraint per real contact, every one of them usable, partners as a fitter has them, an order that
// keeps every true precedence, names from the products, and the base lying on its largest face.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <map>
#include <ostream>
#include <set>
#include <string>
#include <vector>

#include "bundled.hpp"
#include "assembler.hpp"
#include "files.hpp"
#include "step_fixtures.hpp"
#include "vaw/cad_assembly.hpp"
#include "vaw/cad_faces.hpp"
#include "vaw/collision/collision_world.hpp"
#include "vaw/evaluation/sequence.hpp"
#include "vaw/kept_results.hpp"
#include "vaw/scene_loader.hpp"

namespace {

namespace fs = std::filesystem;
using vaw::Assembly;
using vaw::Constraint;
using vaw::PartId;
using vaw::steptest::ExportStyle;

struct Variant {
  const char* label;
  ExportStyle style;
};

std::string label(const ::testing::TestParamInfo<Variant>& info) { return info.param.label; }
// Named in test lists by its label, not its bytes.
void PrintTo(const Variant& v, std::ostream* os) { *os << v.label; }

const Variant kVariants[] = {
    {"Clean", {}},
    {"SplitInTwo", {2, false, true, false, false, "AP214"}},
    {"SplitInFour", {4, false, true, false, false, "AP214"}},
    {"SplitInFourBSpline", {4, true, true, false, false, "AP214"}},
    {"SplitInTwoBSpline", {2, true, true, false, false, "AP214"}},
    // As Pro/ENGINEER wrote it: AP203 in inches, Y up, names on the products only, cylinders in halves.
    {"Ap203InchesYUpUnnamed", {2, false, false, true, true, "AP203"}},
};

class RealExport : public ::testing::TestWithParam<Variant> {
 protected:
  static std::map<std::string, Assembly>& cache() {
    static std::map<std::string, Assembly> loaded;
    return loaded;
  }
  const Assembly& assembly() {
    const Variant& v = GetParam();
    auto it = cache().find(v.label);
    if (it == cache().end()) {
      const fs::path file = vaw::test::tempDir() / (std::string("bolted-rod-") + v.label + ".stp");
      vaw::steptest::writeBoltedRod(file, v.style);
      it = cache().emplace(v.label, vaw::loadAny(file, vaw::test::importers())).first;
    }
    return it->second;
  }
  // A part by its instance name in the named file ("bolt-3"); in a file without instance names, the part of
  // that product in the same place in file order ("BOLT #3").
  PartId id(const std::string& instance) {
    const Assembly& a = assembly();
    std::string name = instance;
    if (!GetParam().style.namedInstances) {
      static const std::map<std::string, std::string> products = {{"plate", "PLATE"}, {"bracket", "L-BRACKET"}, {"bolt", "BOLT"},
                                                                  {"nut", "NUT"},     {"rod", "ROD"},             {"rod-nut", "ROD-NUT"}};
      const auto dash = instance.find_last_of('-');
      const bool numbered = dash != std::string::npos && std::isdigit(static_cast<unsigned char>(instance[dash + 1]));
      const std::string kind = numbered ? instance.substr(0, dash) : instance;
      name = products.at(kind);
      if (numbered && instance.substr(dash + 1) != "1") name += " #" + instance.substr(dash + 1);
    }
    for (const auto& p : a.parts)
      if (p.name == name) return p.id;
    ADD_FAILURE() << "no part " << name;
    return 0;
  }
  // The constraints between two parts, as "kind part on partner".
  std::vector<const Constraint*> between(PartId x, PartId y) {
    std::vector<const Constraint*> out;
    const Assembly& a = assembly();
    for (const auto& c : a.constraints) {
      const PartId partner = c.partner.value_or(*a.base);
      if ((c.part == x && partner == y) || (c.part == y && partner == x)) out.push_back(&c);
    }
    return out;
  }
  // The checks, each on the file of this variant (loaded once per test process).
  void OneConstraintPerRealContactAndEachOneFits();
  void PartnersAsAFitterHasThem();
  void AnOrderKeepsEveryTruePrecedence();
  void TheBaseLiesOnItsLargestFaceAndTheAssemblyTurnsWithIt();
  void NamesComeFromTheFileNeverFromTheKernel();

  // Every constraint between `part` and `partner` has them that way round, and there is one per `kinds`.
  void expectPartner(const std::string& part, const std::string& partner, std::multiset<Constraint::Type> kinds) {
    const auto cs = between(id(part), id(partner));
    std::multiset<Constraint::Type> found;
    for (const Constraint* c : cs) {
      found.insert(c->type);
      EXPECT_EQ(c->part, id(part)) << c->name << ": " << part << " goes onto " << partner;
    }
    EXPECT_EQ(found, kinds) << part << " with " << partner;
  }
};

void RealExport::OneConstraintPerRealContactAndEachOneFits() {
  const Assembly& a = assembly();
  ASSERT_EQ(a.parts.size(), 18u);
  int inserts = 0, mates = 0;
  std::set<std::string> names;
  for (const auto& c : a.constraints) {
    (c.type == Constraint::Type::Insert ? inserts : mates) += 1;
    EXPECT_TRUE(names.insert(c.name).second) << "two constraints named " << c.name;
  }
  EXPECT_EQ(inserts, 22);
  EXPECT_EQ(mates, 16);
  // Each found in the geometry meets its partner's surfaces: no "no cylindrical surface on the axis".
  const auto fits = vaw::collision::constraintFits(a);
  ASSERT_EQ(fits.size(), a.constraints.size());
  for (const auto& f : fits) EXPECT_EQ(f.support.problem, "") << a.constraints[f.constraint].name;
  // The clearances as modelled: bolts in their holes and the rod in its bores 0.25 mm, nuts on shanks 0.
  for (const auto& c : a.constraints) {
    if (c.type != Constraint::Type::Insert) continue;
    ASSERT_TRUE(c.found.has_value());
    const bool nut = a.parts[c.part].product == "NUT" || a.parts[c.part].product == "ROD-NUT";
    EXPECT_NEAR(c.found->clearance, nut ? 0.0 : 0.00025, 2e-6) << c.name;
  }
}

void RealExport::PartnersAsAFitterHasThem() {
  using T = Constraint::Type;
  for (int k = 1; k <= 6; ++k) {
    const std::string bolt = "bolt-" + std::to_string(k), bracket = k <= 3 ? "bracket-1" : "bracket-2";
    // The head clamps the bracket: the bracket first, the bolt through it and onto it.
    expectPartner(bolt, bracket, {T::Insert, T::Mate});
    expectPartner(bolt, "plate", {T::Insert});
    // The nut after its bolt, onto its shank, against the plate.
    expectPartner("nut-" + std::to_string(k), bolt, {T::Insert});
    expectPartner("nut-" + std::to_string(k), "plate", {T::Mate});
  }
  expectPartner("rod", "bracket-1", {T::Insert});
  expectPartner("rod", "bracket-2", {T::Insert});
  expectPartner("rod-nut-1", "rod", {T::Insert});
  expectPartner("rod-nut-1", "bracket-1", {T::Mate});
  expectPartner("rod-nut-2", "rod", {T::Insert});
  expectPartner("rod-nut-2", "bracket-2", {T::Mate});
  expectPartner("bracket-1", "plate", {T::Mate});
}

void RealExport::AnOrderKeepsEveryTruePrecedence() {
  const Assembly& a = assembly();
  const auto plan = vaw::eval::planSequence(a);
  ASSERT_TRUE(plan.complete()) << plan.stuck.size() << " parts without an order";
  EXPECT_EQ(plan.undecided, 0);
  const auto at = [&](const std::string& n) {
    return std::find(plan.order.begin(), plan.order.end(), id(n)) - plan.order.begin();
  };
  for (int k = 1; k <= 6; ++k) {
    const std::string bolt = "bolt-" + std::to_string(k);
    EXPECT_LT(at(k <= 3 ? "bracket-1" : "bracket-2"), at(bolt));
    EXPECT_LT(at(bolt), at("nut-" + std::to_string(k)));
  }
  EXPECT_LT(at("bracket-1"), at("rod"));
  EXPECT_LT(at("bracket-2"), at("rod"));
  EXPECT_LT(at("rod"), at("rod-nut-1"));
  EXPECT_LT(at("rod"), at("rod-nut-2"));
  for (const auto& e : plan.precedence)
    EXPECT_LT(std::find(plan.order.begin(), plan.order.end(), e.before), std::find(plan.order.begin(), plan.order.end(), e.after));
}

void RealExport::TheBaseLiesOnItsLargestFaceAndTheAssemblyTurnsWithIt() {
  const Assembly& a = assembly();
  ASSERT_TRUE(a.base.has_value());
  EXPECT_EQ(*a.base, id("plate"));
  EXPECT_EQ(a.cadUp, "auto");
  // The model's up: the file's +Y when it was written Y up.
  const Eigen::Vector3d modelUp = GetParam().style.yUp ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ();
  EXPECT_NEAR((a.cadUpAxis - modelUp).norm(), 0.0, 1e-9);
  // The plate lies flat: 200 x 100 footprint, 10 mm high, held 12 mm over the table top (z = 0) by the
  // bolts' ends under it, so that the assembly as built stands on the table.
  Eigen::AlignedBox3d plate;
  for (const auto& v : a.parts[*a.base].mesh->vertices) plate.extend(a.parts[*a.base].pose * v);
  EXPECT_NEAR(plate.sizes().z(), 0.010, 1e-6);
  EXPECT_NEAR(plate.min().z(), 0.012, 1e-6);
  EXPECT_NEAR(std::max(plate.sizes().x(), plate.sizes().y()), 0.200, 1e-6);
  // The rod lies along the plate, above it, 40 mm over the plate's bottom face.
  const Eigen::Vector3d rodCentre = *a.parts[id("rod")].finalPose * a.parts[id("rod")].mass.centerOfMass;
  EXPECT_NEAR(rodCentre.z() - plate.min().z(), 0.040, 1e-6);
  // A bolt's way home is straight down.
  for (const auto& c : a.constraints)
    if (c.part == id("bolt-1") && c.type == Constraint::Type::Mate) {
      const Eigen::Vector3d out = a.parts[c.partner.value_or(*a.base)].finalPose.value_or(a.parts[*a.base].pose).linear() * c.homeDirection;
      EXPECT_NEAR(out.z(), 1.0, 1e-9);
    }
}

void RealExport::NamesComeFromTheFileNeverFromTheKernel() {
  const Assembly& a = assembly();
  for (const auto& p : a.parts) {
    EXPECT_EQ(p.name.find("=>"), std::string::npos) << p.name;
    EXPECT_EQ(p.name.find("0:1:"), std::string::npos) << p.name;
  }
  EXPECT_EQ(a.parts[id("bolt-4")].product, "BOLT");
  if (!GetParam().style.namedInstances) {
    std::multiset<std::string> names;
    for (const auto& p : a.parts) names.insert(p.name);
    EXPECT_EQ(names.count("BOLT"), 1u);
    EXPECT_EQ(names.count("BOLT #6"), 1u);
    EXPECT_EQ(names.count("L-BRACKET #2"), 1u);
    EXPECT_EQ(names.count("PLATE"), 1u);
  }
}

// Every check on one file: the file is written and read once (about 1.5 s), not once per check.
TEST_P(RealExport, EveryCheck) {
  {
    SCOPED_TRACE("one constraint per real contact, each meeting its surfaces");
    OneConstraintPerRealContactAndEachOneFits();
  }
  {
    SCOPED_TRACE("partners as a fitter has them");
    PartnersAsAFitterHasThem();
  }
  {
    SCOPED_TRACE("an order keeping every true precedence");
    AnOrderKeepsEveryTruePrecedence();
  }
  {
    SCOPED_TRACE("the base on its largest face, the assembly turned with it");
    TheBaseLiesOnItsLargestFaceAndTheAssemblyTurnsWithIt();
  }
  {
    SCOPED_TRACE("names from the file, never from the kernel");
    NamesComeFromTheFileNeverFromTheKernel();
  }
}

INSTANTIATE_TEST_SUITE_P(Files, RealExport, ::testing::ValuesIn(kVariants), label);

// Faces of one surface are one face: each product's cylinders and planes once, whatever the split.
TEST(RealExportFaces, SplitCylindersAreOneSurfaceWithTheirWholeExtent) {
  const fs::path file = vaw::test::tempDir() / "bolted-rod-faces.stp";
  vaw::steptest::writeBoltedRod(file, {4, true, true, false, false, "AP214"});
  const Assembly a = vaw::loadAny(file, vaw::test::importers());
  const vaw::CadSolid* bolt = nullptr;
  for (const auto& p : a.parts)
    if (p.product == "BOLT") bolt = p.cad.get();
  ASSERT_NE(bolt, nullptr);
  std::vector<const vaw::CadFace*> cylinders;
  for (const auto& f : bolt->faces)
    if (f.surface == vaw::CadFace::Surface::Cylinder) cylinders.push_back(&f);
  // Shank and head, whole: 30 mm and 5.5 mm along the axis, 2 pi r h of area each.
  ASSERT_EQ(cylinders.size(), 2u);
  std::sort(cylinders.begin(), cylinders.end(), [](auto* x, auto* y) { return x->radius < y->radius; });
  EXPECT_NEAR(cylinders[0]->radius, 0.004, 1e-6);
  EXPECT_NEAR(cylinders[0]->axialMax - cylinders[0]->axialMin, 0.030, 1e-6);
  EXPECT_NEAR(cylinders[0]->area, 2 * M_PI * 0.004 * 0.030, 1e-8);
  EXPECT_TRUE(cylinders[0]->fromSpline);
  EXPECT_NEAR(cylinders[1]->radius, 0.0065, 1e-6);
  EXPECT_NEAR(cylinders[1]->axialMax - cylinders[1]->axialMin, 0.0055, 1e-6);
  // The triangles of each face are contiguous and every triangle belongs to exactly one face.
  std::size_t next = 0;
  for (const auto& f : bolt->faces) {
    EXPECT_EQ(f.firstTriangle, next);
    next += f.triangleCount;
  }
  EXPECT_EQ(next, bolt->mesh.triangles.size());
}

// The merge on a solid built by hand: a cylinder in four quarter faces, two coplanar faces, one other.
TEST(RealExportFaces, MergeSplitFacesJoinsOnlyFacesOfOneSurface) {
  vaw::CadSolid s;
  s.mesh.vertices = {Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY()};
  for (int t = 0; t < 8; ++t) s.mesh.triangles.emplace_back(0, 1, 2);
  const auto cyl = [&](double axialMin, double axialMax, Eigen::Vector3d dir, std::size_t first) {
    vaw::CadFace f;
    f.surface = vaw::CadFace::Surface::Cylinder;
    f.radius = 0.01;
    f.direction = dir;
    f.axialMin = axialMin;
    f.axialMax = axialMax;
    f.area = 1.0;
    f.firstTriangle = first;
    f.triangleCount = 1;
    return f;
  };
  s.faces.push_back(cyl(0.0, 0.02, Eigen::Vector3d::UnitZ(), 0));
  vaw::CadFace plane;
  plane.surface = vaw::CadFace::Surface::Plane;
  plane.direction = Eigen::Vector3d::UnitZ();
  plane.point = Eigen::Vector3d(0, 0, 0.05);
  plane.area = 2.0;
  plane.firstTriangle = 1;
  plane.triangleCount = 1;
  s.faces.push_back(plane);
  s.faces.push_back(cyl(0.0, 0.02, Eigen::Vector3d::UnitZ(), 2));
  // Written the other way along the axis, from the other end: covers z -0.01..0.01.
  vaw::CadFace flipped = cyl(-0.01, 0.01, -Eigen::Vector3d::UnitZ(), 3);
  s.faces.push_back(flipped);
  vaw::CadFace hole = cyl(0.0, 0.02, Eigen::Vector3d::UnitZ(), 4);
  hole.convex = false;  // a bore of the same radius on the same axis is another surface
  s.faces.push_back(hole);
  vaw::CadFace plane2 = plane;
  plane2.point = Eigen::Vector3d(0.3, 0.1, 0.05);
  plane2.firstTriangle = 5;
  s.faces.push_back(plane2);
  vaw::CadFace below = plane;
  below.point.z() = 0.04;  // parallel, 10 mm lower: another plane
  below.firstTriangle = 6;
  s.faces.push_back(below);
  vaw::CadFace other;
  other.firstTriangle = 7;
  other.triangleCount = 1;
  s.faces.push_back(other);

  EXPECT_EQ(vaw::mergeSplitFaces(s), 3u);
  ASSERT_EQ(s.faces.size(), 5u);
  EXPECT_EQ(s.faces[0].surface, vaw::CadFace::Surface::Cylinder);
  EXPECT_NEAR(s.faces[0].axialMin, -0.01, 1e-12);
  EXPECT_NEAR(s.faces[0].axialMax, 0.02, 1e-12);
  EXPECT_DOUBLE_EQ(s.faces[0].area, 3.0);
  EXPECT_EQ(s.faces[0].triangleCount, 3u);
  EXPECT_EQ(s.faces[1].surface, vaw::CadFace::Surface::Plane);
  EXPECT_DOUBLE_EQ(s.faces[1].area, 4.0);
  EXPECT_EQ(s.faces[1].triangleCount, 2u);
  EXPECT_FALSE(s.faces[2].convex);
  EXPECT_EQ(s.mesh.triangles.size(), 8u);
  EXPECT_EQ(vaw::mergeSplitFaces(s), 0u);
}

// The user's choice of up wins over the automatic one, and the choice is checked.
TEST(RealExportUp, TheFilesAxisCanBeChosen) {
  const fs::path file = vaw::test::tempDir() / "bolted-rod-yup.stp";
  vaw::steptest::writeBoltedRod(file, {1, false, true, true, false, "AP214"});
  vaw::LoadOptions options;
  options.cadUp = "+z";
  const Assembly a = vaw::loadAny(file, vaw::test::importers(), options);
  EXPECT_EQ(a.cadUp, "+z");
  EXPECT_NEAR((a.cadUpAxis - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-9);
  Eigen::AlignedBox3d plate;
  for (const auto& v : a.parts[*a.base].mesh->vertices) plate.extend(a.parts[*a.base].pose * v);
  EXPECT_NEAR(plate.sizes().z(), 0.100, 1e-6);  // on its long side, as the file has it
  options.cadUp = "up";
  try {
    (void)vaw::loadAny(file, vaw::test::importers(), options);
    ADD_FAILURE() << "an unknown up choice was taken";
  } catch (const vaw::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("+y"), std::string::npos) << e.what();
  }
}

// Reopening an unchanged file (docs/step.md, "Reopening a file"): neither Open CASCADE nor the sweeps of who
// goes first run again, and the assembly is the one a fresh read gives; a kept answer that names parts the
// file does not have is swept again.
TEST(RealExportReopen, AnUnchangedFileReopensToTheSameAssemblyWithoutReadingOrSweeping) {
  const fs::path file = vaw::test::tempDir() / "bolted-rod-reopen.stp";
  vaw::steptest::writeBoltedRod(file, {4, true, true, false, false, "AP214"});
  const Assembly fresh = vaw::loadAny(file, vaw::test::importers());
  vaw::LoadOptions options;
  options.import.resultCache = vaw::test::tempDir() / "kept-reopen";
  std::vector<std::string> stages;
  const vaw::ProgressFn seeing = [&](double, const std::string& stage) {
    stages.push_back(stage);
    return true;
  };
  const auto saw = [&](const std::string& what) {
    return std::any_of(stages.begin(), stages.end(), [&](const std::string& s) { return s.find(what) != std::string::npos; });
  };
  const auto expectSame = [&](const Assembly& a) {
    ASSERT_EQ(a.parts.size(), fresh.parts.size());
    for (std::size_t i = 0; i < a.parts.size(); ++i) EXPECT_TRUE(a.parts[i].pose.isApprox(fresh.parts[i].pose, 1e-12)) << a.parts[i].name;
    ASSERT_EQ(a.constraints.size(), fresh.constraints.size());
    for (std::size_t i = 0; i < a.constraints.size(); ++i) {
      EXPECT_EQ(a.constraints[i].part, fresh.constraints[i].part) << a.constraints[i].name;
      EXPECT_EQ(a.constraints[i].partner, fresh.constraints[i].partner) << a.constraints[i].name;
      EXPECT_TRUE(a.constraints[i].homeDirection.isApprox(fresh.constraints[i].homeDirection, 1e-12)) << a.constraints[i].name;
    }
  };

  expectSame(vaw::loadAny(file, vaw::test::importers(), options, seeing));
  EXPECT_TRUE(saw("tessellating"));
  EXPECT_TRUE(std::any_of(stages.begin(), stages.end(), [](const std::string& s) {
    return s.rfind("which part goes first: ", 0) == 0 && s.find("bolt-") != std::string::npos && s.find(" and ") != std::string::npos;
  })) << "progress names the pair at hand";
  EXPECT_TRUE(saw("recognising constraints: "));

  stages.clear();
  expectSame(vaw::loadAny(file, vaw::test::importers(), options, seeing));
  EXPECT_TRUE(saw("as read before (unchanged)"));
  EXPECT_FALSE(saw("tessellating")) << "Open CASCADE read the file again";
  EXPECT_FALSE(saw("which part goes first: ")) << "who goes first was swept again";

  // A kept answer naming a part the file does not have.
  const fs::path kept = options.import.resultCache / "who-goes-first";
  std::vector<fs::path> entries;
  for (const auto& e : fs::directory_iterator(kept)) entries.push_back(e.path());
  ASSERT_EQ(entries.size(), 1u);
  const std::vector<std::uint8_t> bogus(8, 0xff);
  vaw::KeptResults(kept, 1u << 20).store(entries.front().stem().string(), bogus);
  stages.clear();
  expectSame(vaw::loadAny(file, vaw::test::importers(), options, seeing));
  EXPECT_TRUE(saw("which part goes first: "));
}

// "This face down": any face of the base, as an up choice the scene keeps; a face square to a file axis
// names the axis, any other the direction's three numbers.
TEST(RealExportUp, AFaceOfTheBaseCanBePutDown) {
  const fs::path file = vaw::test::tempDir() / "bolted-rod-facedown.stp";
  vaw::steptest::writeBoltedRod(file, {1, false, true, true, false, "AP214"});
  vaw::LoadOptions options;
  options.cadUp = "+z";
  const Assembly standing = vaw::loadAny(file, vaw::test::importers(), options);
  const PartId base = *standing.base;
  // The plate's face that faces the table while it stands (+z up) is one of its narrow sides; its broad
  // faces stand upright. Put the broad face that points along world +y down.
  const vaw::CadSolid& plate = *standing.parts[base].cad;
  std::optional<Eigen::Vector3d> broad;
  double area = 0.0;
  for (const auto& f : plate.faces) {
    const Eigen::Vector3d n = standing.parts[base].pose.linear() * f.direction;
    if (f.surface == vaw::CadFace::Surface::Plane && n.y() > 0.99 && f.area > area) {
      broad = f.direction;
      area = f.area;
    }
  }
  ASSERT_TRUE(broad.has_value());
  const auto up = vaw::upForFaceDown(standing, *broad);
  ASSERT_TRUE(up.has_value());
  EXPECT_TRUE(*up == "+y" || *up == "-y") << *up;
  options.cadUp = *up;
  const Assembly flat = vaw::loadAny(file, vaw::test::importers(), options);
  EXPECT_NEAR((flat.parts[*flat.base].pose.linear() * *broad - Eigen::Vector3d(0, 0, -1)).norm(), 0.0, 1e-9) << "that face down";

  // A direction square to no axis: three numbers, read back to the same turn.
  const Eigen::Vector3d slanted = Eigen::Vector3d(1, 2, 2).normalized();
  const auto slantedUp = vaw::upForFaceDown(standing, slanted);
  ASSERT_TRUE(slantedUp.has_value());
  EXPECT_EQ(slantedUp->find_first_of("+xyz"), std::string::npos) << *slantedUp;
  options.cadUp = *slantedUp;
  const Assembly tilted = vaw::loadAny(file, vaw::test::importers(), options);
  EXPECT_EQ(tilted.cadUp, *slantedUp);
  EXPECT_NEAR((tilted.parts[*tilted.base].pose.linear() * slanted - Eigen::Vector3d(0, 0, -1)).norm(), 0.0, 1e-7);
  EXPECT_NEAR((*vaw::upDirection(*slantedUp) - tilted.cadUpAxis).norm(), 0.0, 1e-12);

  for (const char* bad : {"0 0 0", "1 2", "nan 0 1", "1 0 0 1", "+q"}) EXPECT_FALSE(vaw::validUpChoice(bad)) << bad;
  EXPECT_NEAR((*vaw::upDirection("0 0 -2") - Eigen::Vector3d(0, 0, -1)).norm(), 0.0, 1e-15);
  Assembly scene = standing;
  scene.cadFile.clear();
  EXPECT_FALSE(vaw::upForFaceDown(scene, *broad).has_value()) << "only a CAD assembly stands another way";
}

}  // namespace

namespace {

// By hand in the world, as the window does it: a bolt before its bracket is refused; the bracket on the
// plate, then the headed bolt through it into the plate slides home and is PLACED; the base turned over,
// its nut goes onto the bolt's end against the plate.
TEST(RealExportAssembling, TheHeadedBoltGoesThroughItsBracketIntoThePlate) {
  const fs::path file = vaw::test::tempDir() / "bolted-rod-hands.stp";
  vaw::steptest::writeBoltedRod(file, {4, true, true, false, false, "AP214"});
  const Assembly a = vaw::loadAny(file, vaw::test::importers());
  vaw::test::Assembler hands(a);
  hands.carry("bolt-4", hands.above("bolt-4", 3.0));
  hands.settle();
  EXPECT_NE(hands.state("bolt-4"), vaw::interact::PartState::Placed) << hands.events("bolt-4", true);
  hands.carry("bracket-1", hands.above("bracket-1", 4.0));
  hands.settle();
  ASSERT_EQ(hands.state("bracket-1"), vaw::interact::PartState::Placed) << hands.events("bracket-1", true);
  hands.carry("bolt-1", hands.above("bolt-1", 6.0));
  hands.settle();
  EXPECT_EQ(hands.state("bolt-1"), vaw::interact::PartState::Placed) << hands.events("bolt-1", true);
  const PartId bolt = *a.findPart("bolt-1");
  EXPECT_LT((hands.world().part(bolt).pose.translation() - a.parts[bolt].finalPose->translation()).norm(), 1e-4);

  // Its nut goes on under the plate: the left hand turns the base over (and lifts it clear of the table),
  // so that the nut comes down onto the bolt's end and the plate's underside, and is PLACED.
  const Eigen::Isometry3d held = hands.world().basePose();
  Eigen::Isometry3d over = Eigen::Isometry3d::Identity();
  over.translate(Eigen::Vector3d(0, 0, 0.15));
  over.rotate(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  vaw::sim::Input turn;
  for (int i = 1; i <= 540; ++i) {
    Eigen::Isometry3d partWay = Eigen::Isometry3d::Identity();
    partWay.translate(Eigen::Vector3d(0, 0, 0.15 * i / 540.0));
    partWay.rotate(Eigen::AngleAxisd(M_PI * i / 540.0, Eigen::Vector3d::UnitX()));
    turn.base = partWay * held;
    hands.world().step(turn);
  }
  hands.settle(30);
  ASSERT_EQ(hands.state("bolt-1"), vaw::interact::PartState::Placed) << hands.events("bolt-1", true);
  const PartId nut = *a.findPart("nut-1");
  Eigen::Isometry3d nutHome = hands.world().basePose() * held.inverse() * *a.parts[nut].finalPose;
  nutHome.translation().z() += 0.006;
  nutHome.translation() += Eigen::Vector3d(0.00033, 0.00017, 0.0);
  hands.carry("nut-1", nutHome);
  nutHome.translation() -= Eigen::Vector3d(0.00033, 0.00017, 0.0);
  hands.settle();
  EXPECT_EQ(hands.state("nut-1"), vaw::interact::PartState::Placed) << hands.events("nut-1", true);
  nutHome.translation().z() -= 0.006;
  EXPECT_LT((hands.world().part(nut).pose.translation() - nutHome.translation()).norm(), 1e-4) << "on the plate's underside";
}

}  // namespace
