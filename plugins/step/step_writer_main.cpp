// vaw-step-write: writes a closed triangle mesh as one named STEP solid (AP214, a manifold solid B-rep of
// plane faces, or with --faceted a faceted B-rep), in which coplanar triangles are merged into polygons: a
// voxel surface becomes its plane regions, not millions of triangles. The STEP plugin runs it as a child, as it does the reader, so that a
// mesh too large for the machine ends this process and not the window (docs/step.md, docs/swept-volume.md).
//
//   vaw-step-write MESH.stl --out FILE.step --unit mm|inch|m [--name NAME] [--faceted] [--parent PID] [--memory-limit-mb MB]
//
// The advanced B-rep (the default) is every CAD system's ordinary solid: faces on planes, bounded by loops
// of edges between vertices. A faceted B-rep bounds each plane face by a loop of points and has no edge or
// vertex entities; the same solid in about a third of the file (the 1 mm volume of a gear's carry: 18.8 MB
// against 6.3 MB, docs/benchmarks.md), which some CAD systems take in as a faceted body rather than as an
// ordinary solid.
//
// MESH is a binary STL in the unit given, whose triangles face outwards and share their corners (a closed
// manifold). Progress goes to stdout as the reader's does ("progress 0.350 making faces"). Exit 0: FILE
// written. Exit 3: it could not be; one line on stderr says why. Exit 5: it needed more memory than its
// limit. Exit 6: its parent was gone. Exit 2: bad arguments.
//
// The file is written here entity by entity rather than through Open CASCADE's STEP translator: a solid of
// plane faces and straight edges needs a few entity types, and the translator took the gearbox gear's 1 mm
// swept volume 7.6 s, 551 MB and 35 MB of file for what this writes in a fraction of each (every direction,
// vector and plane written once, each edge's line starting at its first vertex's point; docs/benchmarks.md).
// The tests read every file back through Open CASCADE's reader.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cerrno>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <new>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "step_child.hpp"

namespace {

[[noreturn]] void refuse(const std::string& why) {
  std::fprintf(stderr, "%s\n", why.c_str());
  std::exit(3);
}

void progress(double fraction, const std::string& stage) {
  std::printf("progress %.3f %s\n", fraction, stage.c_str());
  std::fflush(stdout);
}

using Vec = Eigen::Vector3d;

struct Mesh {
  std::vector<Vec> point;
  std::vector<std::array<int, 3>> tri;
};

// A binary STL, its corners joined where their coordinates are the same bits (the mesh was written with
// shared corners, so a shared corner is written identically each time).
Mesh readStl(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) refuse(file + ": cannot be read");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < 84) refuse(file + ": not a binary STL (shorter than its header)");
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);
  if (bytes.size() != 84 + 50 * static_cast<std::size_t>(count))
    refuse(file + ": not a binary STL (" + std::to_string(bytes.size()) + " bytes for " + std::to_string(count) + " triangles)");
  if (count == 0) refuse(file + ": no triangles");
  Mesh m;
  m.tri.resize(count);
  std::unordered_map<std::string_view, int> index;
  index.reserve(count);
  for (std::uint32_t t = 0; t < count; ++t)
    for (int c = 0; c < 3; ++c) {
      const char* at = bytes.data() + 84 + 50 * static_cast<std::size_t>(t) + 12 + 12 * c;
      const auto [it, fresh] = index.try_emplace(std::string_view(at, 12), static_cast<int>(m.point.size()));
      if (fresh) {
        float xyz[3];
        std::memcpy(xyz, at, 12);
        if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2])) refuse(file + ": triangle " + std::to_string(t + 1) + " has a corner that is not a finite point");
        m.point.emplace_back(xyz[0], xyz[1], xyz[2]);
      }
      m.tri[t][static_cast<std::size_t>(c)] = it->second;
    }
  return m;
}

// The B-rep: each face a largest region of coplanar triangles joined across their edges (a voxel surface's
// plane patches), bounded by one outer loop and its holes. The edges between two regions are straight runs
// of the mesh's edges, each run one B-rep edge shared by the two faces on either side, ending wherever a
// third region meets or the run turns: the faces meet edge to edge with no vertex of one lying inside
// another's edge (no T-junctions), so the shell is closed by construction, with no sewing and no later
// merging. A mesh of no coplanar neighbours becomes one face per triangle.
struct Brep {
  struct Run {
    int from, to;  // mesh vertices
  };
  struct Face {
    Vec normal;
    std::vector<std::vector<std::pair<int, bool>>> loops;  // the outer loop first; each a run and whether it goes from -> to
  };
  std::vector<Run> runs;
  std::vector<Face> faces;
};

Brep brepOf(const Mesh& mesh) {
  const int nodes = static_cast<int>(mesh.point.size()), count = static_cast<int>(mesh.tri.size());
  Eigen::AlignedBox3d box;
  for (const Vec& p : mesh.point) box.extend(p);
  const double tol = 1e-6 * box.diagonal().norm();  // STL's single-precision coordinates
  const auto at = [&](int v) -> const Vec& { return mesh.point[static_cast<std::size_t>(v)]; };
  const auto corner = [&](int t, int k) { return mesh.tri[static_cast<std::size_t>(t)][static_cast<std::size_t>(k)]; };
  std::vector<Vec> normal(static_cast<std::size_t>(count));
  for (int t = 0; t < count; ++t) {
    const Vec v = (at(corner(t, 1)) - at(corner(t, 0))).cross(at(corner(t, 2)) - at(corner(t, 0)));
    if (v.norm() <= 1e-12) refuse("triangle " + std::to_string(t + 1) + " has no area");
    normal[static_cast<std::size_t>(t)] = v.normalized();
  }
  const auto key = [](int a, int b) { return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b)); };

  // Each edge's two triangles; anything else is not a closed manifold.
  std::unordered_map<std::uint64_t, std::array<int, 2>> sides;
  sides.reserve(static_cast<std::size_t>(count) * 2);
  for (int t = 0; t < count; ++t)
    for (int k = 0; k < 3; ++k) {
      auto [it, fresh] = sides.try_emplace(key(corner(t, k), corner(t, (k + 1) % 3)), std::array<int, 2>{t, -1});
      if (fresh) continue;
      if (it->second[1] >= 0) refuse("edge of triangle " + std::to_string(t + 1) + " has more than two triangles: not a closed manifold");
      it->second[1] = t;
    }
  for (const auto& [k, s] : sides)
    if (s[1] < 0) refuse("the mesh has an open edge: not a closed manifold");

  // Regions: coplanar triangles joined across an edge.
  progress(0.05, "merging coplanar triangles");
  std::vector<int> parent(static_cast<std::size_t>(count));
  for (int t = 0; t < count; ++t) parent[static_cast<std::size_t>(t)] = t;
  const auto find = [&](int t) {
    while (parent[static_cast<std::size_t>(t)] != t) t = parent[static_cast<std::size_t>(t)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(t)])];
    return t;
  };
  const auto coplanar = [&](int a, int b) {
    const Vec& n = normal[static_cast<std::size_t>(a)];
    if ((n - normal[static_cast<std::size_t>(b)]).norm() > 1e-6) return false;
    const Vec& p = at(corner(a, 0));
    for (int k = 0; k < 3; ++k)
      if (std::abs((at(corner(b, k)) - p).dot(n)) > tol) return false;
    return true;
  };
  for (const auto& [k, s] : sides)
    if (coplanar(s[0], s[1])) parent[static_cast<std::size_t>(find(s[0]))] = find(s[1]);
  std::vector<int> region(static_cast<std::size_t>(count));
  for (int t = 0; t < count; ++t) region[static_cast<std::size_t>(t)] = find(t);
  const auto crease = [&](const std::array<int, 2>& s) { return region[static_cast<std::size_t>(s[0])] != region[static_cast<std::size_t>(s[1])]; };
  progress(0.2, "finding the plane regions' borders");

  // The crease graph: mesh edges between two regions, chained into straight runs through vertices where
  // only the run itself passes.
  std::vector<std::vector<int>> creaseAt(static_cast<std::size_t>(nodes));  // vertex -> its crease neighbours
  for (const auto& [k, s] : sides)
    if (crease(s)) {
      const int a = static_cast<int>(k >> 32), b = static_cast<int>(k & 0xffffffffu);
      creaseAt[static_cast<std::size_t>(a)].push_back(b);
      creaseAt[static_cast<std::size_t>(b)].push_back(a);
    }
  Brep brep;
  std::unordered_map<std::uint64_t, int> runOf;  // crease edge -> its run
  const auto straightOn = [&](int prev, int v) {
    // The run goes on through v when v joins only it and it does not turn there.
    const auto& n = creaseAt[static_cast<std::size_t>(v)];
    if (n.size() != 2) return -1;
    const int next = n[0] == prev ? n[1] : n[0];
    const Vec in = at(v) - at(prev), out = at(next) - at(v);
    return in.cross(out).norm() <= tol * in.norm() && in.dot(out) > 0.0 ? next : -1;
  };
  // Runs in the mesh's order of edges, so that the file is the same for the same mesh.
  std::vector<std::uint64_t> creases;
  for (const auto& [k, s] : sides)
    if (crease(s)) creases.push_back(k);
  std::sort(creases.begin(), creases.end());
  for (const std::uint64_t k : creases) {
    if (runOf.contains(k)) continue;
    const int a = static_cast<int>(k >> 32), b = static_cast<int>(k & 0xffffffffu);
    std::vector<int> chain = {a, b};
    for (int prev = a, v = b, next; (next = straightOn(prev, v)) >= 0 && next != chain.front(); prev = v, v = next) chain.push_back(next);
    for (int prev = b, v = a, next; (next = straightOn(prev, v)) >= 0 && next != chain.back(); prev = v, v = next) chain.insert(chain.begin(), next);
    const int id = static_cast<int>(brep.runs.size());
    for (std::size_t i = 0; i + 1 < chain.size(); ++i) runOf[key(chain[i], chain[i + 1])] = id;
    brep.runs.push_back({chain.front(), chain.back()});
  }
  progress(0.4, "making " + std::to_string(brep.runs.size()) + " edges into faces");

  // Each region's border, as its triangles wind it (outward normal: the outer loop counterclockwise, holes
  // clockwise), walked into loops; where the region touches itself at a vertex the walk turns most to the
  // left there, so each loop stays simple.
  std::map<int, std::vector<std::pair<int, int>>> border;  // region -> half-edges (from, to)
  for (int t = 0; t < count; ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = corner(t, k), b = corner(t, (k + 1) % 3);
      if (crease(sides.at(key(a, b)))) border[region[static_cast<std::size_t>(t)]].emplace_back(a, b);
    }
  for (auto& [r, halves] : border) {
    const Vec n = normal[static_cast<std::size_t>(r)];
    std::unordered_map<int, std::vector<std::size_t>> leaving;
    for (std::size_t i = 0; i < halves.size(); ++i) leaving[halves[i].first].push_back(i);
    std::vector<char> used(halves.size(), 0);
    Brep::Face face{n, {{}}};
    int outer = 0;
    for (std::size_t first = 0; first < halves.size(); ++first) {
      if (used[first]) continue;
      std::vector<std::size_t> loop;
      for (std::size_t h = first;;) {
        used[h] = 1;
        loop.push_back(h);
        const auto [from, to] = halves[h];
        const Vec in = at(to) - at(from);
        std::size_t best = halves.size();
        double bestTurn = -10.0;
        for (const std::size_t o : leaving[to]) {
          if (used[o] && o != first) continue;
          const Vec out = at(halves[o].second) - at(to);
          const double turn = std::atan2(n.dot(in.cross(out)), in.dot(out));
          if (turn > bestTurn) bestTurn = turn, best = o;
        }
        if (best == halves.size()) refuse("a plane region's border does not close");
        if (best == first) break;
        h = best;
      }
      // The loop as runs: started where a run begins, consecutive half-edges of one run one edge.
      std::size_t start = 0;
      while (start < loop.size()) {
        const auto [from, to] = halves[loop[start]];
        const auto [pf, pt] = halves[loop[(start + loop.size() - 1) % loop.size()]];
        if (runOf.at(key(from, to)) != runOf.at(key(pf, pt))) break;
        ++start;
      }
      if (start == loop.size()) refuse("a plane region's border is one straight run");
      std::vector<std::pair<int, bool>> edges;
      double area = 0.0;  // twice the loop's signed area about n
      const Vec& o = at(halves[loop[start]].first);
      for (std::size_t i = 0; i < loop.size(); ++i) {
        const auto [from, to] = halves[loop[(start + i) % loop.size()]];
        area += n.dot((at(from) - o).cross(at(to) - o));
        const int id = runOf.at(key(from, to));
        const auto& before = halves[loop[(start + i + loop.size() - 1) % loop.size()]];
        if (i > 0 && runOf.at(key(before.first, before.second)) == id) continue;  // the same run goes on
        edges.emplace_back(id, from == brep.runs[static_cast<std::size_t>(id)].from);
      }
      if (area > 0.0) {
        ++outer;
        face.loops.front() = std::move(edges);
      } else {
        face.loops.push_back(std::move(edges));
      }
    }
    if (outer != 1) refuse("a plane region with " + std::to_string(outer) + " outer borders");
    brep.faces.push_back(std::move(face));
  }
  return brep;
}

// Part 21's REAL: the shortest digits that read back as the same number (as a float where it is one, the
// STL's coordinates), with the decimal point the format requires ("1." and "1.5E-05", never "1" or "1.5e-05").
void real(std::string& out, double value) {
  char b[32];
  const auto f = static_cast<float>(value);
  const auto r = f == value ? std::to_chars(b, b + sizeof b, f) : std::to_chars(b, b + sizeof b, value);
  const std::string_view s(b, static_cast<std::size_t>(r.ptr - b));
  const std::size_t e = s.find('e');
  const std::string_view mantissa = s.substr(0, e);
  out += mantissa;
  if (mantissa.find('.') == std::string_view::npos) out += '.';
  if (e != std::string_view::npos) {
    out += 'E';
    out += s.substr(e + 1);
  }
}

// A Part 21 string: quotes and backslashes doubled, anything beyond ASCII as \X2\ UTF-16 \X0\.
std::string quoted(const std::string& utf8) {
  std::string out = "'";
  for (std::size_t i = 0; i < utf8.size();) {
    const auto c = static_cast<unsigned char>(utf8[i]);
    if (c < 0x80) {
      if (c == '\'' || c == '\\') out += static_cast<char>(c);
      out += c >= 0x20 ? static_cast<char>(c) : ' ';
      ++i;
      continue;
    }
    const int extra = c >= 0xF0 ? 3 : c >= 0xE0 ? 2 : c >= 0xC0 ? 1 : 0;
    std::uint32_t cp = c & (0x3Fu >> extra);
    for (int k = 1; k <= extra && i + static_cast<std::size_t>(k) < utf8.size(); ++k) cp = (cp << 6) | (static_cast<unsigned char>(utf8[i + static_cast<std::size_t>(k)]) & 0x3Fu);
    i += static_cast<std::size_t>(extra) + 1;
    std::vector<std::uint32_t> units;
    if (cp >= 0x10000) {
      units = {0xD800 + ((cp - 0x10000) >> 10), 0xDC00 + ((cp - 0x10000) & 0x3FF)};
    } else {
      units = {cp};
    }
    out += "\\X2\\";
    char h[8];
    for (const std::uint32_t u : units) {
      std::snprintf(h, sizeof h, "%04X", static_cast<unsigned>(u));
      out += h;
    }
    out += "\\X0\\";
  }
  return out + "'";
}

// The file's entities, numbered as they are added; one that is referred to many times is written once.
class Part21 {
 public:
  int add(std::string_view type, const std::string& params) {
    const int id = next_++;
    body_ += '#';
    body_ += std::to_string(id);
    body_ += '=';
    body_ += type;
    body_ += '(';
    body_ += params;
    body_ += ");\n";
    return id;
  }
  int point(const Vec& p) {
    std::string s = "'',(";
    for (int i = 0; i < 3; ++i) {
      if (i > 0) s += ',';
      real(s, p[i]);
    }
    return add("CARTESIAN_POINT", s + ")");
  }
  int direction(const Vec& d) {
    const std::array<double, 3> k{d.x(), d.y(), d.z()};
    if (const auto it = directions_.find(k); it != directions_.end()) return it->second;
    std::string s = "'',(";
    for (int i = 0; i < 3; ++i) {
      if (i > 0) s += ',';
      real(s, d[i] == 0.0 ? 0.0 : d[i]);
    }
    return directions_[k] = add("DIRECTION", s + ")");
  }
  int vector(const Vec& d) {
    const int dir = direction(d);
    if (const auto it = vectors_.find(dir); it != vectors_.end()) return it->second;
    return vectors_[dir] = add("VECTOR", "''," + ref(dir) + ",1.");
  }
  static std::string ref(int id) { return "#" + std::to_string(id); }
  [[nodiscard]] const std::string& body() const { return body_; }
  [[nodiscard]] int next() const { return next_; }

 private:
  std::string body_;
  int next_ = 1;
  std::map<std::array<double, 3>, int> directions_;
  std::unordered_map<int, int> vectors_;
};

// Any unit direction across n, the same for the same n.
Vec across(const Vec& n) {
  Eigen::Index least = 0;
  n.cwiseAbs().minCoeff(&least);
  return n.cross(Vec::Unit(least)).normalized();
}

std::string timestamp() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char b[32];
  std::strftime(b, sizeof b, "%Y-%m-%dT%H:%M:%S", &utc);
  return b;
}

std::string stepFile(const Mesh& mesh, const Brep& brep, const std::string& unit, const std::string& name, const std::string& fileName, bool faceted) {
  Part21 f;
  const auto ref = Part21::ref;
  // The product, so a CAD system lists the solid by its name, and the units the numbers are in.
  const int app = f.add("APPLICATION_CONTEXT", "'core data for automotive mechanical design processes'");
  f.add("APPLICATION_PROTOCOL_DEFINITION", "'international standard','automotive_design',2000," + ref(app));
  const int productContext = f.add("PRODUCT_CONTEXT", "''," + ref(app) + ",'mechanical'");
  const int product = f.add("PRODUCT", quoted(name) + "," + quoted(name) + ",''," + "(" + ref(productContext) + ")");
  f.add("PRODUCT_RELATED_PRODUCT_CATEGORY", "'part',$,(" + ref(product) + ")");
  const int formation = f.add("PRODUCT_DEFINITION_FORMATION", "'',''," + ref(product));
  const int definitionContext = f.add("PRODUCT_DEFINITION_CONTEXT", "'part definition'," + ref(app) + ",'design'");
  const int definition = f.add("PRODUCT_DEFINITION", "'design',''," + ref(formation) + "," + ref(definitionContext));
  const int shape = f.add("PRODUCT_DEFINITION_SHAPE", "'',''," + ref(definition));
  int length = 0;
  if (unit == "inch") {
    const int mm = f.add("", "LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.)");
    const int measure = f.add("LENGTH_MEASURE_WITH_UNIT", "LENGTH_MEASURE(25.4)," + ref(mm));
    const int exponents = f.add("DIMENSIONAL_EXPONENTS", "1.,0.,0.,0.,0.,0.,0.");
    length = f.add("", "CONVERSION_BASED_UNIT('INCH'," + ref(measure) + ") LENGTH_UNIT() NAMED_UNIT(" + ref(exponents) + ")");
  } else {
    length = f.add("", std::string("LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(") + (unit == "mm" ? ".MILLI." : "$") + ",.METRE.)");
  }
  const int angle = f.add("", "NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.)");
  const int solidAngle = f.add("", "NAMED_UNIT(*) SI_UNIT($,.STERADIAN.) SOLID_ANGLE_UNIT()");
  Eigen::AlignedBox3d box;
  for (const Vec& p : mesh.point) box.extend(p);
  std::string accuracy;
  real(accuracy, 1e-6 * box.diagonal().norm());
  const int uncertainty = f.add("UNCERTAINTY_MEASURE_WITH_UNIT", "LENGTH_MEASURE(" + accuracy + ")," + ref(length) + ",'distance_accuracy_value','confusion accuracy'");
  const int context = f.add("", "GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((" + ref(uncertainty) +
                                    ")) GLOBAL_UNIT_ASSIGNED_CONTEXT((" + ref(length) + "," + ref(angle) + "," + ref(solidAngle) +
                                    ")) REPRESENTATION_CONTEXT('Context #1','3D Context with UNIT and UNCERTAINTY')");
  const int origin = f.add("AXIS2_PLACEMENT_3D", "''," + ref(f.point(Vec::Zero())) + "," + ref(f.direction(Vec::UnitZ())) + "," + ref(f.direction(Vec::UnitX())));

  std::unordered_map<int, int> pointOf;  // mesh vertex -> its CARTESIAN_POINT
  const auto pointAt = [&](int v) {
    if (const auto it = pointOf.find(v); it != pointOf.end()) return it->second;
    return pointOf[v] = f.point(mesh.point[static_cast<std::size_t>(v)]);
  };

  // The topology of an advanced B-rep: a vertex at each run's ends, an edge per run. Edges on one line share
  // it (a voxel surface's edges lie on a few grid lines), the line through the first such edge's first
  // vertex. A faceted B-rep has neither: each loop is the points where its runs begin, in order, and as a
  // neighbour's corner on a face's border ends a run there (brepOf), two faces' loops meet at the same
  // points and the shell closes.
  std::vector<int> edge;
  if (!faceted) {
    std::unordered_map<int, int> vertex;  // mesh vertex -> its VERTEX_POINT
    const auto vertexOf = [&](int v) {
      if (const auto it = vertex.find(v); it != vertex.end()) return it->second;
      return vertex[v] = f.add("VERTEX_POINT", "''," + ref(pointAt(v)));
    };
    std::map<std::pair<int, std::array<float, 3>>, int> lines;  // (direction, the line's point nearest the origin) -> LINE
    edge.resize(brep.runs.size());
    for (std::size_t i = 0; i < brep.runs.size(); ++i) {
      const auto& run = brep.runs[i];
      const Vec& a = mesh.point[static_cast<std::size_t>(run.from)];
      const int from = vertexOf(run.from), to = vertexOf(run.to);
      const Vec d = (mesh.point[static_cast<std::size_t>(run.to)] - a).normalized();
      const Vec nearest = a - a.dot(d) * d;
      const int vector = f.vector(d);
      const auto [it, fresh] = lines.try_emplace({vector, {static_cast<float>(nearest.x()), static_cast<float>(nearest.y()), static_cast<float>(nearest.z())}}, 0);
      if (fresh) it->second = f.add("LINE", "''," + ref(pointAt(run.from)) + "," + ref(vector));
      edge[i] = f.add("EDGE_CURVE", "''," + ref(from) + "," + ref(to) + "," + ref(it->second) + ",.T.");
    }
  }
  progress(0.6, "writing " + std::to_string(brep.faces.size()) + " faces");
  std::map<std::pair<int, double>, int> planes;
  std::string faceList;
  for (const Brep::Face& face : brep.faces) {
    std::string bounds;
    for (std::size_t l = 0; l < face.loops.size(); ++l) {
      std::string list;
      for (const auto& [run, forward] : face.loops[l]) {
        if (!list.empty()) list += ',';
        const auto& r = brep.runs[static_cast<std::size_t>(run)];
        list += ref(faceted ? pointAt(forward ? r.from : r.to)
                            : f.add("ORIENTED_EDGE", "'',*,*," + ref(edge[static_cast<std::size_t>(run)]) + (forward ? ",.T." : ",.F.")));
      }
      const int loop = f.add(faceted ? "POLY_LOOP" : "EDGE_LOOP", "'',(" + list + ")");
      if (!bounds.empty()) bounds += ',';
      bounds += ref(f.add(l == 0 ? "FACE_OUTER_BOUND" : "FACE_BOUND", "''," + ref(loop) + ",.T."));
    }
    // Faces on one plane share it: the plane through the first such face's first vertex.
    const auto& first = brep.runs[static_cast<std::size_t>(face.loops.front().front().first)];
    const int v = face.loops.front().front().second ? first.from : first.to;
    const int normal = f.direction(face.normal);
    const auto [it, fresh] = planes.try_emplace({normal, static_cast<double>(static_cast<float>(face.normal.dot(mesh.point[static_cast<std::size_t>(v)])))}, 0);
    if (fresh) {
      const int placement = f.add("AXIS2_PLACEMENT_3D", "''," + ref(pointAt(v)) + "," + ref(normal) + "," + ref(f.direction(across(face.normal))));
      it->second = f.add("PLANE", "''," + ref(placement));
    }
    if (!faceList.empty()) faceList += ',';
    faceList += ref(f.add(faceted ? "FACE_SURFACE" : "ADVANCED_FACE", "'',(" + bounds + ")," + ref(it->second) + ",.T."));
  }
  const int shell = f.add("CLOSED_SHELL", "'',(" + faceList + ")");
  const int solid = f.add(faceted ? "FACETED_BREP" : "MANIFOLD_SOLID_BREP", quoted(name) + "," + ref(shell));
  const int representation = f.add(faceted ? "FACETED_BREP_SHAPE_REPRESENTATION" : "ADVANCED_BREP_SHAPE_REPRESENTATION",
                                    "''," + std::string("(") + ref(origin) + "," + ref(solid) + ")," + ref(context));
  f.add("SHAPE_DEFINITION_REPRESENTATION", ref(shape) + "," + ref(representation));

  std::string out = "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('vaw solid'),'2;1');\nFILE_NAME(" + quoted(fileName) + ",'" + timestamp() +
                    "',(''),(''),'vaw-step-write','vaw','');\nFILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\nENDSEC;\nDATA;\n";
  out.reserve(out.size() + f.body().size() + 32);
  out += f.body();
  out += "ENDSEC;\nEND-ISO-10303-21;\n";
  return out;
}

}  // namespace

int usage() {
  std::fprintf(stderr, "usage: vaw-step-write MESH.stl --out FILE.step --unit mm|inch|m [--name NAME] [--faceted] [--parent PID] [--memory-limit-mb MB]\n");
  return 2;
}

int main(int argc, char** argv) {
  std::string in, out, unit, name = "vaw solid";
  long parent = 0;
  double memoryMB = 0.0;
  bool faceted = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    try {
      if ((a == "--out" || a == "--unit" || a == "--name") && i + 1 < argc) {
        (a == "--out" ? out : a == "--unit" ? unit : name) = argv[++i];
      } else if (a == "--faceted") {
        faceted = true;
      } else if (a == "--parent" && i + 1 < argc) {
        parent = std::stol(argv[++i]);
      } else if (a == "--memory-limit-mb" && i + 1 < argc) {
        memoryMB = std::stod(argv[++i]);
      } else if (!a.empty() && a[0] != '-' && in.empty()) {
        in = a;
      } else {
        return usage();
      }
    } catch (const std::exception&) {
      return usage();
    }
  }
  if (in.empty() || out.empty() || (unit != "mm" && unit != "inch" && unit != "m")) return usage();
  if (!vaw::step::containChild(parent, memoryMB)) return 6;
  progress(0.0, "reading the mesh");
  try {
    const Mesh mesh = readStl(in);
    const Brep brep = brepOf(mesh);
    const std::string text = stepFile(mesh, brep, unit, name, std::filesystem::path(out).filename().string(), faceted);
    progress(0.9, "writing the file");
    std::FILE* file = std::fopen(out.c_str(), "wb");
    if (file == nullptr) refuse(out + ": cannot write: " + std::strerror(errno));
    const bool written = std::fwrite(text.data(), 1, text.size(), file) == text.size();
    if (std::fclose(file) != 0 || !written) refuse(out + ": cannot write: " + std::strerror(errno));
    progress(1.0, "done");
    return 0;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "it needed more memory than the writer's limit of %.0f MB\n", memoryMB);
    return 5;
  } catch (const std::exception& e) {
    refuse(e.what());
  }
}
