// A product's size (docs/step.md, "Large products"): the 1,027-part tiled product of
// tests/step/step_fixtures.hpp (54 copies of a 19-part sub-assembly of brackets, headed bolts, nuts, a rod
// and dowel pins on one 1.9 m base plate with 540 holes), written with Open CASCADE in the test and read
// through the STEP plugin. Every insert and mate of every tile is recognised, the base plate's included,
// each usable and with the partners a fitter would give it, and every tile gets exactly what the first gets;
// the order search puts all of them in place keeping every precedence the geometry imposes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numeric>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "bundled.hpp"
#include "files.hpp"
#include "step_fixtures.hpp"
#include "vaw/collision/collision_world.hpp"
#include "vaw/constraint_recognition.hpp"
#include "vaw/evaluation/sequence.hpp"
#include "vaw/scene_loader.hpp"

namespace {

using vaw::Assembly;
using vaw::Constraint;

constexpr int kTilesX = 9, kTilesY = 6, kTiles = kTilesX * kTilesY;

const Assembly& product() {
  static const Assembly loaded = [] {
    const auto file = vaw::test::tempDir() / "tiled-product.stp";
    vaw::steptest::writeTiledProduct(file, kTilesX, kTilesY);
    return vaw::loadAny(file, vaw::test::importers());
  }();
  return loaded;
}

// "bolt-3 #7" -> {"bolt-3", 7}; the first tile's parts carry no number.
std::pair<std::string, int> tileOf(const std::string& name) {
  const auto hash = name.find(" #");
  if (hash == std::string::npos) return {name, 1};
  return {name.substr(0, hash), std::stoi(name.substr(hash + 2))};
}

TEST(LargeProduct, EveryInsertAndMateIsRecognisedTheBasePlatesIncluded) {
  const Assembly& a = product();
  ASSERT_EQ(a.parts.size(), 1u + 19u * kTiles);
  ASSERT_TRUE(a.base.has_value());
  EXPECT_EQ(a.parts[*a.base].name, "base-plate");
  int inserts = 0, mates = 0, onTheBase = 0;
  for (const Constraint& c : a.constraints) {
    (c.type == Constraint::Type::Insert ? inserts : mates) += 1;
    if (c.partner.value_or(*a.base) == *a.base) ++onTheBase;
  }
  // A tile: 18 bolt inserts (plate, bracket, nut), 2 for the rod, 4 dowels; mates: brackets on the plate, bolt
  // heads on the brackets, nuts under the plate.
  EXPECT_EQ(inserts, 24 * kTiles);
  EXPECT_EQ(mates, 14 * kTiles);
  // On the plate: 6 bolts and 4 dowels in its holes, 2 brackets and 6 nuts on its faces, in every tile.
  EXPECT_EQ(onTheBase, 18 * kTiles);
  const auto fits = vaw::collision::constraintFits(a);
  ASSERT_EQ(fits.size(), a.constraints.size());
  int unusable = 0;
  for (const auto& f : fits)
    if (!f.support.problem.empty() && ++unusable <= 5) ADD_FAILURE() << a.constraints[f.constraint].name << ": " << f.support.problem;
  EXPECT_EQ(unusable, 0);
}

// The same contacts with the same partners in every tile, as in the first: what holds for one copy of a
// sub-assembly holds for all 54, whether its answer was worked out or reused.
TEST(LargeProduct, EveryTileIsRecognisedAsTheFirstWithThePartnersAFitterGives) {
  const Assembly& a = product();
  using Contact = std::tuple<Constraint::Type, std::string, std::string>;
  std::map<int, std::multiset<Contact>> byTile;
  for (const Constraint& c : a.constraints) {
    const auto [part, tile] = tileOf(a.parts[c.part].name);
    const auto [partner, partnerTile] = tileOf(a.parts[c.partner.value_or(*a.base)].name);
    if (partner != "base-plate") {
      EXPECT_EQ(partnerTile, tile) << c.name;
    }
    byTile[tile].insert({c.type, part, partner});
  }
  ASSERT_EQ(byTile.size(), static_cast<std::size_t>(kTiles));
  const auto& first = byTile.at(1);
  ASSERT_EQ(first.size(), 38u);
  for (const auto& [tile, contacts] : byTile) EXPECT_EQ(contacts, first) << "tile " << tile;
  using T = Constraint::Type;
  for (int k = 1; k <= 6; ++k) {
    const std::string bolt = "bolt-" + std::to_string(k), bracket = k <= 3 ? "bracket-1" : "bracket-2";
    // The head clamps the bracket: the bracket first, the bolt through it onto it and into the plate.
    EXPECT_EQ(first.count({T::Insert, bolt, bracket}), 1u) << bolt;
    EXPECT_EQ(first.count({T::Mate, bolt, bracket}), 1u) << bolt;
    EXPECT_EQ(first.count({T::Insert, bolt, "base-plate"}), 1u) << bolt;
    // The nut after its bolt, against the plate.
    EXPECT_EQ(first.count({T::Insert, "nut-" + std::to_string(k), bolt}), 1u) << bolt;
    EXPECT_EQ(first.count({T::Mate, "nut-" + std::to_string(k), "base-plate"}), 1u) << bolt;
  }
  EXPECT_EQ(first.count({T::Insert, "rod", "bracket-1"}), 1u);
  EXPECT_EQ(first.count({T::Insert, "rod", "bracket-2"}), 1u);
  for (int k = 1; k <= 4; ++k) EXPECT_EQ(first.count({T::Insert, "dowel-" + std::to_string(k), "base-plate"}), 1u) << k;
}

// Laid out to be reached: every part waits on the table round the base, none on another, none farther from
// the base's edge than the base is long, the table under all of them.
TEST(LargeProduct, ThePartsWaitRoundTheBaseWithinReachAndApart) {
  const Assembly& a = product();
  const auto boxOf = [&](vaw::PartId id) {
    Eigen::AlignedBox3d b;
    for (const auto& v : a.parts[id].mesh->vertices) b.extend(a.parts[id].pose * v);
    return b;
  };
  const Eigen::AlignedBox3d base = boxOf(*a.base);
  const double reach = base.sizes().head<2>().maxCoeff();
  std::vector<std::pair<Eigen::AlignedBox3d, vaw::PartId>> boxes;
  for (vaw::PartId id = 0; id < a.parts.size(); ++id) {
    const Eigen::AlignedBox3d b = boxOf(id);
    boxes.emplace_back(b, id);
    if (id == *a.base) continue;
    EXPECT_NEAR(b.min().z(), 0.0, 1e-6) << a.parts[id].name << " rests on the table";
    // How far outside the base's footprint, in the plane.
    const Eigen::Vector2d out = (base.min().head<2>() - b.max().head<2>()).cwiseMax(b.min().head<2>() - base.max().head<2>()).cwiseMax(0.0);
    EXPECT_LE(out.norm(), reach) << a.parts[id].name;
  }
  // No two overlap (boxes sorted along x, each compared with those that start before it ends).
  std::sort(boxes.begin(), boxes.end(), [](const auto& x, const auto& y) { return x.first.min().x() < y.first.min().x(); });
  int overlaps = 0;
  for (std::size_t i = 0; i < boxes.size(); ++i)
    for (std::size_t j = i + 1; j < boxes.size() && boxes[j].first.min().x() < boxes[i].first.max().x(); ++j) {
      const Eigen::AlignedBox3d common = boxes[i].first.intersection(boxes[j].first);
      if (!common.isEmpty() && (common.sizes().array() > 1e-9).all() && ++overlaps <= 5)
        ADD_FAILURE() << a.parts[boxes[i].second].name << " overlaps " << a.parts[boxes[j].second].name;
    }
  EXPECT_EQ(overlaps, 0);
  // The table holds them all.
  ASSERT_FALSE(a.environment.empty());
  Eigen::AlignedBox3d table;
  for (const auto& v : a.environment[0].mesh->vertices) table.extend(a.environment[0].pose * v);
  for (const auto& [b, id] : boxes)
    EXPECT_TRUE(table.min().head<2>().cwiseMin(b.min().head<2>()) == table.min().head<2>() &&
                table.max().head<2>().cwiseMax(b.max().head<2>()) == table.max().head<2>())
        << a.parts[id].name << " is off the table";
}

// An order for all 1,026 parts but the base, in which each tile goes together as a fitter would put it
// together: its brackets before their bolts, each bolt before its nut, both brackets before the rod.
TEST(LargeProduct, AnOrderPutsEveryPartInPlaceKeepingEveryTruePrecedence) {
  const Assembly& a = product();
  const auto plan = vaw::eval::planSequence(a);
  ASSERT_TRUE(plan.complete()) << plan.stuck.size() << " parts without an order";
  EXPECT_EQ(plan.undecided, 0);
  ASSERT_EQ(plan.order.size(), a.parts.size());
  std::map<std::pair<std::string, int>, std::size_t> at;
  for (std::size_t k = 0; k < plan.order.size(); ++k) at[tileOf(a.parts[plan.order[k]].name)] = k;
  for (int tile = 1; tile <= kTiles; ++tile) {
    const auto step = [&](const std::string& part) { return at.at({part, tile}); };
    for (int k = 1; k <= 6; ++k) {
      const std::string bolt = "bolt-" + std::to_string(k);
      EXPECT_LT(step(k <= 3 ? "bracket-1" : "bracket-2"), step(bolt)) << "tile " << tile << ", " << bolt;
      EXPECT_LT(step(bolt), step("nut-" + std::to_string(k))) << "tile " << tile << ", " << bolt;
    }
    EXPECT_LT(step("bracket-1"), step("rod")) << "tile " << tile;
    EXPECT_LT(step("bracket-2"), step("rod")) << "tile " << tile;
  }
  const auto position = [&](vaw::PartId p) { return std::find(plan.order.begin(), plan.order.end(), p); };
  int broken = 0;
  for (const auto& e : plan.precedence)
    if (position(e.before) >= position(e.after) && ++broken <= 5)
      ADD_FAILURE() << a.parts[e.before].name << " must come before " << a.parts[e.after].name;
  EXPECT_EQ(broken, 0);
  std::printf("[ info ] %zu parts ordered; %d pair checks, %d answered by another's, %d checks\n", plan.order.size(),
              plan.pairChecks, plan.reused, plan.evaluations);
}

// Each of a product's x * y tiles got what the first got (counted per kind across the product), nothing
// else, and no near miss anywhere.
void expectEveryTileAsTheFirst(const Assembly& a, const std::map<std::string, int>& perTile, std::map<std::string, int> counted, int x,
                               int y) {
  for (const auto& [kind, n] : perTile) EXPECT_EQ(counted[kind], n * x * y) << kind << " on " << x << " x " << y << " tiles";
  EXPECT_EQ(counted.size(), perTile.size()) << x << " x " << y;
  std::vector<vaw::RecognitionPart> parts;
  for (const auto& p : a.parts) parts.push_back({p.cad, p.finalPose.value_or(p.pose)});
  EXPECT_TRUE(vaw::nearMisses(parts).empty()) << x << " x " << y;
}

// Recognition does not depend on a part's size (docs/step.md, "Large products"): the same tile on a base
// plate that grows from one tile to ten, and to ten by two, with two holes per tile that nothing goes into,
// gets exactly the same constraints, tile for tile, kind for kind, none of them onto an empty hole; no near
// miss anywhere.
TEST(LargeProduct, RecognitionIsTheSameTileForTileAsTheBaseGrows) {
  std::map<std::string, int> perTile;  // "insert bolt-3 on base-plate" and the like, counted for one tile
  for (const auto& [x, y] : {std::pair{1, 1}, std::pair{2, 1}, std::pair{5, 1}, std::pair{10, 1}, std::pair{10, 2}}) {
    const auto file = vaw::test::tempDir() / ("tiled-" + std::to_string(x) + "x" + std::to_string(y) + "-empty-holes.stp");
    vaw::steptest::writeTiledProduct(file, x, y, true);
    const Assembly a = vaw::loadAny(file, vaw::test::importers());
    const int tiles = x * y;
    ASSERT_EQ(a.parts.size(), 1u + 19u * static_cast<std::size_t>(tiles));
    std::map<std::string, int> counted;
    for (const Constraint& c : a.constraints) {
      const std::string partner = c.partner ? tileOf(a.parts[*c.partner].name).first : a.parts[*a.base].name;
      ++counted[std::string(vaw::name(c.type)) + " " + tileOf(a.parts[c.part].name).first + " on " + partner];
    }
    if (perTile.empty()) {
      perTile = counted;
      EXPECT_EQ(std::accumulate(perTile.begin(), perTile.end(), 0, [](int n, const auto& e) { return n + e.second; }), 38);
      continue;
    }
    expectEveryTileAsTheFirst(a, perTile, counted, x, y);
  }
}

// A product unlike the tiled one (writeRigProduct): nested sub-assemblies in each tile, bolts from above
// with nuts under the plate and from below with nuts on the covers, dowel pins in blind holes, holes left
// empty, the whole product 2.5 m from the file's origin. Recognised identically tile for tile on a plate of
// 1, 3 and 5 x 2 tiles (80 constraints a tile, none onto an empty hole, no near miss), with every insert's
// fit as modelled.
TEST(RigProduct, RecognitionIsTheSameTileForTileOnEveryPlate) {
  std::map<std::string, int> perTile;
  for (const auto& [x, y] : {std::pair{1, 1}, std::pair{3, 1}, std::pair{5, 2}}) {
    const auto file = vaw::test::tempDir() / ("rig-" + std::to_string(x) + "x" + std::to_string(y) + ".stp");
    vaw::steptest::writeRigProduct(file, x, y);
    const Assembly a = vaw::loadAny(file, vaw::test::importers());
    const int tiles = x * y;
    ASSERT_EQ(a.parts.size(), 1u + 35u * static_cast<std::size_t>(tiles));
    ASSERT_TRUE(a.base.has_value());
    EXPECT_EQ(a.parts[*a.base].name, "plate");
    std::map<std::string, int> counted;
    for (const Constraint& c : a.constraints) {
      const std::string partner = c.partner ? tileOf(a.parts[*c.partner].name).first : a.parts[*a.base].name;
      std::string kind = std::string(vaw::name(c.type)) + " " + tileOf(a.parts[c.part].name).first + " on " + partner;
      if (c.found && c.type == Constraint::Type::Insert) {
        char radii[64];
        std::snprintf(radii, sizeof radii, " r %.2f/%.2f mm", c.found->partRadius * 1e3, c.found->partnerRadius * 1e3);
        kind += radii;
      }
      ++counted[kind];
    }
    if (perTile.empty()) {
      perTile = counted;
      EXPECT_EQ(std::accumulate(perTile.begin(), perTile.end(), 0, [](int n, const auto& e) { return n + e.second; }), 80);
      // The pins' fits in the blind holes and in the covers, the bolts' in the plate from both sides.
      EXPECT_EQ((counted["insert pin-1 on plate r 4.00/4.00 mm"]), 1);
      EXPECT_EQ((counted["insert cover on pin-1 r 4.05/4.00 mm"]), 1);
      // bolt-1 of each of the tile's four sub-assemblies: two from above, two from below.
      EXPECT_EQ((counted["insert bolt-1 on plate r 5.00/5.25 mm"]), 4);
      continue;
    }
    expectEveryTileAsTheFirst(a, perTile, counted, x, y);
  }
}

// Its order: every part placed, each bracket's bolts after the bracket and before their nuts, each cover
// after its pins and before the nuts on its bolts.
TEST(RigProduct, AnOrderPutsEveryPartInPlace) {
  const auto file = vaw::test::tempDir() / "rig-5x2.stp";
  if (!std::filesystem::exists(file)) vaw::steptest::writeRigProduct(file, 5, 2);
  const Assembly a = vaw::loadAny(file, vaw::test::importers());
  const vaw::eval::SequencePlan plan = vaw::eval::planSequence(a);
  ASSERT_TRUE(plan.complete()) << plan.stuck.size() << " parts unplaced";
  EXPECT_EQ(plan.order.size(), a.parts.size());
  std::vector<std::size_t> at(a.parts.size());
  for (std::size_t i = 0; i < plan.order.size(); ++i) at[plan.order[i]] = i;
  // Every insert's partner is in before the part that goes into or onto it.
  int inserts = 0;
  for (const Constraint& c : a.constraints) {
    if (c.type != Constraint::Type::Insert || !c.partner) continue;
    const std::string part = tileOf(a.parts[c.part].name).first, partner = tileOf(a.parts[*c.partner].name).first;
    if ((part.rfind("nut-", 0) == 0 && partner.rfind("bolt-", 0) == 0) || (part == "cover" && partner.rfind("pin-", 0) == 0)) {
      EXPECT_LT(at[*c.partner], at[c.part]) << a.parts[c.part].name << " before " << a.parts[*c.partner].name;
      ++inserts;
    }
  }
  EXPECT_EQ(inserts, 10 * (8 + 4 + 4));
}

}  // namespace
