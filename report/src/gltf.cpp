// glTF 2.0 binary (the Khronos specification, "GLB File Format Specification"): a 12-byte header, a JSON
// chunk and a binary chunk, each 4-byte aligned.
#include "vaw/report/gltf.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <string_view>

#include <nlohmann/json.hpp>

#include "vaw/atomic_file.hpp"
#include "vaw/error.hpp"
#include "vaw/sim/world.hpp"
#include "vaw/view/frame.hpp"

namespace vaw::report {

namespace {

using json = nlohmann::json;

constexpr std::uint32_t kArrayBuffer = 34962, kElementArrayBuffer = 34963;
constexpr std::uint32_t kFloat = 5126, kUnsignedInt = 5125;

// The binary chunk and the views and accessors into it.
class Buffer {
 public:
  // A view of `bytes` (4-byte aligned, so that any accessor's components are aligned); its index.
  std::size_t view(const void* bytes, std::size_t size, std::optional<std::uint32_t> target) {
    while (data_.size() % 4 != 0) data_.push_back(0);
    json v = {{"buffer", 0}, {"byteOffset", data_.size()}, {"byteLength", size}};
    if (target) v["target"] = *target;
    const auto* b = static_cast<const std::uint8_t*>(bytes);
    data_.insert(data_.end(), b, b + size);
    views_.push_back(std::move(v));
    return views_.size() - 1;
  }
  // Floats, `width` to an element (1: SCALAR, 3: VEC3, 4: VEC4), with their bounds; the accessor's index.
  std::size_t floats(const std::vector<float>& values, int width, std::optional<std::uint32_t> target) {
    const std::size_t count = values.size() / static_cast<std::size_t>(width);
    json lo = json::array(), hi = json::array();
    for (int c = 0; c < width; ++c) {
      float a = std::numeric_limits<float>::infinity(), b = -a;
      for (std::size_t i = 0; i < count; ++i) {
        a = std::min(a, values[i * static_cast<std::size_t>(width) + static_cast<std::size_t>(c)]);
        b = std::max(b, values[i * static_cast<std::size_t>(width) + static_cast<std::size_t>(c)]);
      }
      lo.push_back(a);
      hi.push_back(b);
    }
    static constexpr std::string_view kType[] = {"", "SCALAR", "VEC2", "VEC3", "VEC4"};
    const std::size_t v = view(values.data(), values.size() * sizeof(float), target);
    accessors_.push_back(
        {{"bufferView", v}, {"componentType", kFloat}, {"count", count}, {"type", kType[width]}, {"min", lo}, {"max", hi}});
    return accessors_.size() - 1;
  }
  std::size_t indices(const std::vector<std::uint32_t>& values) {
    const std::size_t v = view(values.data(), values.size() * sizeof(std::uint32_t), kElementArrayBuffer);
    accessors_.push_back({{"bufferView", v}, {"componentType", kUnsignedInt}, {"count", values.size()}, {"type", "SCALAR"}});
    return accessors_.size() - 1;
  }
  void into(json& doc) {
    while (data_.size() % 4 != 0) data_.push_back(0);
    doc["buffers"] = json::array({{{"byteLength", data_.size()}}});
    doc["bufferViews"] = std::move(views_);
    doc["accessors"] = std::move(accessors_);
  }
  [[nodiscard]] const std::vector<std::uint8_t>& data() const { return data_; }

 private:
  std::vector<std::uint8_t> data_;
  json views_ = json::array(), accessors_ = json::array();
};

float linear(float srgb) { return srgb <= 0.04045f ? srgb / 12.92f : std::pow((srgb + 0.055f) / 1.055f, 2.4f); }

json quaternion(const Eigen::Quaterniond& q) { return {q.x(), q.y(), q.z(), q.w()}; }
json vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// Keys of one part's track kept so that linear interpolation between them stays within the tolerances of
// every sample dropped (greedy: each key as far on as the samples between allow).
std::vector<std::size_t> thinned(const std::vector<Eigen::Vector3d>& at, const std::vector<Eigen::Quaterniond>& turn,
                                 const std::vector<double>& t, const GltfOptions& o) {
  std::vector<std::size_t> keep{0};
  const std::size_t n = t.size();
  std::size_t from = 0;
  while (from + 1 < n) {
    std::size_t to = from + 1;
    // A key at least every 256 samples, which bounds the work on a long, slow stretch.
    while (to + 1 < n && to - from < 256) {
      const std::size_t next = to + 1;
      bool fits = true;
      for (std::size_t k = from + 1; k < next && fits; ++k) {
        const double s = (t[k] - t[from]) / (t[next] - t[from]);
        fits = (at[from] + s * (at[next] - at[from]) - at[k]).norm() <= o.positionTolerance &&
               turn[from].slerp(s, turn[next]).angularDistance(turn[k]) <= o.angleTolerance;
      }
      if (!fits) break;
      to = next;
    }
    keep.push_back(to);
    from = to;
  }
  return keep;
}

}  // namespace

namespace {

// Appends (t, pose) to a track, leaving out the samples in the middle of a stretch at rest: a stretch keeps
// its first and last key, so that the interpolation between keys is the rest itself.
class TrackWriter {
 public:
  explicit TrackWriter(Track& track) : track_(track) {}
  void add(double t, const Eigen::Isometry3d& pose) {
    const std::size_t n = track_.times.size();
    if (n >= 2 && same(track_.poses[n - 1], pose) && same(track_.poses[n - 2], pose)) {
      track_.times[n - 1] = t;  // the rest goes on: its last key moves on with it
      return;
    }
    track_.times.push_back(t);
    track_.poses.push_back(pose);
  }

 private:
  static bool same(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) { return a.matrix() == b.matrix(); }
  Track& track_;
};

}  // namespace

Motion sessionMotion(const std::shared_ptr<const sim::Scene>& scene, const sim::Session& session, double rate) {
  Motion m;
  m.name = "session";
  m.parts.resize(scene->assembly().parts.size());
  std::vector<TrackWriter> writers(m.parts.begin(), m.parts.end());
  double next = 0.0, last = -1.0;
  const auto sample = [&](double t, const sim::World& w) {
    for (const sim::PartRuntime& p : w.parts()) writers[p.id].add(t, p.pose);
    last = t;
  };
  double now = 0.0;
  const sim::World end = sim::replay(scene, session, [&](const sim::World& w) {
    if (last < 0.0) {
      sample(0.0, w);
      next = 1.0 / rate;
    }
    if (w.time() + 1e-9 >= next) {
      sample(w.time(), w);
      next += 1.0 / rate;
    }
    now = w.time();
  });
  if (last < 0.0 || now > last + 1e-9) sample(now, end);
  m.duration = std::max(0.0, last);
  return m;
}

Eigen::Vector3d orderApproach(const Assembly& assembly, const eval::SequencePlan& plan, PartId p) {
  if ((plan.base && p == *plan.base) || std::find(plan.order.begin(), plan.order.end(), p) == plan.order.end())
    return Eigen::Vector3d::Zero();
  Eigen::Vector3d out = Eigen::Vector3d::UnitZ();
  if (const eval::Direction* d = plan.wayOf(p)) out = d->out;
  else if (const auto* s = plan.subAssemblyOf(p)) out = s->out;
  const double size = assembly.parts[p].mesh ? assembly.parts[p].mesh->bounds().diagonal().norm() : 0.05;
  return (1.5 * size + 0.02) * out.normalized();
}

Motion orderMotion(const Assembly& assembly, const eval::SequencePlan& plan, double stepSeconds, double rate) {
  Motion m;
  m.name = "order";
  const std::size_t n = assembly.parts.size();
  m.parts.resize(n);
  const std::vector<Eigen::Isometry3d> home = eval::homePoses(assembly);
  m.duration = static_cast<double>(std::max<std::size_t>(plan.order.size(), 1)) * stepSeconds;
  std::vector<bool> inOrder(n, false);
  // Four fifths of its step on the way, the rest at home: a step's end shows it in place, the next not yet.
  const double flight = 0.8 * stepSeconds;
  const int samples = std::max(2, static_cast<int>(std::ceil(flight * rate)));
  for (std::size_t i = 0; i < plan.order.size(); ++i) {
    const PartId p = plan.order[i];
    inOrder[p] = true;
    Track& track = m.parts[p];
    if (plan.base && p == *plan.base) {
      track.times = {0.0};
      track.poses = {home[p]};
      continue;
    }
    // From out of the way, slowing as it arrives.
    const Eigen::Vector3d away = orderApproach(assembly, plan, p);
    const double start = static_cast<double>(i) * stepSeconds;
    track.shown = start;
    for (int k = 0; k <= samples; ++k) {
      const double s = static_cast<double>(k) / samples;
      Eigen::Isometry3d pose = home[p];
      pose.pretranslate((1.0 - s) * (1.0 - s) * away);
      track.times.push_back(start + s * flight);
      track.poses.push_back(pose);
    }
  }
  // Parts no order inserts: at home at the end.
  for (PartId p = 0; p < n; ++p)
    if (!inOrder[p]) {
      m.parts[p].times = {0.0};
      m.parts[p].poses = {home[p]};
      m.parts[p].shown = m.duration;
    }
  return m;
}

std::vector<std::uint8_t> glb(const Assembly& assembly, const Motion& motion, const GltfOptions& options) {
  const view::SceneDescription scene = view::describe(assembly);
  Buffer buffer;
  json doc;
  doc["asset"] = {{"version", "2.0"}, {"generator", "vaw"}};
  json meshes = json::array(), materials = json::array(), nodes = json::array();
  // The root: the scene's z-up turned to glTF's y-up (a quarter turn about x).
  nodes.push_back({{"name", assembly.name.empty() ? std::string("assembly") : assembly.name},
                   {"rotation", quaternion(Eigen::Quaterniond(Eigen::AngleAxisd(-0.5 * M_PI, Eigen::Vector3d::UnitX())))},
                   {"children", json::array()}});
  std::map<const TriMesh*, std::pair<std::size_t, std::size_t>> geometry;  // positions, indices
  std::map<std::tuple<float, float, float>, std::size_t> materialOf;
  std::map<std::pair<const TriMesh*, std::size_t>, std::size_t> meshOf;
  const auto meshFor = [&](const std::shared_ptr<const TriMesh>& mesh, const view::Rgb& colour, const std::string& name) {
    auto g = geometry.find(mesh.get());
    if (g == geometry.end()) {
      std::vector<float> positions;
      positions.reserve(3 * mesh->vertices.size());
      for (const Eigen::Vector3d& v : mesh->vertices)
        for (int c = 0; c < 3; ++c) positions.push_back(static_cast<float>(v[c]));
      std::vector<std::uint32_t> indices;
      const auto count = static_cast<int>(mesh->vertices.size());
      for (const Eigen::Vector3i& t : mesh->triangles)
        if (t.minCoeff() >= 0 && t.maxCoeff() < count)
          for (int c = 0; c < 3; ++c) indices.push_back(static_cast<std::uint32_t>(t[c]));
      const std::size_t p = buffer.floats(positions, 3, kArrayBuffer);
      const std::size_t i = buffer.indices(indices);
      g = geometry.emplace(mesh.get(), std::pair{p, i}).first;
    }
    const auto key = std::tuple{colour.r, colour.g, colour.b};
    auto mat = materialOf.find(key);
    if (mat == materialOf.end()) {
      materials.push_back({{"pbrMetallicRoughness",
                            {{"baseColorFactor", {linear(colour.r), linear(colour.g), linear(colour.b), 1.0}},
                             {"metallicFactor", 0.0},
                             {"roughnessFactor", 0.7}}}});
      mat = materialOf.emplace(key, materials.size() - 1).first;
    }
    auto it = meshOf.find({mesh.get(), mat->second});
    if (it == meshOf.end()) {
      meshes.push_back({{"name", name},
                        {"primitives", json::array({{{"attributes", {{"POSITION", g->second.first}}},
                                                     {"indices", g->second.second},
                                                     {"material", mat->second}}})}});
      it = meshOf.emplace(std::pair{mesh.get(), mat->second}, meshes.size() - 1).first;
    }
    return it->second;
  };
  const auto addNode = [&](const std::string& name, const Eigen::Isometry3d& pose, std::optional<std::size_t> mesh,
                           bool environment) {
    // The name again in extras: viewers make node names safe for their animation paths (three.js turns
    // "pin #2" into "pin_#2"); extras come through as they are.
    json node = {{"name", name},
                 {"translation", vec(pose.translation())},
                 {"rotation", quaternion(Eigen::Quaterniond(pose.linear()).normalized())},
                 {"extras", {{"name", name}}}};
    if (environment) node["extras"]["environment"] = true;
    if (mesh) node["mesh"] = *mesh;
    nodes.push_back(std::move(node));
    nodes[0]["children"].push_back(nodes.size() - 1);
    return nodes.size() - 1;
  };
  const bool moving = !motion.parts.empty();
  if (moving && motion.parts.size() != assembly.parts.size())
    throw std::invalid_argument("glb: a motion with a track per part of the assembly");
  for (const Track& t : motion.parts)
    if (t.times.empty() || t.times.size() != t.poses.size())
      throw std::invalid_argument("glb: a track without keys, or keys without poses");
  std::vector<std::size_t> partNode(assembly.parts.size());
  for (PartId p = 0; p < assembly.parts.size(); ++p) {
    const Part& part = assembly.parts[p];
    const auto d = p < scene.partDrawable.size() ? scene.partDrawable[p] : std::nullopt;
    std::optional<std::size_t> mesh;
    if (d && part.mesh) mesh = meshFor(part.mesh, scene.drawables[*d].color, part.product.empty() ? part.name : part.product);
    partNode[p] = addNode(part.name, moving ? motion.parts[p].poses.front() : part.pose, mesh, false);
  }
  for (const view::Drawable& d : scene.drawables) {
    if (d.kind != view::DrawableKind::Environment || d.backdrop) continue;
    const EnvironmentObject& e = assembly.environment[d.index];
    if (e.mesh) addNode(e.name, e.pose, meshFor(e.mesh, d.color, e.name), true);
  }

  if (moving) {
    json samplers = json::array(), channels = json::array();
    for (PartId p = 0; p < assembly.parts.size(); ++p) {
      const Track& track = motion.parts[p];
      std::vector<Eigen::Vector3d> at;
      std::vector<Eigen::Quaterniond> turn;
      for (const Eigen::Isometry3d& pose : track.poses) {
        at.push_back(pose.translation());
        Eigen::Quaterniond q(pose.linear());
        q.normalize();
        if (!turn.empty() && turn.back().dot(q) < 0.0) q.coeffs() = -q.coeffs();  // the short way round
        turn.push_back(q);
      }
      const bool moves =
          std::any_of(at.begin(), at.end(),
                      [&](const Eigen::Vector3d& x) { return (x - at.front()).norm() > options.positionTolerance; }) ||
          std::any_of(turn.begin(), turn.end(),
                      [&](const Eigen::Quaterniond& q) { return q.angularDistance(turn.front()) > options.angleTolerance; });
      if (moves) {
        const std::vector<std::size_t> keys = thinned(at, turn, track.times, options);
        std::vector<float> times, translation, rotation;
        for (const std::size_t k : keys) {
          times.push_back(static_cast<float>(track.times[k]));
          for (int c = 0; c < 3; ++c) translation.push_back(static_cast<float>(at[k][c]));
          for (const double c : {turn[k].x(), turn[k].y(), turn[k].z(), turn[k].w()}) rotation.push_back(static_cast<float>(c));
        }
        const std::size_t input = buffer.floats(times, 1, std::nullopt);
        samplers.push_back(
            {{"input", input}, {"output", buffer.floats(translation, 3, std::nullopt)}, {"interpolation", "LINEAR"}});
        channels.push_back({{"sampler", samplers.size() - 1}, {"target", {{"node", partNode[p]}, {"path", "translation"}}}});
        samplers.push_back({{"input", input}, {"output", buffer.floats(rotation, 4, std::nullopt)}, {"interpolation", "LINEAR"}});
        channels.push_back({{"sampler", samplers.size() - 1}, {"target", {{"node", partNode[p]}, {"path", "rotation"}}}});
      }
      if (track.shown && *track.shown > 0.0) {
        // Hidden (scaled to nothing) until its time.
        const std::vector<float> t{0.0f, static_cast<float>(*track.shown)};
        const std::vector<float> s{0.0f, 0.0f, 0.0f, 1.0f, 1.0f, 1.0f};
        samplers.push_back({{"input", buffer.floats(t, 1, std::nullopt)},
                            {"output", buffer.floats(s, 3, std::nullopt)},
                            {"interpolation", "STEP"}});
        channels.push_back({{"sampler", samplers.size() - 1}, {"target", {{"node", partNode[p]}, {"path", "scale"}}}});
        nodes[partNode[p]]["scale"] = {0.0, 0.0, 0.0};
      }
    }
    if (!channels.empty())
      doc["animations"] = json::array({{{"name", motion.name}, {"samplers", samplers}, {"channels", channels}}});
  }
  doc["scene"] = 0;
  doc["scenes"] = json::array({{{"name", nodes[0]["name"]}, {"nodes", {0}}}});
  doc["nodes"] = std::move(nodes);
  if (!meshes.empty()) doc["meshes"] = std::move(meshes);
  if (!materials.empty()) doc["materials"] = std::move(materials);
  buffer.into(doc);

  std::string text = doc.dump();
  while (text.size() % 4 != 0) text.push_back(' ');
  const std::vector<std::uint8_t>& bin = buffer.data();
  std::vector<std::uint8_t> out;
  const auto word = [&](std::uint32_t w) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(w >> (8 * i)));
  };
  const auto total = static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + bin.size());
  word(0x46546C67u);  // "glTF"
  word(2);
  word(total);
  word(static_cast<std::uint32_t>(text.size()));
  word(0x4E4F534Au);  // "JSON"
  out.insert(out.end(), text.begin(), text.end());
  word(static_cast<std::uint32_t>(bin.size()));
  word(0x004E4942u);  // "BIN"
  out.insert(out.end(), bin.begin(), bin.end());
  return out;
}

void writeGlb(const std::filesystem::path& file, const Assembly& assembly, const Motion& motion, const GltfOptions& options) {
  const std::vector<std::uint8_t> bytes = glb(assembly, motion, options);
  writeFileAtomically(file, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace vaw::report
