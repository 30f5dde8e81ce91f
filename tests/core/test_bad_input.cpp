// Every kind of bad input gets an InputError naming the file, the field and what was expected;
// nothing crashes and nothing is half-loaded.
#include <gtest/gtest.h>

#include <functional>
#include <nlohmann/json.hpp>

#include "test_support.hpp"
#include "vaw/limits.hpp"
#include "vaw/primitives.hpp"
#include "vaw/property_file.hpp"
#include "vaw/scene_loader.hpp"

using namespace vaw;
using nlohmann::json;

namespace {

json validScene() {
  return json::parse(R"({
    "format": "vaw-scene", "version": 1, "name": "probe", "units": "mm",
    "materials": {"steel": {"density": 7850, "friction": {"static": 0.3, "kinetic": 0.2, "rotational": 0.0005}}},
    "parts": [
      {"name": "base", "primitive": {"type": "box", "size": [100, 100, 20]}, "material": "steel"},
      {"name": "pin", "mesh": "pin.stl", "material": "steel", "pose": {"position": [0, 0, 200]},
       "final_pose": {"position": [0, 0, 25]}}
    ],
    "base": "base",
    "environment": [{"name": "table", "kind": "table", "primitive": {"type": "box", "size": [1000, 1000, 40]},
                     "pose": {"position": [0, 0, -30]}}],
    "constraints": [{"type": "insert", "part": "pin", "part_axis": {"point": [0, 0, 0], "direction": [0, 0, 1]},
                     "base_axis": {"point": [0, 0, 0], "direction": [0, 0, 1]}}]
  })");
}

json validProperties() {
  return json::parse(R"({
    "format": "vaw-properties", "version": 1, "units": {"length": "mm", "mass": "g"},
    "mass": 18.5, "center_of_mass": [0, 0, 0],
    "inertia_cm": [[1.5, 0, 0], [0, 1.5, 0], [0, 0, 0.23]]
  })");
}

TriMesh pinMesh() { return primitives::cylinder(5, 30, 24); }

struct Case {
  std::string name;
  std::function<std::filesystem::path(const std::filesystem::path& dir)> setup;  // returns the scene path
  std::string field;     // substring of Diagnostic::field
  std::string expected;  // substring of Diagnostic::expected
  std::string fileEnds;  // the file the error must name (its ending)
};

std::filesystem::path writeScene(const std::filesystem::path& dir, const json& scene, const TriMesh& pin = pinMesh()) {
  test::writeFile(dir / "pin.stl", test::asciiStl(pin));
  return test::writeFile(dir / "scene.vaw.json", scene.dump(2));
}

Case edit(std::string name, std::function<void(json&)> change, std::string field, std::string expected,
          std::string fileEnds = "scene.vaw.json") {
  return {std::move(name),
          [change](const std::filesystem::path& dir) {
            json s = validScene();
            change(s);
            return writeScene(dir, s);
          },
          std::move(field), std::move(expected), std::move(fileEnds)};
}

Case properties(std::string name, std::function<void(json&)> change, std::string field, std::string expected) {
  return {std::move(name),
          [change](const std::filesystem::path& dir) {
            json p = validProperties();
            change(p);
            test::writeFile(dir / "pin.props.json", p.dump(2));
            json s = validScene();
            s["parts"][1]["properties"] = "pin.props.json";
            return writeScene(dir, s);
          },
          std::move(field), std::move(expected), "pin.props.json"};
}

Case mesh(std::string name, std::function<void(TriMesh&)> change, std::string field, std::string expected) {
  return {std::move(name),
          [change](const std::filesystem::path& dir) {
            TriMesh m = pinMesh();
            change(m);
            return writeScene(dir, validScene(), m);
          },
          std::move(field), std::move(expected), "pin.stl"};
}

Case raw(std::string name, std::string text, std::string field, std::string expected) {
  return {std::move(name),
          [text](const std::filesystem::path& dir) { return test::writeFile(dir / "scene.vaw.json", text); },
          std::move(field), std::move(expected), "scene.vaw.json"};
}

std::vector<Case> cases() {
  return {
      raw("MalformedJson", "{\"format\": \"vaw-scene\",\n  \"version\": 1,\n  \"name\": \"x\"\n  \"units\": \"mm\"}",
          "line 4", "valid JSON"),
      raw("NaNLiteral", "{\"format\": \"vaw-scene\", \"version\": NaN}", "line 1", "valid JSON"),
      raw("TopLevelNotObject", "[1, 2, 3]", "(top level)", "an object"),
      edit("WrongFormat", [](json& s) { s["format"] = "stl"; }, "format", "\"vaw-scene\""),
      edit("FutureVersion", [](json& s) { s["version"] = 4; }, "version", "version 1 to 3"),
      edit("ToolsNeedVersion2", [](json& s) { s["tools"] = json::array(); }, "tools", "one of the keys"),
      edit("HoistTravelUpsideDown", [](json& s) {
             s["version"] = 2;
             s["tools"] = {{{"type", "hoist"}, {"position", {0, 0}}, {"travel", {500, 100}}}};
           }, "tools[0].travel[1]", "a height above the lowest"),
      edit("UnknownUnits", [](json& s) { s["units"] = "furlong"; }, "units", "a length unit"),
      edit("UnknownMassUnit", [](json& s) { s["units"] = {{"length", "mm"}, {"mass", "stone"}}; }, "units.mass", "a mass unit"),
      edit("MissingMeshFile", [](json& s) { s["parts"][1]["mesh"] = "nowhere.stl"; }, "parts[1].mesh", "an existing, readable mesh file"),
      edit("UnknownMeshFormat", [](json& s) { s["parts"][1]["mesh"] = "scene.vaw.json"; }, "parts[1].mesh",
           "a mesh format an importer plugin reads"),
      edit("ZeroDensity", [](json& s) { s["materials"]["steel"]["density"] = 0; }, "materials.steel.density", "a density from 0.1 to 100000 kg/m^3"),
      edit("NegativeDensity", [](json& s) { s["parts"][1]["density"] = -7850; }, "parts[1].density", "a density from 0.1 to 100000 kg/m^3"),
      edit("UnknownDensityUnit", [](json& s) { s["parts"][1]["density"] = "7.8 kg/l"; }, "parts[1].density", "known unit"),
      {"InfiniteNumber",
       [](const std::filesystem::path& dir) {
         json s = validScene();
         s["parts"][1]["pose"]["position"][2] = "INFINITY";
         std::string text = s.dump(2);
         text.replace(text.find("\"INFINITY\""), 10, "1e999");  // JSON has no literal for infinity
         test::writeFile(dir / "pin.stl", test::asciiStl(pinMesh()));
         return test::writeFile(dir / "scene.vaw.json", text);
       },
       "numbers", "finite numbers", "scene.vaw.json"},
      edit("ZeroAxis", [](json& s) { s["constraints"][0]["part_axis"]["direction"] = {0, 0, 0}; },
           "constraints[0].part_axis.direction", "non-zero direction"),
      edit("ConstraintOnMissingPart", [](json& s) { s["constraints"][0]["part"] = "ghost"; }, "constraints[0].part",
           "the name of a part"),
      edit("ConstraintOnBase", [](json& s) { s["constraints"][0]["part"] = "base"; }, "constraints[0].part",
           "a part other than the base"),
      edit("ImpossibleConstraint", [](json& s) { s["parts"][1]["final_pose"]["position"] = {10, 0, 25}; }, "constraints[0]",
           "holds at the part's final_pose"),
      edit("ConstraintWithoutBase", [](json& s) { s.erase("base"); }, "constraints[0]", "a \"base\" part"),
      edit("BaseNotAPart", [](json& s) { s["base"] = "table"; }, "base", "the name of a part"),
      edit("UnknownMaterial", [](json& s) { s["parts"][1]["material"] = "unobtainium"; }, "parts[1].material",
           "the name of a material"),
      edit("MisspelledKey", [](json& s) { s["parts"][1]["materail"] = "steel"; }, "parts[1].materail", "one of the keys"),
      edit("DuplicatePartName", [](json& s) { s["parts"][1]["name"] = "base"; }, "parts[1].name", "not used before"),
      edit("KineticAboveStatic", [](json& s) { s["materials"]["steel"]["friction"]["kinetic"] = 0.5; },
           "materials.steel.friction.kinetic", "no larger than the static"),
      edit("NonUnitQuaternion", [](json& s) { s["parts"][1]["pose"]["rotation"] = {{"quaternion", {2, 0, 0, 0}}}; },
           "parts[1].pose.rotation.quaternion", "unit quaternion"),
      edit("NoShape", [](json& s) { s["parts"][1].erase("mesh"); }, "parts[1]", "exactly one of"),
      edit("NegativeBoxSize", [](json& s) { s["parts"][0]["primitive"]["size"] = {100, -1, 20}; }, "parts[0].primitive.size[1]",
           "a positive number"),
      edit("NoDensityNoProperties", [](json& s) { s["materials"]["steel"].erase("density"); }, "parts[0]",
           "a density (on the part or its material)"),
      mesh("OpenMesh", [](TriMesh& m) { m.triangles.pop_back(); }, "mesh", "a closed mesh"),
      mesh("InvertedNormals", [](TriMesh& m) { for (auto& t : m.triangles) std::swap(t[1], t[2]); }, "mesh",
           "outward-facing triangles"),
      mesh("InconsistentOrientation", [](TriMesh& m) { std::swap(m.triangles[5][1], m.triangles[5][2]); }, "mesh",
           "consistently oriented"),
      properties("PropertyFileMissingInertia", [](json& p) { p.erase("inertia_cm"); }, "inertia_cm", "required key"),
      properties("PropertyFileMissingUnits", [](json& p) { p.erase("units"); }, "units", "required key"),
      properties("ZeroMass", [](json& p) { p["mass"] = 0; }, "mass", "a positive number"),
      properties("NegativeMass", [](json& p) { p["mass"] = -18.5; }, "mass", "a positive number"),
      properties("NonSpdInertia", [](json& p) { p["inertia_cm"] = {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}}; }, "inertia_cm",
                 "positive-definite"),
      properties("TriangleInequality", [](json& p) { p["inertia_cm"] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 3}}; }, "inertia_cm",
                 "I1 + I2 >= I3"),
      properties("AsymmetricInertia", [](json& p) { p["inertia_cm"] = {{1.5, 0.2, 0}, {0, 1.5, 0}, {0, 0, 0.23}}; },
                 "inertia_cm", "symmetric"),
      properties("MassDensityVolumeDisagree", [](json& p) { p["density"] = 7850; p["volume"] = 1.0; }, "mass",
                 "density * volume"),
      properties("PropertyUnknownKey", [](json& p) { p["colour"] = "red"; }, "colour", "one of the keys"),
      // Hostile values: each crashed, hung or was accepted silently before the world's bounds were checked.
      edit("FarAwayPart", [](json& s) { s["parts"][1]["pose"]["position"][2] = 1e308; }, "parts[1].pose.position", "world bound"),
      edit("FarAwayBase", [](json& s) { s["parts"][0]["pose"] = {{"position", {0, 1e300, 0}}}; }, "parts[0].pose.position",
           "world bound"),
      edit("FarAwayTable", [](json& s) { s["environment"][0]["pose"]["position"][2] = 1e308; }, "environment[0].pose.position",
           "world bound"),
      edit("FarAwayAxisPoint", [](json& s) { s["constraints"][0]["base_axis"]["point"] = {0, 0, 1e300}; },
           "constraints[0].base_axis.point", "world bound"),
      edit("HugeEnvironmentBox", [](json& s) { s["environment"][0]["primitive"]["size"][0] = 1e300; },
           "environment[0].primitive.size[0]", "a length from 1e-06 m to 100 m"),
      edit("HugeDensity", [](json& s) { s["materials"]["steel"]["density"] = 1e308; }, "materials.steel.density",
           "a density from 0.1 to 100000 kg/m^3"),
      edit("TinyDensity", [](json& s) { s["parts"][1]["density"] = 1e-300; }, "parts[1].density", "a density from 0.1"),
      edit("HugeFriction", [](json& s) { s["materials"]["steel"]["friction"]["static"] = 1e300; },
           "materials.steel.friction.static", "a number from 0 to 10"),
      edit("HugeRotationalFriction", [](json& s) { s["materials"]["steel"]["friction"]["rotational"] = 1e300; },
           "materials.steel.friction.rotational", "a number from 0 to 100 N m s"),
      edit("DescriptionNotAString", [](json& s) { s["description"] = 42; }, "description", "a string"),
      edit("SegmentsWrapAround", [](json& s) {
             s["parts"][0]["primitive"] = {{"type", "cylinder"}, {"radius", 50}, {"height", 20}, {"segments", 4294967299ULL}};
           }, "parts[0].primitive.segments", "an integer from 3 to 4096"),
      edit("VersionWrapsAround", [](json& s) { s["version"] = 4294967297ULL; }, "version", "an integer from"),
      edit("GroupsNestedTooDeep", [](json& s) {
             json part = s["parts"][1];
             for (int i = 0; i < 40; ++i) part = {{"name", "g" + std::to_string(i)}, {"children", json::array({part})}};
             s["parts"][1] = part;
           }, "children", "groups nested at most 32 deep"),
      edit("GroupPosesAddUpOutOfBounds", [](json& s) {
             s["parts"][1] = {{"name", "g"}, {"pose", {{"position", {900000, 0, 0}}}}, {"children", json::array({s["parts"][1]})}};
             s["parts"][1]["children"][0]["pose"]["position"] = {900000, 0, 0};
           }, "parts[1].children[0].pose", "with its groups' poses"),
      mesh("FarAwayMeshVertex", [](TriMesh& m) { m.vertices[0].x() = 1e38; }, "vertices", "world bound"),
      properties("HugeMass", [](json& p) { p["mass"] = 1e300; }, "mass", "a mass from 1e-06 to 1e+06 kg"),
      properties("FarAwayCentreOfMass", [](json& p) { p["center_of_mass"] = {0, 0, 1e300}; }, "center_of_mass", "world bound"),
      raw("NestedTooDeep", std::string(100000, '['), "line 1, column 101", "nested at most 100 deep"),
      raw("PropertyFileAsScene", validProperties().dump(), "format", "\"vaw-scene\" (a scene)"),
  };
}

// Keeps gtest from dumping the struct's bytes into every test's name.
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class BadInput : public ::testing::TestWithParam<Case> {};

TEST_P(BadInput, NamedErrorNoCrash) {
  const Case& c = GetParam();
  const auto dir = test::tempDir();
  const auto scene = c.setup(dir);
  try {
    (void)loadScene(scene, test::importers());
    FAIL() << "loaded without error";
  } catch (const InputError& e) {
    const Diagnostic& d = e.diagnostic();
    EXPECT_NE(d.field.find(c.field), std::string::npos) << "field: " << d.field << "\nmessage: " << e.what();
    EXPECT_NE(d.expected.find(c.expected), std::string::npos) << "expected: " << d.expected << "\nmessage: " << e.what();
    EXPECT_TRUE(d.file.ends_with(c.fileEnds)) << "file: " << d.file;
    EXPECT_NE(std::string(e.what()).find(d.file), std::string::npos);
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, BadInput, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& p) { return p.param.name; });

TEST(BadInputSuite, HasAtLeastFifteenCases) { EXPECT_GE(cases().size(), 15u); }

// What the message says, not only where: a file of another vaw kind is named as such.
TEST(BadInputSuite, AnotherVawFileKindIsNamed) {
  const auto dir = test::tempDir();
  const auto props = test::writeFile(dir / "pin.props.json", validProperties().dump());
  try {
    (void)loadAny(props, test::importers());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.diagnostic().found, "\"vaw-properties\" (this is a vaw-properties file, not a scene)") << e.what();
  }
  const auto scene = writeScene(dir, validScene());
  try {
    (void)readPropertyFile(scene);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.diagnostic().found, "\"vaw-scene\" (this is a vaw-scene file, not a property file)") << e.what();
  }
}

TEST(BadInputSuite, DirectoryIsNotInvalidJson) {
  const auto dir = test::tempDir();
  std::filesystem::create_directories(dir / "scene.vaw.json");
  try {
    (void)loadAny(dir / "scene.vaw.json", test::importers());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.diagnostic().expected, "an existing, readable file") << e.what();
    EXPECT_EQ(e.diagnostic().found.rfind("a directory", 0), 0u) << e.what();
  }
}

TEST(BadInputSuite, MeshSymlinkLoopIsNamed) {
  // Threw std::filesystem::filesystem_error (uncaught: abort) and elsewhere read as "no such file".
  const auto dir = test::tempDir();
  std::filesystem::create_symlink("b.stl", dir / "a.stl");
  std::filesystem::create_symlink("a.stl", dir / "b.stl");
  json s = validScene();
  s["parts"][1]["mesh"] = "a.stl";
  test::writeFile(dir / "scene.vaw.json", s.dump());
  try {
    (void)loadScene(dir / "scene.vaw.json", test::importers());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.diagnostic().field, "parts[1].mesh") << e.what();
    EXPECT_NE(e.diagnostic().found.find("a loop of symbolic links"), std::string::npos) << e.what();
  }
  try {
    (void)loadAny(dir / "a.stl", test::importers());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.diagnostic().found.rfind("a loop of symbolic links", 0), 0u) << e.what();
  }
}

TEST(BadInputSuite, TooManyTrianglesAreRefusedBeforeTheChecks) {
  // Welding and the edge checks of a mesh grow with its size (5 million triangles: about 9 s and
  // 1.1 GB); a mesh above the stated limit is refused before them. An importer that returns one.
  struct Huge final : MeshImporter {
    [[nodiscard]] std::string name() const override { return "huge"; }
    [[nodiscard]] std::vector<std::string> extensions() const override { return {"huge"}; }
    [[nodiscard]] bool canRead(const std::filesystem::path&) const override { return true; }
    [[nodiscard]] ImportedMesh read(const std::filesystem::path&, const ImportOptions&, const ProgressFn&) const override {
      ImportedMesh m;
      m.root.mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
      m.root.mesh.triangles.assign(limits::kMaxTriangles + 1, Eigen::Vector3i(0, 1, 2));
      return m;
    }
  };
  ImporterRegistry importers;
  importers.add(std::make_unique<Huge>());
  const auto file = test::writeFile(test::tempDir() / "big.huge", "");
  try {
    (void)loadMeshFile(file, importers);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.diagnostic().field, "triangles") << e.what();
    EXPECT_EQ(e.diagnostic().expected, "at most 10000000 triangles in one mesh") << e.what();
  }
}

TEST(BadInputSuite, UnusualFrictionLoadsWithAWarning) {
  const auto dir = test::tempDir();
  json s = validScene();
  s["materials"]["steel"]["friction"] = {{"static", 3.0}, {"kinetic", 2.5}};
  const Assembly a = loadScene(writeScene(dir, s), test::importers());
  ASSERT_FALSE(a.warnings.empty());
  EXPECT_EQ(a.warnings[0].field, "materials.steel.friction.static");
  EXPECT_EQ(a.materials.at("steel").staticFriction, 3.0);
}

TEST(BadInputSuite, TheValidProbeLoads) {
  // The cases above are single edits of this scene, so each error is caused by its edit alone.
  const auto dir = test::tempDir();
  const Assembly a = loadScene(writeScene(dir, validScene()), test::importers());
  ASSERT_EQ(a.parts.size(), 2u);
  // Mesh files carry single-precision vertices (assimp), so agreement is to float round-off.
  const double exact = 7850 * 24 * 0.5 * 25e-6 * std::sin(2 * M_PI / 24) * 0.03;
  EXPECT_NEAR(a.parts[1].mass.mass, exact, 1e-7 * exact);
  const auto pdir = test::tempDir();
  test::writeFile(pdir / "pin.props.json", validProperties().dump());
  json s = validScene();
  s["parts"][1]["properties"] = "pin.props.json";
  const Assembly b = loadScene(writeScene(pdir, s), test::importers());
  EXPECT_EQ(b.parts[1].massSource, MassSource::PropertyFile);
  EXPECT_NEAR(b.parts[1].mass.mass, 0.0185, 1e-15);
}

TEST(BadInputSuite, MissingSceneFile) {
  try {
    (void)loadAny(test::tempDir() / "absent.vaw.json", test::importers());
    FAIL();
  } catch (const InputError& e) {
    // The name was resolved like a command-line name: the error says where it looked.
    EXPECT_EQ(e.diagnostic().found.rfind("no such file (looked at ", 0), 0u) << e.diagnostic().found;
  }
}

TEST(BadInputSuite, NonFiniteMeshVertex) {
  const auto dir = test::tempDir();
  std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1e999\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  test::writeFile(dir / "bad.obj", obj);
  try {
    (void)loadMeshFile(dir / "bad.obj", test::importers());
    FAIL() << "a mesh with an infinite vertex loaded";
  } catch (const InputError& e) {
    EXPECT_NE(e.diagnostic().file.find("bad.obj"), std::string::npos) << e.what();
    EXPECT_EQ(e.diagnostic().expected, "finite vertex coordinates");
  }
}

TEST(BadInputSuite, CorruptMeshFile) {
  const auto dir = test::tempDir();
  test::writeFile(dir / "broken.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 1000\nend_header\n\x01\x02");
  try {
    (void)loadMeshFile(dir / "broken.ply", test::importers());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_TRUE(e.diagnostic().file.ends_with("broken.ply")) << e.what();
    EXPECT_NE(e.diagnostic().expected.find(".ply"), std::string::npos) << e.what();
  }
}

// A triangle whose corners weld together is the mesher's noise: removed, and the part loads closed.
TEST(BadInputSuite, DegenerateTrianglesAreRemoved) {
  const auto dir = test::tempDir();
  TriMesh m = pinMesh();
  const std::size_t triangles = m.triangles.size();
  m.triangles.emplace_back(0, 1, 1);
  const Assembly a = loadScene(writeScene(dir, validScene(), m), test::importers());
  const auto pin = std::find_if(a.parts.begin(), a.parts.end(), [](const Part& p) { return p.shapeSource.find("pin.stl") != std::string::npos; });
  ASSERT_NE(pin, a.parts.end());
  EXPECT_EQ(pin->mesh->triangles.size(), triangles);
  EXPECT_TRUE(checkMesh(*pin->mesh).valid());
}

}  // namespace
