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

Motion sessionMotion(const std::shared_ptr<const sim::Scene>& scene, const sim::Session& session, double rate) {
  Motion m;
  m.name = "session";
  double next = 0.0;
  std::vector<Eigen::Isometry3d> last;
  double lastTime = 0.0;
  const auto sample = [&](double t, const sim::World& w) {
    std::vector<Eigen::Isometry3d> poses;
    poses.reserve(w.parts().size());
    for (const sim::PartRuntime& p : w.parts()) poses.push_back(p.pose);
    m.times.push_back(t);
    m.poses.push_back(std::move(poses));
  };
  const sim::World end = sim::replay(scene, session, [&](const sim::World& w) {
    if (m.times.empty()) {
      sample(0.0, w);
      next = 1.0 / rate;
    }
    if (w.time() + 1e-9 >= next) {
      sample(w.time(), w);
      next += 1.0 / rate;
    }
    lastTime = w.time();
  });
  if (m.times.empty() || lastTime > m.times.back() + 1e-9) sample(lastTime, end);
  return m;
}

Motion orderMotion(const Assembly& assembly, const eval::SequencePlan& plan, double stepSeconds, double rate) {
  Motion m;
  m.name = "order";
  const std::size_t n = assembly.parts.size();
  const std::vector<Eigen::Isometry3d> home = eval::homePoses(assembly);
  // Each part's step (its place in the order), and where it comes in from.
  std::vector<std::optional<double>> start(n);
  std::vector<Eigen::Vector3d> out(n, Eigen::Vector3d::UnitZ());
  for (std::size_t i = 0; i < plan.order.size(); ++i) {
    const PartId p = plan.order[i];
    start[p] = static_cast<double>(i) * stepSeconds;
    if (const eval::Direction* d = plan.wayOf(p)) out[p] = d->out;
    else if (const auto* s = plan.subAssemblyOf(p)) out[p] = s->out;
  }
  const double end = static_cast<double>(std::max<std::size_t>(plan.order.size(), 1)) * stepSeconds;
  for (PartId p = 0; p < n; ++p)
    if (!start[p]) start[p] = end;  // no order inserts it: shown at home at the end
  const auto poseAt = [&](PartId p, double t) {
    Eigen::Isometry3d pose = home[p];
    if (plan.base && p == *plan.base) return pose;
    const double s = std::clamp((t - *start[p]) / stepSeconds, 0.0, 1.0);
    // From out of the way: the part's own size and a little more.
    const double size = assembly.parts[p].mesh ? assembly.parts[p].mesh->bounds().diagonal().norm() : 0.05;
    const double away = (1.0 - s) * (1.0 - s) * (1.5 * size + 0.02);  // easing in: slower as it arrives
    pose.pretranslate(away * out[p]);
    return pose;
  };
  const int samples = std::max(1, static_cast<int>(std::ceil(end * rate)));
  for (int k = 0; k <= samples; ++k) {
    const double t = end * static_cast<double>(k) / samples;
    std::vector<Eigen::Isometry3d> poses(n);
    for (PartId p = 0; p < n; ++p) poses[p] = poseAt(p, t);
    m.times.push_back(t);
    m.poses.push_back(std::move(poses));
  }
  m.shown.assign(start.begin(), start.end());
  if (plan.base) m.shown[*plan.base].reset();
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
  const auto addNode = [&](const std::string& name, const Eigen::Isometry3d& pose, std::optional<std::size_t> mesh) {
    json node = {{"name", name},
                 {"translation", vec(pose.translation())},
                 {"rotation", quaternion(Eigen::Quaterniond(pose.linear()).normalized())}};
    if (mesh) node["mesh"] = *mesh;
    nodes.push_back(std::move(node));
    nodes[0]["children"].push_back(nodes.size() - 1);
    return nodes.size() - 1;
  };
  const bool moving = !motion.times.empty();
  std::vector<std::size_t> partNode(assembly.parts.size());
  for (PartId p = 0; p < assembly.parts.size(); ++p) {
    const Part& part = assembly.parts[p];
    const auto d = p < scene.partDrawable.size() ? scene.partDrawable[p] : std::nullopt;
    std::optional<std::size_t> mesh;
    if (d && part.mesh) mesh = meshFor(part.mesh, scene.drawables[*d].color, part.product.empty() ? part.name : part.product);
    partNode[p] = addNode(part.name, moving ? motion.poses.front()[p] : part.pose, mesh);
  }
  for (const view::Drawable& d : scene.drawables) {
    if (d.kind != view::DrawableKind::Environment || d.backdrop) continue;
    const EnvironmentObject& e = assembly.environment[d.index];
    if (e.mesh) addNode(e.name, e.pose, meshFor(e.mesh, d.color, e.name));
  }

  if (moving) {
    if (motion.poses.size() != motion.times.size())
      throw std::invalid_argument("glb: a motion's poses and times differ in number");
    json samplers = json::array(), channels = json::array();
    std::map<std::vector<std::size_t>, std::size_t> timeAccessors;  // by the keys kept
    const auto timesOf = [&](const std::vector<std::size_t>& keys) {
      auto it = timeAccessors.find(keys);
      if (it != timeAccessors.end()) return it->second;
      std::vector<float> t;
      for (const std::size_t k : keys) t.push_back(static_cast<float>(motion.times[k]));
      return timeAccessors.emplace(keys, buffer.floats(t, 1, std::nullopt)).first->second;
    };
    for (PartId p = 0; p < assembly.parts.size(); ++p) {
      std::vector<Eigen::Vector3d> at;
      std::vector<Eigen::Quaterniond> turn;
      for (const auto& frame : motion.poses) {
        at.push_back(frame[p].translation());
        Eigen::Quaterniond q(frame[p].linear());
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
        const std::vector<std::size_t> keys = thinned(at, turn, motion.times, options);
        std::vector<float> translation, rotation;
        for (const std::size_t k : keys) {
          for (int c = 0; c < 3; ++c) translation.push_back(static_cast<float>(at[k][c]));
          for (const double c : {turn[k].x(), turn[k].y(), turn[k].z(), turn[k].w()}) rotation.push_back(static_cast<float>(c));
        }
        const std::size_t input = timesOf(keys);
        samplers.push_back(
            {{"input", input}, {"output", buffer.floats(translation, 3, std::nullopt)}, {"interpolation", "LINEAR"}});
        channels.push_back({{"sampler", samplers.size() - 1}, {"target", {{"node", partNode[p]}, {"path", "translation"}}}});
        samplers.push_back({{"input", input}, {"output", buffer.floats(rotation, 4, std::nullopt)}, {"interpolation", "LINEAR"}});
        channels.push_back({{"sampler", samplers.size() - 1}, {"target", {{"node", partNode[p]}, {"path", "rotation"}}}});
      }
      if (p < motion.shown.size() && motion.shown[p] && *motion.shown[p] > motion.times.front()) {
        // Hidden (scaled to nothing) until its time.
        const std::vector<float> t{static_cast<float>(motion.times.front()), static_cast<float>(*motion.shown[p])};
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
