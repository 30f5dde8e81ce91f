#include "vaw/sim/session.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>

#include "../base/json_node.hpp"
#include "vaw/hash.hpp"
#include "vaw/atomic_file.hpp"
#include "vaw/dynamics/hinge.hpp"
#include "vaw/limits.hpp"
#include "vaw/units.hpp"

namespace vaw::sim {

using ::vaw::detail::Json;
using ::vaw::detail::Node;

namespace {

// ---- input script ----

Eigen::Isometry3d readPose(const Node& n, double L, bool allowGrab) {
  if (allowGrab) n.allowOnly({"position", "rotation", "grab"});
  else n.allowOnly({"position", "rotation"});
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = n.get("position").position(L);
  if (auto r = n.opt("rotation")) pose.linear() = r->rotation();
  return pose;
}

// The speed the world would see between two keyframes of a channel (m/s); a jump at one instant is
// infinitely fast.
double speedBetween(double t0, const Eigen::Vector3d& p0, double t1, const Eigen::Vector3d& p1) {
  const double d = (p1 - p0).norm();
  if (d == 0.0) return 0.0;
  return t1 > t0 ? d / (t1 - t0) : std::numeric_limits<double>::infinity();
}

std::string speedText(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, std::isfinite(v) ? "%.4g m/s" : "a jump at one instant", v);
  return buf;
}

template <class T>
struct Key {
  double t;
  T value;
};

template <class T>
using Channel = std::vector<Key<T>>;

Eigen::Isometry3d interpolate(const Channel<Eigen::Isometry3d>& c, double t) {
  if (t <= c.front().t) return c.front().value;
  if (t >= c.back().t) return c.back().value;
  std::size_t i = 1;
  while (c[i].t < t) ++i;
  const auto& a = c[i - 1];
  const auto& b = c[i];
  const double x = (t - a.t) / (b.t - a.t);
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.translation() = a.value.translation() + x * (b.value.translation() - a.value.translation());
  const Eigen::Quaterniond qa(a.value.linear()), qb(b.value.linear());
  out.linear() = qa.slerp(x, qb).toRotationMatrix();
  return out;
}

double interpolate(const Channel<double>& c, double t) {
  if (t <= c.front().t) return c.front().value;
  if (t >= c.back().t) return c.back().value;
  std::size_t i = 1;
  while (c[i].t < t) ++i;
  const double x = (t - c[i - 1].t) / (c[i].t - c[i - 1].t);
  return c[i - 1].value + x * (c[i].value - c[i - 1].value);
}

bool held(const Channel<bool>& c, double t) {
  bool v = false;
  for (const auto& k : c) {
    if (k.t > t) break;
    v = k.value;
  }
  return v;
}

// ---- JSON of poses and settings (exact round trip) ----

Json poseJson(const Eigen::Isometry3d& p) {
  Json a = Json::array();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) a.push_back(p.matrix()(r, c));
  return a;
}

Eigen::Isometry3d poseFrom(const Node& n) {
  if (!n.json().is_array() || n.size() != 12) n.fail("12 numbers: a 3 x 4 pose matrix, row by row");
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) p.matrix()(r, c) = n.at(static_cast<std::size_t>(r * 4 + c)).number();
  const Eigen::Matrix3d R = p.linear();
  if (!((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-9 && R.determinant() > 0.0))
    n.fail("a pose whose 3 x 3 part is a rotation (orthonormal within 1e-9, determinant +1)");
  if (!(p.translation().cwiseAbs().maxCoeff() <= limits::kMaxCoordinate))
    n.fail("a position within " + std::to_string(static_cast<int>(limits::kMaxCoordinate)) + " m of the origin (the world bound)");
  return p;
}

Json handJson(const HandInput& h) {
  Json j{{"pose", poseJson(h.pose)}, {"grab", h.grab}};
  if (h.target) j["target"] = *h.target;
  if (h.velocity) {
    const auto& v = *h.velocity;
    j["velocity"] = Json::array({v.linear.x(), v.linear.y(), v.linear.z(), v.angular.x(), v.angular.y(), v.angular.z()});
  }
  return j;
}

bool boolean(const Node& n) {
  if (!n.json().is_boolean()) n.fail("true or false");
  return n.json().get<bool>();
}

PartId partIndex(const Node& n) {
  const int i = n.integer();
  if (i < 0) n.fail("a part index (0 or more, in scene order)");
  return static_cast<PartId>(i);
}

HandInput handFrom(const Node& n, bool targets) {
  if (targets) n.allowOnly({"pose", "grab", "target", "velocity"});
  else n.allowOnly({"pose", "grab"});
  HandInput h;
  h.pose = poseFrom(n.get("pose"));
  h.grab = boolean(n.get("grab"));
  if (auto t = n.opt("target")) h.target = partIndex(*t);
  if (auto v = n.opt("velocity")) {
    if (!v->json().is_array() || v->size() != 6) v->fail("6 numbers: linear (m/s) then angular (rad/s) velocity, world");
    interact::Twist tw;
    for (int i = 0; i < 3; ++i) {
      tw.linear[i] = v->at(static_cast<std::size_t>(i)).number();
      tw.angular[i] = v->at(static_cast<std::size_t>(i + 3)).number();
    }
    h.velocity = tw;
  }
  return h;
}

Json hoistJson(const HoistInput& h) { return Json{{"engaged", h.engaged}, {"height", h.height}, {"yaw", h.yaw}}; }

HoistInput hoistFrom(const Node& h) {
  h.allowOnly({"engaged", "height", "yaw"});
  HoistInput out;
  out.engaged = boolean(h.get("engaged"));
  out.height = h.get("height").number(-limits::kMaxCoordinate, limits::kMaxCoordinate, "m");
  out.yaw = h.get("yaw").number();
  return out;
}

bool sameTwist(const std::optional<interact::Twist>& a, const std::optional<interact::Twist>& b) {
  return a.has_value() == b.has_value() && (!a || (a->linear == b->linear && a->angular == b->angular));
}
bool sameHand(const HandInput& a, const HandInput& b) {
  return a.grab == b.grab && a.target == b.target && a.pose.matrix() == b.pose.matrix() && sameTwist(a.velocity, b.velocity);
}
bool sameHoist(const HoistInput& a, const HoistInput& b) {
  return a.engaged == b.engaged && a.height == b.height && a.yaw == b.yaw;
}

Json frictionJson(const FrictionValues& f) {
  return Json{{"static", f.staticFriction}, {"kinetic", f.kineticFriction}, {"rotational", f.rotationalFriction}};
}

FrictionValues frictionFrom(const Node& n) {
  n.allowOnly({"static", "kinetic", "rotational"});
  return {n.get("static").number(), n.get("kinetic").number(), n.get("rotational").number()};
}

Json gravityJson(const dyn::GravityScales& g) {
  return Json{{"free_flight", g.freeFlight}, {"slide", g.slide}, {"rotation", g.rotation}};
}

dyn::GravityScales gravityFrom(const Node& g) {
  g.allowOnly({"free_flight", "slide", "rotation"});
  dyn::GravityScales out;
  out.freeFlight = g.get("free_flight").number(0.0, limits::kMaxGravityScale, "");
  out.slide = g.get("slide").number(0.0, limits::kMaxGravityScale, "");
  out.rotation = g.get("rotation").number(0.0, limits::kMaxGravityScale, "");
  return out;
}

dyn::Method methodFrom(const Node& m) {
  const auto method = dyn::parseMethod(m.string(), dyn::Hinge::kMethods);
  if (!method) m.fail("a method a rotation about an axis supports: " + dyn::describe(dyn::Hinge::kMethods));
  return *method;
}

Json editJson(const EditRecord& r) {
  Json j{{"step", r.step}};
  if (const auto* g = std::get_if<GravityEdit>(&r.edit)) {
    j["type"] = "gravity";
    j["gravity_scale"] = gravityJson(g->scales);
  } else if (const auto* m = std::get_if<MaterialFrictionEdit>(&r.edit)) {
    j["type"] = "material-friction";
    j["material"] = m->material;
    j["friction"] = frictionJson(m->friction);
  } else if (const auto* p = std::get_if<PartFrictionEdit>(&r.edit)) {
    j["type"] = "part-friction";
    j["part"] = p->part;
    j["friction"] = p->friction ? frictionJson(*p->friction) : Json(nullptr);
  } else if (const auto* me = std::get_if<MethodEdit>(&r.edit)) {
    j["type"] = "method";
    j["rotation_method"] = std::string(dyn::name(me->rotation));
  } else if (const auto* re = std::get_if<RateEdit>(&r.edit)) {
    j["type"] = "rate";
    j["rate"] = re->rate;
  }
  return j;
}

EditRecord editFrom(const Node& n) {
  n.requireObject();
  EditRecord r;
  const Node stepNode = n.get("step");
  const int step = stepNode.integer();
  if (step < 0) stepNode.fail("a step number (0 or more)");
  r.step = static_cast<std::uint64_t>(step);
  const Node type = n.get("type");
  const std::string t = type.string();
  if (t == "gravity") {
    n.allowOnly({"step", "type", "gravity_scale"});
    r.edit = GravityEdit{gravityFrom(n.get("gravity_scale"))};
  } else if (t == "material-friction") {
    n.allowOnly({"step", "type", "material", "friction"});
    r.edit = MaterialFrictionEdit{n.get("material").string(), frictionFrom(n.get("friction"))};
  } else if (t == "part-friction") {
    n.allowOnly({"step", "type", "part", "friction"});
    PartFrictionEdit e;
    e.part = partIndex(n.get("part"));
    const Node f = n.get("friction");
    if (!f.json().is_null()) e.friction = frictionFrom(f);
    r.edit = e;
  } else if (t == "method") {
    n.allowOnly({"step", "type", "rotation_method"});
    r.edit = MethodEdit{methodFrom(n.get("rotation_method"))};
  } else if (t == "rate") {
    n.allowOnly({"step", "type", "rate"});
    r.edit = RateEdit{n.get("rate").number(limits::kMinRate, limits::kMaxRate, "Hz")};
  } else {
    type.fail("an edit type: gravity, material-friction, part-friction, method or rate");
  }
  return r;
}

Json settingsJson(const Settings& s) {
  Json j{{"rate", s.rate},
              {"gravity_scale", gravityJson(s.gravity)},
              {"rotation_method", std::string(dyn::name(s.rotationMethod))},
              {"release", {{"estimator", s.release.estimator == interact::ReleaseEstimator::WindowedFit ? "windowed-fit" : "two-instance"},
                           {"window", s.release.window}}},
              {"recognize", {{"distance", s.recognizeDistance}, {"angle", s.recognizeAngle}}},
              {"place", {{"distance", s.placeDistance}, {"angle", s.placeAngle}}},
              {"grab_reach", s.grabReach},
              {"inertial_forces", s.inertialForces},
              {"rotation_model_tolerance", s.rotationModelTolerance}};
  // Written only when on, so sessions of scenes without it are as they were.
  if (s.placeAtRest) j["place"]["at_rest"] = true;
  if (s.hoist) j["hoist"] = {{"x", s.hoist->position.x()}, {"y", s.hoist->position.y()}, {"reach", s.hoist->reach}};
  return j;
}

Settings settingsFrom(const Node& n) {
  Settings s;
  s.rate = n.get("rate").number(limits::kMinRate, limits::kMaxRate, "Hz");
  s.gravity = gravityFrom(n.get("gravity_scale"));
  s.rotationMethod = methodFrom(n.get("rotation_method"));
  const Node r = n.get("release");
  const Node est = r.get("estimator");
  if (est.string() == "windowed-fit") s.release.estimator = interact::ReleaseEstimator::WindowedFit;
  else if (est.string() == "two-instance") s.release.estimator = interact::ReleaseEstimator::TwoInstance;
  else est.fail("windowed-fit or two-instance");
  s.release.window = r.get("window").number(0.001, 1.0, "s");
  s.recognizeDistance = n.get("recognize").get("distance").number(0.0, limits::kMaxReach, "m");
  s.recognizeAngle = n.get("recognize").get("angle").number(0.0, 180.0, "degrees");
  s.placeDistance = n.get("place").get("distance").number(0.0, limits::kMaxReach, "m");
  s.placeAngle = n.get("place").get("angle").number(0.0, 180.0, "degrees");
  if (auto a = n.get("place").opt("at_rest")) s.placeAtRest = boolean(*a);
  s.grabReach = n.get("grab_reach").number(0.0, limits::kMaxReach, "m");
  s.inertialForces = boolean(n.get("inertial_forces"));
  s.rotationModelTolerance = n.get("rotation_model_tolerance").number(1e-9, 180.0, "degrees");
  if (auto h = n.opt("hoist")) {
    h->allowOnly({"x", "y", "reach"});
    s.hoist = HoistPlacement{{h->get("x").number(-limits::kMaxCoordinate, limits::kMaxCoordinate, "m"),
                              h->get("y").number(-limits::kMaxCoordinate, limits::kMaxCoordinate, "m")},
                             h->get("reach").number(0.0, limits::kMaxReach, "m")};
  }
  return s;
}

std::string csvEscape(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

}  // namespace

std::vector<Input> loadInputScript(const std::filesystem::path& file, Settings& settings) {
  const Json json = ::vaw::detail::readJsonFile(file);
  const std::string fileName = file.string();
  const Node root(json, "", fileName);
  root.requireFormat("vaw-inputs");
  root.allowOnly({"format", "version", "units", "rate", "duration", "keyframes", "description", "hoist_at"});
  if (auto d = root.opt("description")) (void)d->string();
  const Node version = root.get("version");
  if (version.integer() != kInputsFormatVersion) version.fail("version " + std::to_string(kInputsFormatVersion));
  double L = 1.0;
  if (auto u = root.opt("units")) {
    if (u->string() == "mm") L = 1e-3;
    else if (u->string() != "m") u->fail("\"m\" or \"mm\"");
  }
  if (auto r = root.opt("rate")) settings.rate = r->number(limits::kMinRate, limits::kMaxRate, "Hz");
  if (auto ha = root.opt("hoist_at")) {
    if (!ha->json().is_array() || ha->size() != 2) ha->fail("[x, y]: where the hoist's vertical line stands");
    const Eigen::Vector2d xy = Eigen::Vector2d(ha->at(0).number(), ha->at(1).number()) * L;
    if (!(xy.cwiseAbs().maxCoeff() <= limits::kMaxCoordinate)) ha->fail("[x, y] within the world bound of 1000 m");
    settings.hoist = HoistPlacement{xy, HoistPlacement{}.reach};
  }
  const Node durationNode = root.get("duration");
  const double duration = durationNode.number(0.0, limits::kMaxDuration, "s");
  // Counted in double first: a long duration at a high rate must not overflow the step count.
  const double stepCount = std::round(duration * settings.rate);
  if (!(stepCount >= 1.0 && stepCount <= static_cast<double>(limits::kMaxSteps)))
    durationNode.failWith("a duration of 1 to " + std::to_string(limits::kMaxSteps) + " steps at " + std::to_string(settings.rate) + " Hz",
                          std::to_string(stepCount) + " steps");
  const Node keys = root.get("keyframes");
  keys.requireArray();
  Channel<Eigen::Isometry3d> pose[3];  // left, right, base
  Channel<bool> grab[2], engaged;
  Channel<double> height, yaw;
  double last = -1e300;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const Node k = keys.at(i);
    k.requireObject();
    k.allowOnly({"t", "left", "right", "base", "hoist"});
    const Node tn = k.get("t");
    const double t = tn.number(0.0, limits::kMaxDuration, "s");
    if (t < last) tn.fail("a time not before the previous keyframe's (" + std::to_string(last) + " s)");
    last = t;
    const char* handNames[2] = {"left", "right"};
    // A channel may not move faster than a hand can: a keyframe far from the last one at nearly the
    // same time would throw the part at any speed.
    const auto addPose = [&](Channel<Eigen::Isometry3d>& c, const Node& n, bool allowGrab) {
      const Eigen::Isometry3d p = readPose(n, L, allowGrab);
      if (!c.empty()) {
        const double v = speedBetween(c.back().t, c.back().value.translation(), t, p.translation());
        if (v > limits::kMaxSpeed)
          n.get("position").failWith("a position reached from the previous keyframe at up to 100 m/s", speedText(v));
      }
      c.push_back({t, p});
    };
    for (int h = 0; h < 2; ++h) {
      if (auto hn = k.opt(handNames[h])) {
        hn->requireObject();
        if (hn->has("position")) addPose(pose[h], *hn, true);
        else hn->allowOnly({"grab"});
        if (auto g = hn->opt("grab")) {
          if (!g->json().is_boolean()) g->fail("true or false");
          grab[h].push_back({t, g->json().get<bool>()});
        }
      }
    }
    if (auto b = k.opt("base")) addPose(pose[2], *b, false);
    if (auto hn = k.opt("hoist")) {
      hn->allowOnly({"engaged", "height", "yaw"});
      if (auto e = hn->opt("engaged")) {
        if (!e->json().is_boolean()) e->fail("true or false");
        engaged.push_back({t, e->json().get<bool>()});
      }
      if (auto hh = hn->opt("height")) {
        const double z = hh->number() * L;
        if (!(std::abs(z) <= limits::kMaxCoordinate)) hh->fail("a height within the world bound of 1000 m");
        if (!height.empty()) {
          const double v = speedBetween(height.back().t, Eigen::Vector3d(0, 0, height.back().value), t, Eigen::Vector3d(0, 0, z));
          if (v > limits::kMaxSpeed) hh->failWith("a height reached from the previous keyframe at up to 100 m/s", speedText(v));
        }
        height.push_back({t, z});
      }
      if (auto y = hn->opt("yaw")) yaw.push_back({t, y->number() * kDeg});
    }
  }
  const double h = settings.step();
  const auto steps = static_cast<std::size_t>(stepCount);
  std::vector<Input> inputs(steps);
  for (std::size_t s = 0; s < steps; ++s) {
    const double t = static_cast<double>(s + 1) * h;
    Input& in = inputs[s];
    if (!pose[0].empty()) in.left.pose = interpolate(pose[0], t);
    if (!pose[1].empty()) in.right.pose = interpolate(pose[1], t);
    if (!pose[2].empty()) in.base = interpolate(pose[2], t);
    in.left.grab = held(grab[0], t);
    in.right.grab = held(grab[1], t);
    in.hoist.engaged = held(engaged, t);
    if (!height.empty()) in.hoist.height = interpolate(height, t);
    if (!yaw.empty()) in.hoist.yaw = interpolate(yaw, t);
  }
  return inputs;
}

void saveSession(const Session& s, const std::filesystem::path& file) {
  AtomicFile out(file);
  saveSession(s, out);
  out.commit();
}

void saveSession(const Session& s, AtomicFile& out) {
  // Each input lists what changed since the previous step (the first step everything), so an idle
  // stretch of a long session costs a few bytes a step.
  Json inputs = Json::array();
  const Input* prev = nullptr;
  for (const Input& in : s.inputs) {
    Json j = Json::object();
    if (!prev || !sameHand(in.left, prev->left)) j["left"] = handJson(in.left);
    if (!prev || !sameHand(in.right, prev->right)) j["right"] = handJson(in.right);
    if (!prev || !sameHoist(in.hoist, prev->hoist)) j["hoist"] = hoistJson(in.hoist);
    if (in.base) j["base"] = poseJson(*in.base);
    inputs.push_back(std::move(j));
    prev = &in;
  }
  Json edits = Json::array();
  for (const EditRecord& e : s.edits) edits.push_back(editJson(e));
  Json root{{"format", "vaw-session"}, {"version", kSessionFormatVersion}, {"scene", s.scene}};
  if (s.sceneHash) root["scene_hash"] = hashText(*s.sceneHash);
  root["settings"] = settingsJson(s.settings);
  root["edits"] = std::move(edits);
  root["inputs"] = std::move(inputs);
  // nlohmann writes doubles with max_digits10 (round-trip exact).
  out << root.dump() << "\n";
}

Session loadSession(const std::filesystem::path& file) {
  const Json json = ::vaw::detail::readJsonFile(file);
  const std::string fileName = file.string();
  const Node root(json, "", fileName);
  root.requireFormat("vaw-session");
  const Node version = root.get("version");
  const int v = version.integer();
  if (v < 1 || v > kSessionFormatVersion)
    version.fail("version 1 to " + std::to_string(kSessionFormatVersion) + " (the versions this vaw reads)");
  if (v >= 2) root.allowOnly({"format", "version", "scene", "scene_hash", "settings", "edits", "inputs"});
  else root.allowOnly({"format", "version", "scene", "settings", "inputs"});
  Session s;
  s.file = file;
  const Node scene = root.get("scene");
  s.scene = scene.string();
  if (s.scene.empty() || s.scene.size() > 4096) scene.fail("a scene file name of 1 to 4096 characters");
  if (auto h = root.opt("scene_hash")) {
    const std::string text = h->string();
    char* end = nullptr;
    const unsigned long long value = std::strtoull(text.c_str(), &end, 16);
    if (text.size() != 16 || end != text.c_str() + 16) h->fail("16 hexadecimal digits");
    s.sceneHash = value;
  }
  s.settings = settingsFrom(root.get("settings"));
  const Node inputs = root.get("inputs");
  inputs.requireArray();
  if (inputs.size() > limits::kMaxSteps) inputs.fail("at most " + std::to_string(limits::kMaxSteps) + " steps");
  s.inputs.reserve(inputs.size());
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const Node n = inputs.at(i);
    n.requireObject();
    n.allowOnly({"left", "right", "base", "hoist"});
    // Version 2 omits what did not change since the previous step; version 1 writes everything.
    Input in = s.inputs.empty() ? Input{} : s.inputs.back();
    in.base.reset();
    const bool required = v < 2 || i == 0;
    const auto hand = [&](const char* key, HandInput& h) {
      if (required || n.has(key)) h = handFrom(n.get(key), v >= 2);
    };
    hand("left", in.left);
    hand("right", in.right);
    if (auto b = n.opt("base")) in.base = poseFrom(*b);
    if (required || n.has("hoist")) in.hoist = hoistFrom(n.get("hoist"));
    // Step to step, nothing moves faster than a hand can (the scripts' bound, at the session's rate).
    if (!s.inputs.empty()) {
      const Input& prev = s.inputs.back();
      const double rate = s.settings.rate;
      const auto tooFast = [rate](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return (b - a).norm() * rate > limits::kMaxSpeed; };
      const char* moved = tooFast(prev.left.pose.translation(), in.left.pose.translation())     ? "left"
                          : tooFast(prev.right.pose.translation(), in.right.pose.translation()) ? "right"
                          : prev.base && in.base && tooFast(prev.base->translation(), in.base->translation()) ? "base"
                          : tooFast({0, 0, prev.hoist.height}, {0, 0, in.hoist.height})        ? "hoist"
                                                                                                : nullptr;
      if (moved) n.get(moved).fail("a pose reached from the previous step at up to 100 m/s");
    }
    s.inputs.push_back(in);
  }
  if (auto edits = root.opt("edits")) {
    edits->requireArray();
    for (std::size_t i = 0; i < edits->size(); ++i) {
      const Node e = edits->at(i);
      EditRecord r = editFrom(e);
      if (!s.edits.empty() && r.step < s.edits.back().step) e.get("step").fail("a step not before the previous edit's");
      if (r.step > s.inputs.size()) e.get("step").fail("a step within the session's " + std::to_string(s.inputs.size()) + " steps");
      s.edits.push_back(std::move(r));
    }
  }
  return s;
}

void checkScene(const Session& s, const Scene& scene) {
  if (!s.sceneHash || *s.sceneHash == scene.contentHash()) return;
  fail(s.file.empty() ? std::string("session") : s.file.string(), "scene_hash",
       "the content hash of the scene it was recorded on: " + hashText(*s.sceneHash) +
           " (the scene file or a file it uses changed since, so a replay would not reproduce it)",
       hashText(scene.contentHash()) + " for " + scene.assembly().source.string());
}

std::size_t applyEdits(World& w, const Session& s, std::size_t next) {
  while (next < s.edits.size() && s.edits[next].step == w.stepCount()) {
    const std::string problem = w.apply(s.edits[next].edit);
    if (!problem.empty())
      fail(s.file.empty() ? std::string("session") : s.file.string(), "edits[" + std::to_string(next) + "]",
           "an edit this scene accepts", problem);
    ++next;
  }
  return next;
}

World replay(std::shared_ptr<const Scene> scene, const Session& s, const std::function<void(const World&)>& afterStep) {
  checkScene(s, *scene);
  World w(std::move(scene), s.settings);
  std::size_t edit = 0;
  for (const Input& in : s.inputs) {
    edit = applyEdits(w, s, edit);
    w.step(in);
    if (afterStep) afterStep(w);
  }
  applyEdits(w, s, edit);
  return w;
}

void appendTrajectory(const World& w, std::vector<TrajectoryRow>& rows) {
  for (const PartRuntime& r : w.parts()) {
    rows.push_back({w.stepCount(), w.time(), r.id, r.state, r.pose.translation(), Eigen::Quaterniond(r.pose.linear())});
  }
}

void appendTrajectoryCsv(const World& w, const TrajectoryRow& r, std::string& out) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "%llu,%.17g,", static_cast<unsigned long long>(r.step), r.t);
  out += buf;
  out += csvEscape(w.assembly().parts[r.part].name);
  std::snprintf(buf, sizeof buf, ",%s,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", std::string(interact::name(r.state)).c_str(),
                r.position.x(), r.position.y(), r.position.z(), r.orientation.w(), r.orientation.x(), r.orientation.y(),
                r.orientation.z());
  out += buf;
}

void writeTrajectoriesCsv(const World& w, const std::vector<TrajectoryRow>& rows, const std::filesystem::path& file) {
  AtomicFile out(file);
  out << kTrajectoriesCsvHeader;
  std::string line;
  for (const TrajectoryRow& r : rows) {
    line.clear();
    appendTrajectoryCsv(w, r, line);
    out << line;
  }
  out.commit();
}

void writeTransitionsCsv(const World& w, const std::filesystem::path& file) {
  writeTransitionsCsv(w.assembly(), w.transitions(), w.refusals(), file);
}

void writeTransitionsCsv(const World& w, AtomicFile& out) {
  writeTransitionsCsv(w.assembly(), w.transitions(), w.refusals(), out);
}

void writeTransitionsCsv(const Assembly& assembly, const std::vector<TransitionRecord>& transitions,
                         const std::vector<Refusal>& refusals, const std::filesystem::path& file) {
  AtomicFile out(file);
  writeTransitionsCsv(assembly, transitions, refusals, out);
  out.commit();
}

void writeTransitionsCsv(const Assembly& assembly, const std::vector<TransitionRecord>& transitions,
                         const std::vector<Refusal>& refusals, AtomicFile& out) {
  out << "step,t,part,from,to,event,cause\n";
  char buf[128];
  for (const TransitionRecord& r : transitions) {
    std::snprintf(buf, sizeof buf, "%llu,%.17g,", static_cast<unsigned long long>(r.step), r.t);
    out << buf << csvEscape(assembly.parts[r.part].name) << "," << interact::name(r.from) << ","
        << interact::name(r.to) << "," << interact::name(r.event) << "," << csvEscape(r.cause) << "\n";
  }
  for (const Refusal& r : refusals) {
    std::snprintf(buf, sizeof buf, "%llu,%.17g,", static_cast<unsigned long long>(r.step), r.t);
    out << buf << csvEscape(assembly.parts[r.part].name) << "," << interact::name(r.state) << ",REFUSED,"
        << interact::name(r.event) << "," << csvEscape(r.reason) << "\n";
  }
}

}  // namespace vaw::sim
