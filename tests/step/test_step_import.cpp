// STEP import through the plugin (libvaw_import_step.so and its reader process), on files the fixtures
// write with Open CASCADE, so every expected number is exact (step_fixtures.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <tuple>
#include <utility>
#include <vector>

#include "files.hpp"
#include "step_fixtures.hpp"
#include "vaw/error.hpp"
#include "vaw/importer.hpp"
#include "vaw/mass_properties.hpp"
#include "vaw/mesh.hpp"
#include "vaw/primitives.hpp"
#include "vaw/sim/swept_volume.hpp"

namespace {

namespace fs = std::filesystem;
using vaw::CadFace;
using vaw::CadSolid;
using vaw::ImportedMesh;
using vaw::ImportedNode;
constexpr double kPi = std::numbers::pi;
constexpr double kMm3 = 1e-9;

// The STEP plugin alone, through the registry: assimp also lists .stp and .step (its IFC reader), so a
// registry with every build plugin may not pick this one (RegistryPicksStepForStepFiles checks that).
const vaw::ImporterRegistry& stepPlugin() {
  static vaw::ImporterRegistry registry;
  static const bool loaded = [] {
    // Links, not copies: the plugin finds its reader and writer next to the path it was loaded from.
    const fs::path dir = vaw::test::tempDir() / "plugins";
    fs::create_directories(dir);
    for (const char* f : {"libvaw_import_step.so", "vaw-step-import", "vaw-step-write"})
      fs::create_symlink(fs::path(VAW_BUILD_PLUGIN_DIR) / f, dir / f);
    const auto problems = registry.loadPlugins(dir);
    EXPECT_TRUE(problems.empty()) << problems.front();
    return true;
  }();
  (void)loaded;
  return registry;
}

const vaw::MeshImporter& stepImporter() {
  static const vaw::MeshImporter* importer = stepPlugin().find("x.stp");
  if (importer == nullptr) throw std::runtime_error("the STEP plugin did not load from " VAW_BUILD_PLUGIN_DIR);
  return *importer;
}

ImportedMesh load(const fs::path& file, const vaw::ImportOptions& options = {}, const vaw::ProgressFn& progress = {}) {
  return stepImporter().read(file, options, progress);
}

struct Instance {
  std::string name;
  Eigen::Isometry3d world;
  std::shared_ptr<const CadSolid> solid;
};

void collect(const ImportedNode& n, const Eigen::Isometry3d& parent, std::vector<Instance>& out) {
  const Eigen::Isometry3d world = parent * n.location;
  if (n.solid) out.push_back({n.name, world, n.solid});
  for (const auto& c : n.children) collect(c, world, out);
}

std::map<std::string, Instance> instances(const ImportedMesh& m) {
  std::vector<Instance> list;
  collect(m.root, Eigen::Isometry3d::Identity(), list);
  std::map<std::string, Instance> out;
  for (auto& i : list) out.emplace(i.name, i);
  EXPECT_EQ(out.size(), list.size()) << "instance names are not unique";
  return out;
}

const ImportedNode* child(const ImportedNode& n, const std::string& name) {
  for (const auto& c : n.children)
    if (c.name == name) return &c;
  return nullptr;
}

// mm^3, from the fixture's exact geometry.
const std::map<std::string, double>& analyticVolumes() {
  static const std::map<std::string, double> v = {
      {"plate", 120.0 * 80 * 10 - 2 * kPi * 36 * 8 - kPi * 25 * 8},
      {"bracket", 70.0 * 34 * 8 + 70.0 * 8 * 42 - 2 * kPi * 6.5 * 6.5 * 8},
      {"stud-m12", kPi * 36 * 34},
      {"nut-m12", kPi * (100 - 36) * 8},
      {"pin", kPi * 25 * 30},
      {"sleeve", kPi * (81 - 5.2 * 5.2) * 15},
  };
  return v;
}

struct FaceCount {
  int planes = 0;
  std::vector<const CadFace*> cylinders;
  int other = 0;
  int fromSpline = 0;
};
FaceCount countFaces(const CadSolid& s) {
  FaceCount c;
  for (const auto& f : s.faces) {
    if (f.surface == CadFace::Surface::Plane) ++c.planes;
    else if (f.surface == CadFace::Surface::Cylinder) c.cylinders.push_back(&f);
    else ++c.other;
    if (f.fromSpline) ++c.fromSpline;
  }
  return c;
}

class StepImport : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(vaw::test::tempDir());
    vaw::steptest::writeBoltedBracket(file("bracket.stp"));
    bracket_ = new ImportedMesh(load(file("bracket.stp")));
  }
  static void TearDownTestSuite() {
    delete bracket_;
    delete dir_;
  }
  static fs::path file(const std::string& name) { return *dir_ / name; }
  static const ImportedMesh& bracket() { return *bracket_; }

 private:
  static fs::path* dir_;
  static ImportedMesh* bracket_;
};
fs::path* StepImport::dir_ = nullptr;
ImportedMesh* StepImport::bracket_ = nullptr;

TEST_F(StepImport, BracketHasEightNamedPartInstances) {
  const ImportedMesh& m = bracket();
  EXPECT_TRUE(m.isCad());
  EXPECT_EQ(m.format, "STEP AP214");
  ASSERT_TRUE(m.declaredUnit.has_value());
  EXPECT_EQ(*m.declaredUnit, "millimetre");
  EXPECT_TRUE(m.warnings.empty()) << m.warnings.front();
  const auto parts = instances(m);
  EXPECT_EQ(parts.size(), 8u);
  for (const char* name : {"base-plate", "bracket", "stud-1", "stud-2", "nut-1", "nut-2", "pin", "sleeve"})
    EXPECT_TRUE(parts.count(name)) << name;
}

TEST_F(StepImport, TreeKeepsTheSubAssembly) {
  const ImportedNode& root = bracket().root;
  EXPECT_EQ(root.name, "bolted-bracket");
  EXPECT_FALSE(root.solid);
  ASSERT_EQ(root.children.size(), 7u);
  const ImportedNode* pins = child(root, "pin-assembly");
  ASSERT_NE(pins, nullptr);
  EXPECT_FALSE(pins->solid);
  ASSERT_EQ(pins->children.size(), 2u);
  EXPECT_NE(child(*pins, "pin"), nullptr);
  EXPECT_NE(child(*pins, "sleeve"), nullptr);
  EXPECT_TRUE(pins->location.translation().isApprox(Eigen::Vector3d(0.105, 0.015, 0.0), 1e-12));
  EXPECT_TRUE(child(*pins, "sleeve")->location.translation().isApprox(Eigen::Vector3d(0, 0, 0.010), 1e-12));
  EXPECT_TRUE(child(root, "bracket")->location.translation().isApprox(Eigen::Vector3d(0.060, 0.040, 0.010), 1e-12));
  EXPECT_TRUE(child(root, "bracket")->location.linear().isApprox(Eigen::Matrix3d::Identity(), 1e-12));
}

TEST_F(StepImport, InstancesOfOneProductShareOneSolid) {
  const auto parts = instances(bracket());
  EXPECT_EQ(parts.at("stud-1").solid.get(), parts.at("stud-2").solid.get());
  EXPECT_EQ(parts.at("nut-1").solid.get(), parts.at("nut-2").solid.get());
  EXPECT_NE(parts.at("stud-1").solid.get(), parts.at("nut-1").solid.get());
  EXPECT_EQ(parts.at("stud-1").solid->product, "stud-m12");
  EXPECT_EQ(parts.at("nut-2").solid->product, "nut-m12");
  EXPECT_EQ(parts.at("base-plate").solid->product, "plate");
  // Placed in the world where the fixture put them.
  const Eigen::Vector3d studCentre = parts.at("stud-2").world * parts.at("stud-2").solid->centroid;
  EXPECT_TRUE(studCentre.isApprox(Eigen::Vector3d(0.080, 0.040, 0.019), 1e-12)) << studCentre.transpose();
  const Eigen::Vector3d pinCentre = parts.at("pin").world * parts.at("pin").solid->centroid;
  EXPECT_TRUE(pinCentre.isApprox(Eigen::Vector3d(0.105, 0.015, 0.017), 1e-12)) << pinCentre.transpose();
}

TEST_F(StepImport, VolumesMatchTheExactGeometry) {
  for (const auto& [name, part] : instances(bracket())) {
    const double expected = analyticVolumes().at(part.solid->product) * kMm3;
    EXPECT_NEAR(part.solid->volume, expected, 1e-6 * expected) << name;
  }
}

TEST_F(StepImport, MeshIsClosedAndAgreesWithTheBrep) {
  for (const auto& [name, part] : instances(bracket())) {
    const CadSolid& s = *part.solid;
    vaw::TriMesh mesh = s.mesh;
    vaw::weldVertices(mesh, 1e-9);
    const vaw::MeshCheck check = vaw::checkMesh(mesh);
    EXPECT_TRUE(check.valid()) << name << ": " << check.summary();
    std::size_t covered = 0;
    for (const auto& f : s.faces) {
      EXPECT_EQ(f.firstTriangle, covered) << name;
      covered += f.triangleCount;
    }
    EXPECT_EQ(covered, s.mesh.triangleCount()) << name;
    EXPECT_GT(s.deflection, 0.0);
    const vaw::VolumeIntegrals mi = vaw::integrateVolume(mesh);
    // The tessellation is inside the true surface by at most the deflection: close, not equal.
    EXPECT_NEAR(mi.volume, s.volume, 0.02 * s.volume) << name;
    EXPECT_NEAR(mi.surfaceArea, s.surfaceArea, 0.02 * s.surfaceArea) << name;
    EXPECT_LT((mi.centroid - s.centroid).norm(), 1e-4) << name;
    // Same convention as vaw's own integrals (products of inertia included).
    EXPECT_LT((mi.inertiaUnitDensity - s.inertiaUnitDensity).norm(), 0.03 * s.inertiaUnitDensity.norm()) << name;
  }
}

TEST_F(StepImport, FacesAreRecognised) {
  const auto parts = instances(bracket());
  const FaceCount stud = countFaces(*parts.at("stud-1").solid);
  EXPECT_EQ(stud.planes, 2);
  EXPECT_EQ(stud.other, 0);
  ASSERT_EQ(stud.cylinders.size(), 1u);
  EXPECT_TRUE(stud.cylinders[0]->convex);
  EXPECT_NEAR(stud.cylinders[0]->radius, 0.006, 1e-12);
  EXPECT_NEAR(std::abs(stud.cylinders[0]->direction.z()), 1.0, 1e-12);
  EXPECT_NEAR(stud.cylinders[0]->axialMax - stud.cylinders[0]->axialMin, 0.034, 1e-9);
  EXPECT_NEAR(stud.cylinders[0]->area, 2 * kPi * 6 * 34 * 1e-6, 1e-12);

  const FaceCount plate = countFaces(*parts.at("base-plate").solid);
  EXPECT_EQ(plate.cylinders.size(), 3u);
  for (const CadFace* c : plate.cylinders) {
    EXPECT_FALSE(c->convex) << "a drilled hole is concave";
    EXPECT_NEAR(c->axialMax - c->axialMin, 0.008, 1e-9);
  }
  // Plane normals point out of the material: the plate's top face up, its bottom face down.
  int up = 0, down = 0;
  for (const auto& f : parts.at("base-plate").solid->faces) {
    if (f.surface != CadFace::Surface::Plane) continue;
    if (std::abs(f.point.z() - 0.010) < 1e-12 && f.direction.z() > 0.999) ++up;
    if (std::abs(f.point.z()) < 1e-12 && f.direction.z() < -0.999) ++down;
  }
  EXPECT_EQ(up, 1);
  EXPECT_EQ(down, 1);
}

TEST_F(StepImport, ColoursComeFromTheFile) {
  const auto parts = instances(bracket());
  ASSERT_TRUE(parts.at("base-plate").solid->color.has_value());
  EXPECT_TRUE(parts.at("base-plate").solid->color->isApprox(Eigen::Vector3f(0.6f, 0.6f, 0.62f), 1e-3f));
  ASSERT_TRUE(parts.at("bracket").solid->color.has_value());
  EXPECT_TRUE(parts.at("bracket").solid->color->isApprox(Eigen::Vector3f(0.2f, 0.35f, 0.8f), 1e-3f));
}

TEST_F(StepImport, BsplineFacesKeepVolumesAndAreRecognised) {
  vaw::steptest::writeBoltedBracket(file("bspline.stp"), {.bsplineFaces = true});
  const ImportedMesh m = load(file("bspline.stp"));
  const auto parts = instances(m);
  ASSERT_EQ(parts.size(), 8u);
  for (const auto& [name, part] : parts) {
    const double expected = analyticVolumes().at(part.solid->product) * kMm3;
    EXPECT_NEAR(part.solid->volume, expected, 1e-6 * expected) << name;
  }
  const FaceCount stud = countFaces(*parts.at("stud-1").solid);
  EXPECT_EQ(stud.planes, 2);
  EXPECT_EQ(stud.fromSpline, 3);
  ASSERT_EQ(stud.cylinders.size(), 1u);
  EXPECT_TRUE(stud.cylinders[0]->convex);
  EXPECT_NEAR(stud.cylinders[0]->radius, 0.006, 1e-9);
  EXPECT_NEAR(stud.cylinders[0]->axialMax - stud.cylinders[0]->axialMin, 0.034, 1e-7);

  const FaceCount nut = countFaces(*parts.at("nut-1").solid);
  EXPECT_EQ(nut.planes, 2);
  EXPECT_EQ(nut.other, 0);
  ASSERT_EQ(nut.cylinders.size(), 2u);
  const CadFace* outer = nut.cylinders[0]->radius > nut.cylinders[1]->radius ? nut.cylinders[0] : nut.cylinders[1];
  const CadFace* inner = outer == nut.cylinders[0] ? nut.cylinders[1] : nut.cylinders[0];
  EXPECT_TRUE(outer->convex);
  EXPECT_NEAR(outer->radius, 0.010, 1e-9);
  EXPECT_FALSE(inner->convex);
  EXPECT_NEAR(inner->radius, 0.006, 1e-9);
  // The axis where the analytic file has it.
  const Eigen::Vector3d d = inner->direction;
  const Eigen::Vector3d offAxis = inner->point - inner->point.dot(d) * d;
  EXPECT_LT(offAxis.norm(), 1e-9);
  EXPECT_NEAR(std::abs(d.z()), 1.0, 1e-9);
}

TEST_F(StepImport, InchFileGivesTheSameMetres) {
  vaw::steptest::writeBoltedBracket(file("inch.stp"), {.inches = true});
  const ImportedMesh m = load(file("inch.stp"));
  ASSERT_TRUE(m.declaredUnit.has_value());
  EXPECT_EQ(*m.declaredUnit, "inch");
  const auto mm = instances(bracket());
  const auto inch = instances(m);
  ASSERT_EQ(inch.size(), mm.size());
  for (const auto& [name, a] : mm) {
    const Instance& b = inch.at(name);
    EXPECT_NEAR(b.solid->volume, a.solid->volume, 1e-9 * a.solid->volume) << name;
    // 1e-9 of the part's size, as a centroid may be near 0.
    EXPECT_LT((b.solid->centroid - a.solid->centroid).norm(), 1e-9 * 0.15) << name;
    EXPECT_LT((b.world.translation() - a.world.translation()).norm(), 1e-9 * 0.15) << name;
    EXPECT_NEAR(b.solid->inertiaUnitDensity.norm(), a.solid->inertiaUnitDensity.norm(), 1e-9 * a.solid->inertiaUnitDensity.norm())
        << name;
  }
}

TEST_F(StepImport, AllThreeSchemasLoad) {
  for (const std::string schema : {"AP203", "AP214", "AP242"}) {
    const fs::path f = file("schema-" + schema + ".stp");
    vaw::steptest::writeBoltedBracket(f, {.schema = schema});
    const ImportedMesh m = load(f);
    EXPECT_EQ(m.format, "STEP " + schema);
    const auto parts = instances(m);
    EXPECT_EQ(parts.size(), 8u) << schema;
    for (const auto& [name, part] : parts) {
      const double expected = analyticVolumes().at(part.solid->product) * kMm3;
      EXPECT_NEAR(part.solid->volume, expected, 1e-6 * expected) << schema << " " << name;
    }
  }
}

TEST_F(StepImport, WireframeAndEmptyProductsAreSkippedWithAWarning) {
  vaw::steptest::writeBoltedBracket(file("wire.stp"), {.wireframeBeside = true});
  const ImportedMesh m = load(file("wire.stp"));
  EXPECT_EQ(instances(m).size(), 8u);
  EXPECT_EQ(child(m.root, "construction-lines"), nullptr);
  EXPECT_EQ(child(m.root, "empty-rep"), nullptr);
  std::string all;
  for (const auto& w : m.warnings) all += w + "\n";
  EXPECT_NE(all.find("\"construction-lines\": skipped, no solid"), std::string::npos) << all;
  EXPECT_NE(all.find("\"empty-rep\""), std::string::npos) << all;
}

TEST_F(StepImport, EdgeTouchingBoxesLoad) {
  vaw::steptest::writeEdgeTouchingBoxes(file("edge.stp"));
  const auto parts = instances(load(file("edge.stp")));
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_NEAR(parts.at("box-a").solid->volume, 8e-6, 1e-15);
  EXPECT_NEAR((parts.at("box-b").world.translation() - parts.at("box-a").world.translation()).norm(), 0.02 * std::sqrt(2.0),
              1e-12);
}

TEST_F(StepImport, ProgressIsReported) {
  std::vector<std::pair<double, std::string>> seen;
  (void)load(file("bracket.stp"), {}, [&](double f, const std::string& stage) {
    seen.emplace_back(f, stage);
    return true;
  });
  ASSERT_FALSE(seen.empty());
  bool tessellatingBracket = false;
  for (std::size_t i = 0; i < seen.size(); ++i) {
    if (i > 0) {
      EXPECT_GE(seen[i].first, seen[i - 1].first);
    }
    tessellatingBracket = tessellatingBracket || seen[i].second == "tessellating bracket";
  }
  EXPECT_TRUE(tessellatingBracket);
  EXPECT_DOUBLE_EQ(seen.back().first, 1.0);
}

// ---------------------------------------------------------------------------------------------------
// Bad input: always an InputError naming the file, never a crash.

std::string readAll(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void expectInputError(const fs::path& f, const std::string& says, const vaw::ImportOptions& options = {}) {
  try {
    (void)load(f, options);
    ADD_FAILURE() << f << " loaded";
  } catch (const vaw::InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(f.string()), std::string::npos) << what;
    EXPECT_EQ(e.diagnostic().file, f.string());
    EXPECT_NE(what.find(says), std::string::npos) << what;
  }
}

TEST_F(StepImport, MissingFile) { expectInputError(file("no-such-file.stp"), "no such file"); }

TEST_F(StepImport, TextFileThatIsNotStep) {
  expectInputError(vaw::test::writeFile(file("notes.stp"), "just some notes\nnot a model\n"), "not a STEP file");
}

TEST_F(StepImport, TruncatedInTheDataSection) {
  const std::string text = readAll(file("bracket.stp"));
  const std::size_t data = text.find("DATA;");
  ASSERT_NE(data, std::string::npos);
  const fs::path f = vaw::test::writeFile(file("truncated.stp"), text.substr(0, data + (text.size() - data) / 2));
  expectInputError(f, "truncated");
}

TEST_F(StepImport, Ifc4SchemaIsRefusedByName) {
  std::string text = readAll(file("bracket.stp"));
  const std::size_t at = text.find("FILE_SCHEMA");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, text.find(';', at) - at, "FILE_SCHEMA(('IFC4'))");
  expectInputError(vaw::test::writeFile(file("ifc4.stp"), text), "unsupported schema \"IFC4\"");
}

// Valid Part 21 that Open CASCADE 7.6.3 dies on (SIGSEGV): a comment or a line break between "#12" and
// "=". The first pass rewrites both spellings in a private copy, so the file loads with all its parts.
TEST_F(StepImport, CommentOrLineBreakBeforeTheEqualsSignLoads) {
  const std::string text = readAll(file("bracket.stp"));
  for (const char* spelling : {"\n#12 /* a comment */ = ", "\n#12\n= "}) {
    std::string changed = text;
    const std::size_t at = changed.find("\n#12 = ");
    ASSERT_NE(at, std::string::npos);
    changed.replace(at, 7, spelling);
    const fs::path f = vaw::test::writeFile(file("spelling.stp"), changed);
    const auto parts = instances(load(f));
    EXPECT_EQ(parts.size(), 8u) << spelling;
    EXPECT_EQ(readAll(f), changed) << "the user's file is never written";
  }
}

// What Open CASCADE would spend minutes on is refused by the first pass, in well under a second, with the
// entity named.
TEST_F(StepImport, NonFiniteHugeAndInstanceBombFilesAreRefusedAtOnce) {
  const std::string text = readAll(file("bracket.stp"));
  const std::size_t point = text.find("CARTESIAN_POINT('',(");
  ASSERT_NE(point, std::string::npos);
  const std::size_t id = text.rfind("\n#", point) + 1;
  const std::string entity = text.substr(id, text.find(' ', id) - id) + " CARTESIAN_POINT";
  const std::size_t value = point + std::string("CARTESIAN_POINT('',(").size();
  const std::size_t valueEnd = text.find(',', value);
  std::string nan = text, huge = text;
  nan.replace(value, valueEnd - value, "nan");
  huge.replace(value, valueEnd - value, "1.E308");

  // The bracket's first NEXT_ASSEMBLY_USAGE_OCCURRENCE 20,000 times over.
  const std::string bomb = vaw::steptest::withMoreUses(text, 20000);

  for (const auto& [name, content, says] :
       {std::tuple<std::string, std::string, std::string>{"nan.stp", nan, entity + ": expected finite numbers"},
        {"huge.stp", huge, entity + ": expected coordinates within"},
        {"bomb.stp", bomb, "found an assembly of 20008 part instances, 20001 of them of \"plate\""}}) {
    const auto start = std::chrono::steady_clock::now();
    expectInputError(vaw::test::writeFile(file(name), content), says);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0) << name;
  }
  // The limit is the caller's: the bracket's 8 instances are too many for a limit of 5.
  vaw::ImportOptions few;
  few.maxInstances = 5;
  expectInputError(file("bracket.stp"), "expected at most 5 part instances", few);
}

TEST_F(StepImport, CancelStopsQuickly) {
  for (const int stopAt : {1, 3}) {
    int calls = 0;
    const auto start = std::chrono::steady_clock::now();
    EXPECT_THROW((void)load(file("bracket.stp"), {}, [&](double, const std::string&) { return ++calls < stopAt; }),
                 vaw::LoadCancelled);
    EXPECT_EQ(calls, stopAt);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 2.0);
  }
}

TEST_F(StepImport, TimeLimitEndsASlowRead) {
  // About 0.2 s to read here, four times the limit.
  vaw::steptest::writeManyParts(file("many.stp"), 1000);
  vaw::ImportOptions options;
  options.timeoutSeconds = 0.05;
  const auto start = std::chrono::steady_clock::now();
  expectInputError(file("many.stp"), "still reading after 0.05 s", options);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 2.0);
}

TEST_F(StepImport, ManyPartsLoadWithinTheDefaultLimit) {
  vaw::steptest::writeManyParts(file("many-ok.stp"), 60);
  const auto parts = instances(load(file("many-ok.stp")));
  EXPECT_EQ(parts.size(), 60u);
}

// ---------------------------------------------------------------------------------------------------
// Reads kept for reopening (docs/step.md, "Reopening a file").

struct Seen {
  std::vector<std::string> stages;
  [[nodiscard]] bool has(const std::string& part) const {
    return std::any_of(stages.begin(), stages.end(), [&](const std::string& s) { return s.find(part) != std::string::npos; });
  }
};

ImportedMesh loadSeeing(const fs::path& f, const vaw::ImportOptions& options, Seen& seen) {
  seen = {};
  return load(f, options, [&](double, const std::string& stage) {
    seen.stages.push_back(stage);
    return true;
  });
}

std::vector<fs::path> keptEntries(const fs::path& cache) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(cache / "step-results", ec))
    if (e.path().extension() == ".vawkept") out.push_back(e.path());
  return out;
}

void expectSameAssembly(const ImportedMesh& a, const ImportedMesh& b) {
  const auto x = instances(a), y = instances(b);
  ASSERT_EQ(x.size(), y.size());
  for (const auto& [name, i] : x) {
    const auto j = y.find(name);
    ASSERT_NE(j, y.end()) << name;
    EXPECT_TRUE(i.world.isApprox(j->second.world, 0.0)) << name;
    EXPECT_EQ(i.solid->volume, j->second.solid->volume) << name;
    EXPECT_EQ(i.solid->mesh.vertices, j->second.solid->mesh.vertices) << name;
    EXPECT_EQ(i.solid->mesh.triangles, j->second.solid->mesh.triangles) << name;
    EXPECT_EQ(i.solid->faces.size(), j->second.solid->faces.size()) << name;
  }
  EXPECT_EQ(a.format, b.format);
  EXPECT_EQ(a.declaredUnit, b.declaredUnit);
}

TEST_F(StepImport, AnUnchangedFileReopensWithoutBeingReadAgain) {
  const fs::path f = file("kept.stp");
  fs::copy_file(file("bracket.stp"), f);
  vaw::ImportOptions options;
  options.resultCache = file("cache-unchanged");
  Seen seen;
  const ImportedMesh first = loadSeeing(f, options, seen);
  EXPECT_TRUE(seen.has("tessellating bracket"));
  ASSERT_EQ(keptEntries(options.resultCache).size(), 1u);

  const ImportedMesh again = loadSeeing(f, options, seen);
  EXPECT_TRUE(seen.has("as read before (unchanged)"));
  EXPECT_FALSE(seen.has("tessellating")) << "Open CASCADE read the file again";
  expectSameAssembly(first, again);
  expectSameAssembly(bracket(), again);

  // Cancel is honoured on a kept read too.
  int calls = 0;
  EXPECT_THROW((void)load(f, options, [&](double, const std::string&) { return ++calls < 2; }), vaw::LoadCancelled);

  // One byte more (a line break after the end) is another file; a finer tessellation another read.
  {
    std::ofstream(f, std::ios::app) << "\n";
  }
  (void)loadSeeing(f, options, seen);
  EXPECT_TRUE(seen.has("tessellating bracket"));
  options.relativeDeflection = 0.0005;
  (void)loadSeeing(f, options, seen);
  EXPECT_TRUE(seen.has("tessellating bracket"));
  EXPECT_EQ(keptEntries(options.resultCache).size(), 3u);
  // Without a folder nothing is kept or looked up.
  (void)loadSeeing(f, vaw::ImportOptions{}, seen);
  EXPECT_TRUE(seen.has("tessellating bracket"));
}

// A cache folder that cannot be made: the file opens all the same, with a warning that it is not kept.
TEST_F(StepImport, AnUnwritableCacheFolderOpensTheFileWithAWarning) {
  vaw::ImportOptions options;
  options.resultCache = file("bracket.stp") / "cache";  // under a file: no folder can be made there
  const ImportedMesh m = load(file("bracket.stp"), options);
  expectSameAssembly(bracket(), m);
  EXPECT_TRUE(std::any_of(m.warnings.begin(), m.warnings.end(),
                          [](const std::string& w) { return w.find("not kept for reopening without reading again") != std::string::npos; }))
      << (m.warnings.empty() ? std::string("no warnings") : m.warnings.front());
}

TEST_F(StepImport, ADamagedOrHalfWrittenKeptReadIsReadAfresh) {
  vaw::ImportOptions options;
  options.resultCache = file("cache-damaged");
  Seen seen;
  (void)loadSeeing(file("bracket.stp"), options, seen);
  const auto entries = keptEntries(options.resultCache);
  ASSERT_EQ(entries.size(), 1u);
  const std::string whole = readAll(entries.front());

  const auto damagedThenRead = [&](const std::string& content, const char* what) {
    std::ofstream(entries.front(), std::ios::binary | std::ios::trunc) << content;
    const ImportedMesh m = loadSeeing(file("bracket.stp"), options, seen);
    EXPECT_TRUE(seen.has("tessellating bracket")) << what << ": a damaged entry was used";
    expectSameAssembly(bracket(), m);
    EXPECT_EQ(readAll(entries.front()), whole) << what << ": the entry is written whole again";
  };
  damagedThenRead(whole.substr(0, whole.size() / 2), "cut in half");
  std::string flipped = whole;
  flipped[flipped.size() - 10] = static_cast<char>(flipped[flipped.size() - 10] ^ 0x5a);
  damagedThenRead(flipped, "one byte changed");
  damagedThenRead("", "empty");

  // A writer killed before its rename leaves a hidden temporary file: never read, removed once old.
  const fs::path stray = options.resultCache / "step-results" / ".0123456789abcdef.vawkept.AbCdEf.tmp";
  std::ofstream(stray) << "half";
  fs::last_write_time(stray, fs::file_time_type::clock::now() - std::chrono::hours(2));
  (void)loadSeeing(file("bracket.stp"), options, seen);
  EXPECT_TRUE(seen.has("as read before"));
  vaw::steptest::writeManyParts(file("many-kept.stp"), 20);
  (void)loadSeeing(file("many-kept.stp"), options, seen);
  EXPECT_FALSE(fs::exists(stray));
}

TEST_F(StepImport, KeptReadsStayUnderTheSizeLimitLeastRecentlyUsedFirstOut) {
  vaw::ImportOptions options;
  options.resultCache = file("cache-limit");
  Seen seen;
  // Three files of nearly one size (20, 21 and 22 boxes).
  for (int n : {20, 21, 22}) vaw::steptest::writeManyParts(file("many-" + std::to_string(n) + ".stp"), n);
  (void)loadSeeing(file("many-20.stp"), options, seen);
  const auto one = keptEntries(options.resultCache);
  ASSERT_EQ(one.size(), 1u);
  const double entryMB = static_cast<double>(fs::file_size(one.front())) / 1048576.0;
  (void)loadSeeing(file("many-21.stp"), options, seen);
  // Used again: 21 is now the least recently used, though 20 was kept first.
  (void)loadSeeing(file("many-20.stp"), options, seen);
  EXPECT_TRUE(seen.has("as read before"));
  // Room for two entries, not three.
  options.resultCacheMB = 2.5 * entryMB;
  (void)loadSeeing(file("many-22.stp"), options, seen);
  EXPECT_EQ(keptEntries(options.resultCache).size(), 2u);
  (void)loadSeeing(file("many-20.stp"), options, seen);
  EXPECT_TRUE(seen.has("as read before"));
  (void)loadSeeing(file("many-22.stp"), options, seen);
  EXPECT_TRUE(seen.has("as read before"));
  (void)loadSeeing(file("many-21.stp"), options, seen);
  EXPECT_TRUE(seen.has("tessellating")) << "the least recently used entry went";
  // No room: nothing kept.
  options.resultCacheMB = 0.0;
  (void)loadSeeing(file("bracket.stp"), options, seen);
  (void)loadSeeing(file("bracket.stp"), options, seen);
  EXPECT_TRUE(seen.has("tessellating"));
}

// A swept volume (docs/swept-volume.md) written as a STEP solid through the plugin's writer reads back
// through its reader (Open CASCADE's) as one named solid with the voxels' volume, in place, in millimetres
// and in inches.
TEST(StepExport, ASweptVolumeWrittenAsAStepSolidReadsBackWithItsVolume) {
  const vaw::TriMesh ball = vaw::primitives::sphere(0.005, 32, 16);
  Eigen::Isometry3d a = Eigen::Isometry3d::Identity(), b = a, c = a;
  a.translation() = Eigen::Vector3d(0.010, 0.020, 0.030);
  b.translation() = Eigen::Vector3d(0.050, 0.020, 0.030);
  c.translation() = Eigen::Vector3d(0.050, 0.060, 0.040);
  const vaw::SweptVolume sv = vaw::sweep(ball, {{a, b, c}}, 0.001);
  const vaw::SolidExporter* writer = stepPlugin().exporterFor("swept.STEP");
  ASSERT_NE(writer, nullptr);
  EXPECT_EQ(stepPlugin().exporterFor("swept.stl"), nullptr);
  std::uintmax_t advancedSize = 0;
  for (const auto unit : {vaw::LengthUnit::Millimetre, vaw::LengthUnit::Inch}) for (const bool faceted : {false, true}) {
    SCOPED_TRACE(std::string(vaw::name(unit)) + (faceted ? ", faceted" : ", advanced"));
    const fs::path out = vaw::test::tempDir() / ("swept-" + std::string(vaw::name(unit)) + (faceted ? "-faceted" : "") + ".step");
    // A name with a quote and a letter beyond ASCII, which Part 21 writes escaped.
    vaw::ExportOptions form;
    form.faceted = faceted;
    writer->write(sv.mesh, "ball's Bügel swept", unit, out, form, {});
    const std::string text = readAll(out);
    EXPECT_EQ(text.find("=EDGE_CURVE(") == std::string::npos, faceted);
    EXPECT_EQ(text.find("=FACETED_BREP(") != std::string::npos, faceted);
    EXPECT_EQ(text.find("=MANIFOLD_SOLID_BREP(") != std::string::npos, !faceted);
    if (!faceted) advancedSize = text.size();
    else EXPECT_LT(text.size(), advancedSize / 2);
    const ImportedMesh back = load(out);
    EXPECT_EQ(back.declaredUnit, unit == vaw::LengthUnit::Inch ? std::optional<std::string>("inch") : std::optional<std::string>("millimetre"));
    const auto all = instances(back);
    ASSERT_EQ(all.size(), 1U);
    const Instance& solid = all.begin()->second;
    EXPECT_EQ(solid.solid->product, "ball's Bügel swept");
    EXPECT_NEAR(solid.solid->volume, sv.volume, 1e-6 * sv.volume);
    const Eigen::AlignedBox3d box = solid.solid->mesh.bounds(), expected = sv.mesh.bounds();
    EXPECT_NEAR((solid.world * box.min() - expected.min()).norm(), 0.0, 1e-6);
    EXPECT_NEAR((solid.world * box.max() - expected.max()).norm(), 0.0, 1e-6);
  }
  // A folder that is not there: refused, naming the file.
  try {
    writer->write(sv.mesh, "ball swept", vaw::LengthUnit::Millimetre, vaw::test::tempDir() / "no-such-folder" / "swept.step", {}, {});
    FAIL() << "written into a folder that does not exist";
  } catch (const vaw::OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("no-such-folder/swept.step"), std::string::npos) << e.what();
  }
}

// The writer runs as the reader does: its stages reach the caller in order, a caller that stops it or a
// time limit passed ends it with the reason, and the file that was there stays as it was.
TEST(StepExport, TheWriterIsHeardStoppedAndTimedOutLeavingTheFileAsItWas) {
  const vaw::TriMesh ball = vaw::primitives::sphere(0.005, 32, 16);
  Eigen::Isometry3d a = Eigen::Isometry3d::Identity(), b = a;
  b.translation() = Eigen::Vector3d(0.040, 0.0, 0.0);
  const vaw::SweptVolume sv = vaw::sweep(ball, {{a, b}}, 0.001);
  const vaw::SolidExporter* writer = stepPlugin().exporterFor("swept.step");
  ASSERT_NE(writer, nullptr);
  const fs::path out = vaw::test::tempDir() / "swept-heard.step";

  std::vector<std::pair<double, std::string>> heard;
  writer->write(sv.mesh, "ball swept", vaw::LengthUnit::Millimetre, out, {}, [&](double f, const std::string& stage) {
    heard.emplace_back(f, stage);
    return true;
  });
  ASSERT_TRUE(fs::exists(out));
  const auto said = [&](const std::string& what) {
    return std::any_of(heard.begin(), heard.end(), [&](const auto& h) { return h.second.find(what) != std::string::npos; });
  };
  EXPECT_TRUE(said("merging coplanar triangles"));
  EXPECT_TRUE(said("writing the file"));
  for (std::size_t i = 1; i < heard.size(); ++i) EXPECT_GE(heard[i].first, heard[i - 1].first) << heard[i].second;
  const auto before = fs::file_size(out);
  const auto written = fs::last_write_time(out);

  // Stopped at its first word: refused with why, the file as it was, nothing half-written beside it.
  try {
    writer->write(sv.mesh, "ball swept", vaw::LengthUnit::Millimetre, out, {}, [](double, const std::string&) { return false; });
    FAIL() << "a stopped write went on";
  } catch (const vaw::OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("not written: stopped while"), std::string::npos) << e.what();
  }
  // Past its time limit: a mesh of 260,000 triangles with no two coplanar (a face each), which takes the
  // writer far longer than the limit.
  vaw::ExportOptions quick;
  quick.timeoutSeconds = 0.01;
  try {
    writer->write(vaw::primitives::sphere(0.005, 512, 256), "fine ball", vaw::LengthUnit::Millimetre, out, quick, {});
    FAIL() << "a write past its time limit went on";
  } catch (const vaw::OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("still writing after 0.01 s"), std::string::npos) << e.what();
  }
  EXPECT_EQ(fs::file_size(out), before);
  EXPECT_EQ(fs::last_write_time(out), written);
  for (const auto& entry : fs::directory_iterator(out.parent_path()))
    EXPECT_EQ(entry.path().filename().string().find(".writing"), std::string::npos) << entry.path();
}

// With every build plugin loaded, a .stp file must go to this plugin, not to assimp's IFC reader.
TEST(StepRegistry, RegistryPicksStepForStepFiles) {
  vaw::ImporterRegistry registry;
  const auto problems = registry.loadPlugins(VAW_BUILD_PLUGIN_DIR);
  EXPECT_TRUE(problems.empty()) << problems.front();
  for (const char* f : {"a.stp", "a.STEP", "a.p21"}) {
    const vaw::MeshImporter* imp = registry.find(f);
    ASSERT_NE(imp, nullptr) << f;
    EXPECT_EQ(imp->name(), "Open CASCADE STEP") << f;
  }
}

}  // namespace
