// Collision: BVH and surface-patch build at load, the two checks of a part on its base per step, time of
// impact, and the filtered query against FCL's plain query on the same pair. Results: docs/benchmarks.md.
//   build-coll/bin/vaw_bench_collision --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// FCL is used here directly only to time its plain query against vaw's filtered one.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wold-style-cast"
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/narrowphase/collision.h>
#pragma GCC diagnostic pop

#include "vaw/collision/collision_world.hpp"
#include "vaw/collision/time_of_impact.hpp"
#include "vaw/dynamics/gravity.hpp"
#include "vaw/primitives.hpp"
#include "vaw/scene_loader.hpp"

namespace {

using namespace vaw;
using namespace vaw::collision;

Eigen::Isometry3d at(double x, double y, double z) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() = Eigen::Vector3d(x, y, z);
  return p;
}

const ImporterRegistry& importers() {
  static ImporterRegistry r;
  static bool loaded = [] {
    (void)r.loadPlugins(VAW_BUILD_PLUGIN_DIR);
    return true;
  }();
  (void)loaded;
  return r;
}

const char* const kScenes[] = {"block-on-plate", "sleeve-on-shaft", "gear-on-shaft", "large-gearbox"};

const Assembly& scene(int i) {
  static std::map<int, Assembly> cache;
  auto it = cache.find(i);
  if (it == cache.end()) {
    const auto file = std::filesystem::path(VAW_BUILD_RESOURCE_DIR) / "scenes" / (std::string(kScenes[i]) + ".vaw.json");
    it = cache.emplace(i, loadScene(file, importers())).first;
  }
  return it->second;
}


// The large performance case: a 10,092-triangle block (60 x 40 x 30 mm, every face a 29 x 29 grid)
// resting on a 248,832-triangle plate (300 x 200 x 40 mm, 144 x 144 grids, top at z = 20 mm) that carries
// a wall (its face at x = 100 mm) as part of the same base mesh.
struct Large {
  Assembly a;
  Constraint mate;
  Large() {
    TriMesh base = vaw::primitives::gridBox({0.3, 0.2, 0.04}, 144);
    TriMesh wall = primitives::box({0.02, 0.2, 0.05});
    base.append(wall, at(0.11, 0, 0.045));
    Part b;
    b.id = 0;
    b.name = "plate";
    b.mesh = std::make_shared<const TriMesh>(std::move(base));
    b.mass.mass = 1.0;
    Part p;
    p.id = 1;
    p.name = "block";
    p.mesh = std::make_shared<const TriMesh>(vaw::primitives::gridBox({0.06, 0.04, 0.03}, 29));
    p.pose = at(0.0, 0.0, 0.035);
    p.mass.mass = 0.2;
    a.parts = {b, p};
    a.base = 0;
    mate.type = Constraint::Type::Mate;
    mate.part = 1;
    mate.partPlane = {{0, 0, -0.015}, {0, 0, -1}};
    mate.basePlane = {{0, 0, 0.02}, {0, 0, 1}};
    a.constraints = {mate};
  }
};
const Large& large() {
  static const Large l;
  return l;
}
CollisionWorld& largeWorld() {
  static CollisionWorld w(large().a);
  return w;
}

// ---- build at load ----
void BM_BuildWorld(benchmark::State& state) {
  const Assembly& a = scene(static_cast<int>(state.range(0)));
  double largest = 0.0;
  for (auto _ : state) {
    CollisionWorld w(a);
    largest = 0.0;
    for (const ObjectId& id : w.objects()) largest = std::max(largest, w.info(id).buildSeconds);
    benchmark::DoNotOptimize(w);
  }
  state.SetLabel(kScenes[state.range(0)]);
  state.counters["objects"] = static_cast<double>(a.parts.size() + a.environment.size());
  state.counters["triangles"] = static_cast<double>(a.totalTriangles());
  state.counters["largest_object_ms"] = 1e3 * largest;
}
BENCHMARK(BM_BuildWorld)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);

void BM_BuildLarge(benchmark::State& state) {
  const Assembly& a = large().a;
  for (auto _ : state) {
    CollisionWorld w(a);
    benchmark::DoNotOptimize(w);
    state.counters["base_ms"] = 1e3 * w.info(ObjectId::part(0)).buildSeconds;
    state.counters["part_ms"] = 1e3 * w.info(ObjectId::part(1)).buildSeconds;
  }
  state.counters["base_triangles"] = static_cast<double>(a.parts[0].mesh->triangleCount());
  state.counters["part_triangles"] = static_cast<double>(a.parts[1].mesh->triangleCount());
}
BENCHMARK(BM_BuildLarge)->Unit(benchmark::kMillisecond);

// Surface patches alone (part of the build above) for the 250k-triangle base.
void BM_ClassifyLarge(benchmark::State& state) {
  const TriMesh& m = *large().a.parts[0].mesh;
  std::size_t planes = 0;
  for (auto _ : state) planes = classifySurfaces(m).planes.size();
  state.counters["planar_patches"] = static_cast<double>(planes);
}
BENCHMARK(BM_ClassifyLarge)->Unit(benchmark::kMillisecond);

// ---- the two checks per step ----
// The bundled scenes' constrained part at its final pose (resting / inserted), nudged each iteration
// along the free direction as a slide would.
void BM_ChecksBundled(benchmark::State& state) {
  const int i = static_cast<int>(state.range(0));
  Assembly a = scene(i);
  const Constraint& c = a.constraints.front();
  Part& p = a.parts[c.part];
  p.pose = p.finalPose.value_or(p.pose);
  if (c.type == Constraint::Type::Insert) {
    // Halfway along the shaft: 20 mm up its axis from the final pose.
    p.pose.pretranslate(a.parts[*a.base].pose.linear() * c.baseAxis.direction.normalized() * 0.02);
  }
  CollisionWorld w(a);
  const Support s = w.support(c);
  const Eigen::Isometry3d start = p.pose;
  int k = 0;
  bool touching = true, blocked = false;
  std::size_t bv = 0, leaves = 0;
  for (auto _ : state) {
    Eigen::Isometry3d q = start;
    q.pretranslate(Eigen::Vector3d(1e-5 * (k++ % 100), 0, 0) * (c.type == Constraint::Type::Mate ? 1.0 : 0.0));
    touching = w.touching(s, q).touching;
    const BlockResult b = w.blocked(s, q, 1);
    blocked = b.blocked;
    bv = b.boundingVolumeTests;
    leaves = b.leafTests;
  }
  state.counters["bv_tests"] = static_cast<double>(bv);
  state.counters["leaf_tests"] = static_cast<double>(leaves);
  state.SetLabel(std::string(kScenes[i]) + (s.problem.empty() ? "" : " (" + s.problem + ")") + (touching ? " touching" : " NOT touching") +
                 (blocked ? " BLOCKED" : ""));
  state.counters["part_triangles"] = static_cast<double>(p.mesh->triangleCount());
  state.counters["base_triangles"] = static_cast<double>(a.parts[*a.base].mesh->triangleCount());
}
BENCHMARK(BM_ChecksBundled)->DenseRange(0, 3)->Unit(benchmark::kMicrosecond);

// 10k-triangle part on the 250k-triangle base: 0 = mid-plate, 1 = CM 1 mm from the plate's edge (the
// support polygon is clipped), 2 = front face touching the wall.
void BM_ChecksLarge(benchmark::State& state) {
  CollisionWorld& w = largeWorld();
  const Support s = w.support(large().mate);
  const double x = state.range(0) == 0 ? 0.0 : state.range(0) == 1 ? -0.149 : 0.07;
  const Eigen::Isometry3d pose = at(x, 0.0, 0.035);
  bool touching = false, blocked = false;
  std::size_t bv = 0, leaves = 0, nblocked = 0, ncontacts = 0;
  for (auto _ : state) {
    touching = w.touching(s, pose).touching;
    const BlockResult b = w.blocked(s, pose, 1);
    blocked = b.blocked;
    nblocked += b.blocked ? 1 : 0;
    ncontacts += b.contacts.size();
    bv = b.boundingVolumeTests;
    leaves = b.leafTests;
  }
  state.counters["nblocked"] = static_cast<double>(nblocked);
  state.counters["ncontacts"] = static_cast<double>(ncontacts);
  state.counters["bv_tests"] = static_cast<double>(bv);
  state.counters["leaf_tests"] = static_cast<double>(leaves);
  state.SetLabel(std::string(state.range(0) == 0 ? "mid-plate" : state.range(0) == 1 ? "at the edge" : "at the wall") +
                 (touching ? ", touching" : ", NOT touching") + (blocked ? ", blocked" : ", free"));
}
BENCHMARK(BM_ChecksLarge)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);

void BM_TouchingOnlyLarge(benchmark::State& state) {
  CollisionWorld& w = largeWorld();
  const Support s = w.support(large().mate);
  const Eigen::Isometry3d pose = at(state.range(0) == 0 ? 0.0 : -0.149, 0.0, 0.035);
  for (auto _ : state) benchmark::DoNotOptimize(w.touching(s, pose));
}
BENCHMARK(BM_TouchingOnlyLarge)->DenseRange(0, 1)->Unit(benchmark::kMicrosecond);

// ---- filtered query against FCL's plain query on the same pair ----
struct FclPair {
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> a, b;
  static std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> bvh(const TriMesh& m) {
    auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
    std::vector<fcl::Triangle> tris;
    for (const auto& t : m.triangles)
      tris.emplace_back(static_cast<std::size_t>(t[0]), static_cast<std::size_t>(t[1]), static_cast<std::size_t>(t[2]));
    model->beginModel();
    model->addSubModel(m.vertices, tris);
    model->endModel();
    return model;
  }
};

// Pair: 0 = the 10k block pressed 0.5 mm into the wall of the 250k base (lifted 5 um off the plate, as the
// blocked check tests it); 1 = the bundled sleeve halfway down its shaft (coaxial contacts everywhere).
struct ComparePair {
  const Assembly* a = nullptr;
  std::unique_ptr<CollisionWorld> world;
  FclPair fcl;
  ObjectId part, base;
  Eigen::Isometry3d partPose, basePose;
  FilterMode mode = FilterMode::SkipCoplanar;
};
ComparePair& pair(int which) {
  static std::map<int, std::unique_ptr<ComparePair>> cache;
  auto& slot = cache[which];
  if (!slot) {
    slot = std::make_unique<ComparePair>();
    ComparePair& c = *slot;
    if (which == 0) {
      c.a = &large().a;
      c.partPose = at(0.0705, 0.0, 0.035 + 5e-6);
      c.mode = FilterMode::SkipCoplanar;
      c.part = ObjectId::part(1);
      c.base = ObjectId::part(0);
    } else {
      static Assembly sleeve = scene(1);
      const PartId sp = *sleeve.findPart("sleeve");
      sleeve.parts[sp].pose = at(0, 0, 0.1);
      c.a = &sleeve;
      c.partPose = sleeve.parts[sp].pose;
      c.mode = FilterMode::SkipCoaxial;
      c.part = ObjectId::part(sp);
      c.base = ObjectId::part(*sleeve.base);
    }
    c.world = std::make_unique<CollisionWorld>(*c.a);
    c.basePose = c.a->parts[c.base.index].pose;
    c.fcl.a = FclPair::bvh(*c.a->parts[c.part.index].mesh);
    c.fcl.b = FclPair::bvh(*c.a->parts[c.base.index].mesh);
  }
  return *slot;
}

void BM_PlainFcl(benchmark::State& state) {
  ComparePair& c = pair(static_cast<int>(state.range(0)));
  const bool all = state.range(1) == 1;
  fcl::CollisionRequestd req(all ? 100000 : 1, all);
  std::size_t n = 0;
  for (auto _ : state) {
    fcl::CollisionResultd res;
    fcl::collide(c.fcl.a.get(), c.partPose, c.fcl.b.get(), c.basePose, req, res);
    n = res.numContacts();
  }
  state.SetLabel(std::string(state.range(0) == 0 ? "block into wall" : "sleeve on shaft") + (all ? ", all contacts" : ", first contact"));
  state.counters["contacts"] = static_cast<double>(n);
}
BENCHMARK(BM_PlainFcl)->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMicrosecond);

void BM_Filtered(benchmark::State& state) {
  ComparePair& c = pair(static_cast<int>(state.range(0)));
  const bool all = state.range(1) == 1;
  QueryOptions o;
  o.mode = c.mode;
  o.maxContacts = all ? 100000 : 1;
  o.stopAtFirst = !all;
  o.dropTouching = state.range(2) == 1;
  std::size_t n = 0, filtered = 0;
  for (auto _ : state) {
    const QueryResult r = c.world->query(c.part, c.partPose, c.base, o);
    n = r.contacts.size();
    filtered = r.filtered;
  }
  state.SetLabel(std::string(state.range(0) == 0 ? "block into wall, " : "sleeve on shaft, ") + std::string(name(c.mode)) +
                 (o.dropTouching ? " + drop touching" : "") + (all ? ", all contacts" : ", first contact"));
  state.counters["contacts"] = static_cast<double>(n);
  state.counters["filtered"] = static_cast<double>(filtered);
}
BENCHMARK(BM_Filtered)->ArgsProduct({{0, 1}, {0, 1}, {0, 1}})->Unit(benchmark::kMicrosecond);

// ---- time of impact ----
// One 90 Hz step of the 10k block sliding at 1 m/s: 0 = nothing in reach, 1 = meets the wall in the step.
void BM_ToiSlideLarge(benchmark::State& state) {
  CollisionWorld& w = largeWorld();
  const Support s = w.support(large().mate);
  const Eigen::Isometry3d start = at(state.range(0) == 0 ? -0.05 : 0.07 - 0.005, 0.0, 0.035);
  const Motion m = axisSlide(start, Eigen::Vector3d::UnitX(), 1.0, 0.0, 1.0 / 90.0);
  MotionEvent ev;
  for (auto _ : state) ev = firstEventOnBase(w, s, m);
  state.SetLabel(state.range(0) == 0 ? "free step" : "hits the wall");
  state.counters["checks"] = ev.evaluations;
  state.counters["event"] = static_cast<double>(ev.kind);
}
BENCHMARK(BM_ToiSlideLarge)->DenseRange(0, 1)->Unit(benchmark::kMicrosecond);

// The bundled block dropped onto the table (exact box proxy): the 90 Hz step in which it lands, 0.25 g.
void BM_ToiDrop(benchmark::State& state) {
  static Assembly a = [] {
    Assembly s = scene(0);
    s.parts[*s.findPart("block")].pose = at(0.5, 0.2, 1.015);
    return s;
  }();
  const PartId block = *a.findPart("block");
  CollisionWorld w(a);
  dyn::Release r;
  r.position = a.parts[block].pose * w.centreOfMass(block);
  const Eigen::Vector3d g = 0.25 * dyn::worldGravity();
  const double tHit = std::sqrt(2.0 / (0.25 * kStandardGravity));
  const double h = 1.0 / 90.0, t0 = std::floor(tHit / h) * h;
  const Motion m = ballistic(r, g, w.centreOfMass(block), t0, t0 + h, w.maxRadius(ObjectId::part(block), w.centreOfMass(block)));
  MotionEvent ev;
  for (auto _ : state) ev = timeOfImpact(w, ObjectId::part(block), m);
  state.counters["distance_queries"] = ev.evaluations;
  state.counters["hit"] = ev.kind == EventKind::Contact ? 1 : 0;
}
BENCHMARK(BM_ToiDrop)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
