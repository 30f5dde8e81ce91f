#include "step_result_parser.hpp"

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <numbers>

#include "step_result.hpp"

namespace vaw::step {
namespace {

using nlohmann::json;

[[noreturn]] void malformed(const std::string& why) { throw MalformedResult(why); }

// Bounds nlohmann's recursive CBOR parse: a SAX pass that stops at the first container nested too deep.
class DepthCheck final : public nlohmann::json_sax<json> {
 public:
  bool null() override { return true; }
  bool boolean(bool) override { return true; }
  bool number_integer(number_integer_t) override { return true; }
  bool number_unsigned(number_unsigned_t) override { return true; }
  bool number_float(number_float_t, const string_t&) override { return true; }
  bool string(string_t&) override { return true; }
  bool binary(binary_t&) override { return true; }
  bool start_object(std::size_t) override { return enter(); }
  bool key(string_t&) override { return true; }
  bool end_object() override { return leave(); }
  bool start_array(std::size_t) override { return enter(); }
  bool end_array() override { return leave(); }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) override {
    why = e.what();
    return false;
  }
  bool tooDeep = false;
  std::string why;

 private:
  bool enter() {
    tooDeep = ++depth_ > kMaxResultDepth;
    return !tooDeep;
  }
  bool leave() {
    --depth_;
    return true;
  }
  int depth_ = 0;
};

double finite(const json& j, const char* what) {
  const double v = j.get<double>();
  if (!std::isfinite(v)) malformed(std::string(what) + " is not finite");
  return v;
}

Eigen::Vector3d vec3(const json& j, const char* what) {
  if (!j.is_array() || j.size() != 3) malformed(std::string(what) + " is not 3 numbers");
  return {finite(j[0], what), finite(j[1], what), finite(j[2], what)};
}

Eigen::Vector3f color(const json& j) {
  const Eigen::Vector3d c = vec3(j, "a colour");
  return c.cwiseMax(0.0).cwiseMin(1.0).cast<float>();
}

template <typename T>
std::vector<T> unblob(const json& j, const char* what) {
  if (!j.is_binary()) malformed(std::string(what) + " is not a byte string");
  const auto& bytes = j.get_binary();
  if (bytes.size() % (3 * sizeof(T)) != 0) malformed(std::string(what) + " is not whole triples");
  std::vector<T> v(bytes.size() / sizeof(T));
  if (!v.empty()) std::memcpy(v.data(), bytes.data(), v.size() * sizeof(T));
  return v;
}

std::shared_ptr<const CadSolid> solidFrom(const json& j) {
  auto s = std::make_shared<CadSolid>();
  s->product = j.at("product").get<std::string>();
  s->volume = finite(j.at("volume"), "a volume");
  s->centroid = vec3(j.at("centroid"), "a centroid");
  const json& I = j.at("inertia");
  if (!I.is_array() || I.size() != 9) malformed("an inertia tensor is not 9 numbers");
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) s->inertiaUnitDensity(r, c) = finite(I[static_cast<std::size_t>(3 * r + c)], "an inertia tensor");
  s->surfaceArea = finite(j.at("area"), "an area");
  s->deflection = finite(j.at("deflection"), "a deflection");
  if (j.contains("color")) s->color = color(j.at("color"));
  const auto v = unblob<double>(j.at("vertices"), "vertices");
  const auto t = unblob<std::int32_t>(j.at("triangles"), "triangles");
  s->mesh.vertices.reserve(v.size() / 3);
  for (std::size_t i = 0; i + 2 < v.size(); i += 3) {
    if (!(std::isfinite(v[i]) && std::isfinite(v[i + 1]) && std::isfinite(v[i + 2]))) malformed("a vertex is not finite");
    s->mesh.vertices.emplace_back(v[i], v[i + 1], v[i + 2]);
  }
  const auto vertexCount = static_cast<std::int64_t>(s->mesh.vertices.size());
  s->mesh.triangles.reserve(t.size() / 3);
  for (std::size_t i = 0; i + 2 < t.size(); i += 3) {
    for (std::size_t k = 0; k < 3; ++k)
      if (t[i + k] < 0 || t[i + k] >= vertexCount) malformed("a triangle refers to no vertex");
    s->mesh.triangles.emplace_back(t[i], t[i + 1], t[i + 2]);
  }
  const json& faces = j.at("faces");
  if (!faces.is_array()) malformed("faces is not a list");
  for (const json& jf : faces) {
    CadFace f;
    switch (static_cast<SurfaceKind>(jf.at("surface").get<int>())) {
      case SurfaceKind::Plane: f.surface = CadFace::Surface::Plane; break;
      case SurfaceKind::Cylinder: f.surface = CadFace::Surface::Cylinder; break;
      case SurfaceKind::Cone: f.surface = CadFace::Surface::Cone; break;
      case SurfaceKind::Other: f.surface = CadFace::Surface::Other; break;
      default: malformed("a face's surface kind is unknown");
    }
    f.area = finite(jf.at("area"), "a face's area");
    f.firstTriangle = jf.at("first").get<std::size_t>();
    f.triangleCount = jf.at("count").get<std::size_t>();
    if (f.firstTriangle > s->mesh.triangles.size() || f.triangleCount > s->mesh.triangles.size() - f.firstTriangle)
      malformed("a face's triangles are not the solid's");
    if (jf.contains("point")) f.point = vec3(jf.at("point"), "a face's point");
    if (jf.contains("direction")) {
      const Eigen::Vector3d d = vec3(jf.at("direction"), "a face's direction");
      if (!(d.norm() > 0.5)) malformed("a face's direction is not a unit vector");
      f.direction = d.normalized();
    }
    f.fromSpline = jf.value("fromSpline", false);
    f.radius = finite(jf.value("radius", json(0.0)), "a face's radius");
    f.convex = jf.value("convex", true);
    f.axialMin = finite(jf.value("axialMin", json(0.0)), "a face's extent");
    f.axialMax = finite(jf.value("axialMax", json(0.0)), "a face's extent");
    f.halfAngle = finite(jf.value("halfAngle", json(0.0)), "a cone's half angle");
    if (f.surface == CadFace::Surface::Cone && !(f.halfAngle > 0.0 && f.halfAngle < 0.5 * std::numbers::pi))
      malformed("a cone's half angle is not between 0 and 90 degrees");
    s->faces.push_back(f);
  }
  // The reader writes Open CASCADE's faces as they are: the core makes a split cylinder one surface.
  return s;
}

ImportedNode nodeFrom(const json& j, const std::vector<std::shared_ptr<const CadSolid>>& solids) {
  ImportedNode n;
  n.name = j.at("name").get<std::string>();
  if (j.contains("location")) {
    const json& l = j.at("location");
    if (!l.is_array() || l.size() != 12) malformed("a location is not 12 numbers");
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) m(r, c) = finite(l[static_cast<std::size_t>(4 * r + c)], "a location");
    n.location = Eigen::Isometry3d(m);
  }
  if (j.contains("color")) n.color = color(j.at("color"));
  if (j.contains("solid")) {
    const auto i = j.at("solid").get<std::size_t>();
    if (i >= solids.size()) malformed("an instance refers to no solid");
    n.solid = solids[i];
  }
  if (j.contains("children"))
    for (const json& c : j.at("children")) n.children.push_back(nodeFrom(c, solids));
  return n;
}

}  // namespace

std::variant<ImportedMesh, ReaderError> parseResult(std::span<const std::uint8_t> cbor) {
  DepthCheck check;
  if (!json::sax_parse(cbor.begin(), cbor.end(), &check, json::input_format_t::cbor)) {
    if (check.tooDeep) malformed("nested deeper than " + std::to_string(kMaxResultDepth) + " levels");
    malformed(check.why.empty() ? std::string("not CBOR") : check.why);
  }
  try {
    const json j = json::from_cbor(cbor.begin(), cbor.end());
    if (!j.is_object()) malformed("not a map");
    const int version = j.value("version", 0);
    if (version != kResultVersion)
      malformed("version " + std::to_string(version) + " where this plugin reads " + std::to_string(kResultVersion) +
                " (a reader from another build beside the plugin?)");
    if (j.contains("error")) {
      const json& e = j.at("error");
      return ReaderError{e.at("field").get<std::string>(), e.at("expected").get<std::string>(), e.at("found").get<std::string>()};
    }
    ImportedMesh out;
    std::vector<std::shared_ptr<const CadSolid>> solids;
    for (const json& s : j.at("solids")) solids.push_back(solidFrom(s));
    out.root = nodeFrom(j.at("root"), solids);
    out.warnings = j.value("warnings", std::vector<std::string>{});
    out.format = j.value("format", std::string("STEP"));
    if (j.contains("unit")) out.declaredUnit = j.at("unit").get<std::string>();
    return out;
  } catch (const json::exception& e) {
    malformed(e.what());
  }
}

}  // namespace vaw::step
