// A session and an order as glTF 2.0 binaries, read back byte by byte: the container as the specification
// lays it out, every accessor inside the buffer and aligned, each mesh the part's own vertices and
// triangles, and the animation, evaluated as a viewer evaluates it (linear keys, slerp, stepped scale),
// within the stated tolerance of every sampled pose and exactly at the end.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>

#include <nlohmann/json.hpp>

#include "files.hpp"
#include "sim_test_support.hpp"
#include "vaw/evaluation/sequence.hpp"
#include "vaw/report/gltf.hpp"
#include "vaw/sim/session.hpp"

using namespace vaw;
using json = nlohmann::json;

namespace {

// The GLB's JSON and binary chunks, checked as the specification requires on the way.
struct Glb {
  json doc;
  std::vector<std::uint8_t> bin;

  explicit Glb(const std::vector<std::uint8_t>& bytes) {
    const auto word = [&](std::size_t at) {
      std::uint32_t w;
      std::memcpy(&w, bytes.data() + at, 4);
      return w;
    };
    EXPECT_GE(bytes.size(), 28u);
    EXPECT_EQ(word(0), 0x46546C67u) << "magic glTF";
    EXPECT_EQ(word(4), 2u) << "container version";
    EXPECT_EQ(word(8), bytes.size()) << "the header's length is the file's";
    const std::uint32_t jsonLength = word(12);
    EXPECT_EQ(word(16), 0x4E4F534Au) << "JSON chunk first";
    EXPECT_EQ(jsonLength % 4, 0u);
    doc = json::parse(bytes.begin() + 20, bytes.begin() + 20 + jsonLength);
    const std::size_t binAt = 20 + jsonLength;
    const std::uint32_t binLength = word(binAt);
    EXPECT_EQ(word(binAt + 4), 0x004E4942u) << "BIN chunk second";
    EXPECT_EQ(binLength % 4, 0u);
    EXPECT_EQ(binAt + 8 + binLength, bytes.size());
    bin.assign(bytes.begin() + static_cast<std::ptrdiff_t>(binAt + 8), bytes.end());
    EXPECT_EQ(doc["buffers"][0]["byteLength"].get<std::size_t>(), bin.size());
  }

  // An accessor's floats (after checking it lies inside its view and the buffer, aligned).
  [[nodiscard]] std::vector<float> floats(std::size_t accessor) const {
    const json& a = doc["accessors"][accessor];
    EXPECT_EQ(a["componentType"], 5126);
    const int width = a["type"] == "SCALAR" ? 1 : a["type"] == "VEC3" ? 3 : a["type"] == "VEC4" ? 4 : 0;
    EXPECT_GT(width, 0);
    const std::size_t count = a["count"].get<std::size_t>() * static_cast<std::size_t>(width);
    const json& v = doc["bufferViews"][a["bufferView"].get<std::size_t>()];
    const std::size_t at = v["byteOffset"].get<std::size_t>();
    EXPECT_EQ(at % 4, 0u);
    EXPECT_LE(count * 4, v["byteLength"].get<std::size_t>());
    EXPECT_LE(at + v["byteLength"].get<std::size_t>(), bin.size());
    std::vector<float> out(count);
    std::memcpy(out.data(), bin.data() + at, count * 4);
    // The bounds it states are its values'.
    for (int c = 0; c < width; ++c) {
      float lo = INFINITY, hi = -INFINITY;
      for (std::size_t i = static_cast<std::size_t>(c); i < count; i += static_cast<std::size_t>(width)) {
        lo = std::min(lo, out[i]);
        hi = std::max(hi, out[i]);
      }
      if (a.contains("min")) {
        EXPECT_EQ(a["min"][c].get<float>(), lo);
        EXPECT_EQ(a["max"][c].get<float>(), hi);
      }
    }
    return out;
  }
  [[nodiscard]] std::vector<std::uint32_t> indices(std::size_t accessor) const {
    const json& a = doc["accessors"][accessor];
    EXPECT_EQ(a["componentType"], 5125);
    const json& v = doc["bufferViews"][a["bufferView"].get<std::size_t>()];
    const std::size_t count = a["count"].get<std::size_t>();
    std::vector<std::uint32_t> out(count);
    std::memcpy(out.data(), bin.data() + v["byteOffset"].get<std::size_t>(), count * 4);
    return out;
  }
  [[nodiscard]] std::size_t node(const std::string& name) const {
    for (std::size_t i = 0; i < doc["nodes"].size(); ++i)
      if (doc["nodes"][i]["name"] == name) return i;
    ADD_FAILURE() << "no node " << name;
    return 0;
  }
  // What a viewer shows of a node's `path` at time t: its channel's keys interpolated (linear, slerp for a
  // rotation; stepped where the sampler says STEP), or none when no channel drives it.
  [[nodiscard]] std::optional<std::vector<double>> at(std::size_t node, const std::string& path, double t) const {
    if (!doc.contains("animations")) return std::nullopt;
    const json& anim = doc["animations"][0];
    for (const json& ch : anim["channels"]) {
      if (ch["target"]["node"] != node || ch["target"]["path"] != path) continue;
      const json& s = anim["samplers"][ch["sampler"].get<std::size_t>()];
      const std::vector<float> times = floats(s["input"]);
      const std::vector<float> values = floats(s["output"]);
      const std::size_t w = values.size() / times.size();
      std::size_t k = 0;
      while (k + 1 < times.size() && times[k + 1] <= t) ++k;
      std::vector<double> v(w);
      if (k + 1 == times.size() || s["interpolation"] == "STEP") {
        for (std::size_t c = 0; c < w; ++c) v[c] = values[k * w + c];
        return v;
      }
      const double u = (t - times[k]) / (times[k + 1] - times[k]);
      if (path == "rotation") {
        const Eigen::Quaterniond a(values[k * w + 3], values[k * w], values[k * w + 1], values[k * w + 2]);
        const Eigen::Quaterniond b(values[(k + 1) * w + 3], values[(k + 1) * w], values[(k + 1) * w + 1],
                                   values[(k + 1) * w + 2]);
        const Eigen::Quaterniond q = a.slerp(u, b);
        return std::vector<double>{q.x(), q.y(), q.z(), q.w()};
      }
      for (std::size_t c = 0; c < w; ++c) v[c] = (1 - u) * values[k * w + c] + u * values[(k + 1) * w + c];
      return v;
    }
    return std::nullopt;
  }
};

// How far a node's animated pose at t is from `pose`: the position's distance (m) and the turn between (rad).
std::pair<double, double> offBy(const Glb& g, std::size_t node, double t, const Eigen::Isometry3d& pose) {
  const auto p = g.at(node, "translation", t);
  const auto r = g.at(node, "rotation", t);
  if (!p || !r) return {INFINITY, INFINITY};
  const Eigen::Quaterniond q((*r)[3], (*r)[0], (*r)[1], (*r)[2]);
  return {(Eigen::Vector3d((*p)[0], (*p)[1], (*p)[2]) - pose.translation()).norm(),
          q.angularDistance(Eigen::Quaterniond(pose.linear()))};
}

}  // namespace

TEST(Gltf, ASessionReplaysWithinItsToleranceAndEndsWhereTheSessionEnds) {
  const auto scene = sim::Scene::build(simtest::loadBundled("sleeve-on-shaft.vaw.json"));
  sim::Session s;
  s.scene = "sleeve-on-shaft.vaw.json";
  s.sceneHash = scene->contentHash();
  s.inputs = sim::loadInputScript(std::filesystem::path(VAW_SOURCE_DIR) / "tests/sim/scripts/sleeve-turnover.vaw-inputs.json",
                                  s.settings);
  const report::Motion m = report::sessionMotion(scene, s, 30.0);
  const sim::World end = sim::replay(scene, s);
  EXPECT_NEAR(m.duration, end.time(), 1e-9) << "the last sample is the session's end";
  ASSERT_EQ(m.parts.size(), scene->assembly().parts.size());
  const report::Track& carried = m.parts[*scene->assembly().findPart("sleeve")];
  ASSERT_GT(carried.times.size(), 30u);
  EXPECT_NEAR(carried.times.back(), end.time(), 1e-9);
  report::GltfOptions o;
  o.positionTolerance = 1e-4;
  o.angleTolerance = 1e-3;
  const Glb g(report::glb(scene->assembly(), m, o));
  const json& d = g.doc;
  EXPECT_EQ(d["asset"]["version"], "2.0");
  // The root turns z-up to y-up; under it a node per part and the table (not the room's floor).
  const json& root = d["nodes"][0];
  const Eigen::Quaterniond turn(root["rotation"][3].get<double>(), root["rotation"][0].get<double>(),
                                root["rotation"][1].get<double>(), root["rotation"][2].get<double>());
  EXPECT_LT((turn * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitY()).norm(), 1e-12);
  const Assembly& a = scene->assembly();
  EXPECT_EQ(root["children"].size(), a.parts.size() + 1);
  const std::size_t sleeve = g.node("sleeve");
  EXPECT_GT(g.node("table"), 0u);
  // Each part's mesh: its vertices (as floats) and its triangles.
  for (const char* name : {"sleeve", "base"}) {
    const TriMesh& mesh = *a.parts[*a.findPart(name)].mesh;
    const json& prim = d["meshes"][d["nodes"][g.node(name)]["mesh"].get<std::size_t>()]["primitives"][0];
    const std::vector<float> xyz = g.floats(prim["attributes"]["POSITION"]);
    ASSERT_EQ(xyz.size(), 3 * mesh.vertices.size()) << name;
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
      for (int c = 0; c < 3; ++c) EXPECT_EQ(xyz[3 * i + static_cast<std::size_t>(c)], static_cast<float>(mesh.vertices[i][c]));
    const std::vector<std::uint32_t> idx = g.indices(prim["indices"]);
    ASSERT_EQ(idx.size(), 3 * mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(idx[3 * t + static_cast<std::size_t>(c)], static_cast<std::uint32_t>(mesh.triangles[t][c]));
  }
  // The script turns the base over and carries the sleeve: both are animated, the table is not.
  EXPECT_FALSE(g.at(g.node("table"), "translation", 0.0).has_value());
  for (const char* name : {"sleeve", "base"}) {
    const PartId p = *a.findPart(name);
    const std::size_t node = g.node(name);
    double worstAt = 0.0, worstTurn = 0.0;
    const report::Track& track = m.parts[p];
    for (std::size_t k = 0; k < track.times.size(); ++k) {
      const auto [dx, da] = offBy(g, node, track.times[k], track.poses[k]);
      worstAt = std::max(worstAt, dx);
      worstTurn = std::max(worstTurn, da);
    }
    // The tolerance of the keys dropped, and single precision on a position within a metre.
    EXPECT_LE(worstAt, o.positionTolerance + 1e-6) << name;
    EXPECT_LE(worstTurn, o.angleTolerance + 1e-5) << name;
    const auto [endAt, endTurn] = offBy(g, node, end.time(), end.part(p).pose);
    EXPECT_LE(endAt, 1e-6) << name;
    EXPECT_LE(endTurn, 1e-5) << name;
  }
  // Thinned: fewer keys than samples.
  std::size_t keys = 0;
  for (const json& ch : d["animations"][0]["channels"])
    if (ch["target"]["node"] == sleeve && ch["target"]["path"] == "translation")
      keys =
          d["accessors"][d["animations"][0]["samplers"][ch["sampler"].get<std::size_t>()]["input"].get<std::size_t>()]["count"];
  EXPECT_GT(keys, 2u);
  EXPECT_LT(keys, carried.times.size());
  RecordProperty("keys", static_cast<int>(keys));
  RecordProperty("samples", static_cast<int>(carried.times.size()));

  // Written whole to a file; a file that cannot be written is a named error.
  const auto dir = test::tempDir();
  report::writeGlb(dir / "s.glb", a, m, o);
  EXPECT_EQ(std::filesystem::file_size(dir / "s.glb"), report::glb(a, m, o).size());
  EXPECT_THROW(report::writeGlb(dir / "no-such-folder" / "s.glb", a, m, o), OutputError);
}

TEST(Gltf, AnOrderShowsEachPartFromItsStepAndEndsAssembled) {
  const Assembly a = simtest::loadBundled("gear-on-shaft.vaw.json");
  const eval::SequencePlan plan = eval::planSequence(a);
  ASSERT_EQ(plan.order.size(), a.parts.size());
  const report::Motion m = report::orderMotion(a, plan, 1.0, 20.0);
  const Glb g(report::glb(a, m));
  const std::vector<Eigen::Isometry3d> home = eval::homePoses(a);
  for (std::size_t i = 1; i < plan.order.size(); ++i) {
    const PartId p = plan.order[i];
    const std::size_t node = g.node(a.parts[p].name);
    const double step = static_cast<double>(i);
    // Hidden before its step, shown from it on.
    EXPECT_EQ(*g.at(node, "scale", step - 0.5), (std::vector<double>{0, 0, 0}));
    EXPECT_EQ(*g.at(node, "scale", step + 0.01), (std::vector<double>{1, 1, 1}));
    EXPECT_EQ(g.doc["nodes"][node]["scale"], (json{0.0, 0.0, 0.0}));
    // Out along its way at the step's start, home at its end.
    const Eigen::Vector3d out = plan.wayOf(p)->out;
    const auto start = g.at(node, "translation", step);
    ASSERT_TRUE(start.has_value());
    const Eigen::Vector3d away = Eigen::Vector3d((*start)[0], (*start)[1], (*start)[2]) - home[p].translation();
    EXPECT_GT(away.norm(), 0.02);
    EXPECT_NEAR(away.normalized().dot(out), 1.0, 1e-5) << "it comes in along its way";
    const auto [dx, da] = offBy(g, node, step + 1.0, home[p]);
    EXPECT_LE(dx, 1e-6);
    EXPECT_LE(da, 1e-5);
  }
  // The base stands where it is, neither moved nor hidden.
  const std::size_t base = g.node(a.parts[*plan.base].name);
  EXPECT_FALSE(g.at(base, "translation", 0.5).has_value());
  EXPECT_FALSE(g.at(base, "scale", 0.0).has_value());
}
