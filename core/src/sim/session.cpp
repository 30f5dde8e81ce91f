#include "vaw/sim/session.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "../json_node.hpp"
#include "vaw/atomic_file.hpp"
#include "vaw/dynamics/hinge.hpp"
#include "vaw/limits.hpp"

namespace vaw::sim {

using detail::Json;
using detail::Node;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

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

Json handJson(const HandInput& h) { return Json{{"pose", poseJson(h.pose)}, {"grab", h.grab}}; }

HandInput handFrom(const Node& n) {
  n.allowOnly({"pose", "grab"});
  HandInput h;
  h.pose = poseFrom(n.get("pose"));
  const Node g = n.get("grab");
  if (!g.json().is_boolean()) g.fail("true or false");
  h.grab = g.json().get<bool>();
  return h;
}

Json settingsJson(const Settings& s) {
  return Json{{"rate", s.rate},
              {"gravity_scale", {{"free_flight", s.gravity.freeFlight}, {"slide", s.gravity.slide}, {"rotation", s.gravity.rotation}}},
              {"rotation_method", std::string(dyn::name(s.rotationMethod))},
              {"release", {{"estimator", s.release.estimator == interact::ReleaseEstimator::WindowedFit ? "windowed-fit" : "two-instance"},
                           {"window", s.release.window}}},
              {"recognize", {{"distance", s.recognizeDistance}, {"angle", s.recognizeAngle}}},
              {"place", {{"distance", s.placeDistance}, {"angle", s.placeAngle}}},
              {"grab_reach", s.grabReach},
              {"inertial_forces", s.inertialForces},
              {"rotation_model_tolerance", s.rotationModelTolerance},
              {"hoist", {{"x", s.hoistXY.x()}, {"y", s.hoistXY.y()}, {"reach", s.hoistReach}}}};
}

Settings settingsFrom(const Node& n) {
  Settings s;
  s.rate = n.get("rate").number(limits::kMinRate, limits::kMaxRate, "Hz");
  const Node g = n.get("gravity_scale");
  s.gravity.freeFlight = g.get("free_flight").number(0.0, limits::kMaxGravityScale, "");
  s.gravity.slide = g.get("slide").number(0.0, limits::kMaxGravityScale, "");
  s.gravity.rotation = g.get("rotation").number(0.0, limits::kMaxGravityScale, "");
  const Node m = n.get("rotation_method");
  const auto method = dyn::parseMethod(m.string(), dyn::Hinge::kMethods);
  if (!method) m.fail("a method a rotation about an axis supports: " + dyn::describe(dyn::Hinge::kMethods));
  s.rotationMethod = *method;
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
  s.grabReach = n.get("grab_reach").number(0.0, limits::kMaxReach, "m");
  const Node inertial = n.get("inertial_forces");
  if (!inertial.json().is_boolean()) inertial.fail("true or false");
  s.inertialForces = inertial.json().get<bool>();
  s.rotationModelTolerance = n.get("rotation_model_tolerance").number(1e-9, 180.0, "degrees");
  s.hoistXY = {n.get("hoist").get("x").number(-limits::kMaxCoordinate, limits::kMaxCoordinate, "m"),
               n.get("hoist").get("y").number(-limits::kMaxCoordinate, limits::kMaxCoordinate, "m")};
  s.hoistReach = n.get("hoist").get("reach").number(0.0, limits::kMaxReach, "m");
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
  const Json json = detail::readJsonFile(file);
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
    settings.hoistXY = Eigen::Vector2d(ha->at(0).number(), ha->at(1).number()) * L;
    if (!(settings.hoistXY.cwiseAbs().maxCoeff() <= limits::kMaxCoordinate)) ha->fail("[x, y] within the world bound of 1000 m");
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
  Json inputs = Json::array();
  for (const Input& in : s.inputs) {
    Json j{{"left", handJson(in.left)},
           {"right", handJson(in.right)},
           {"hoist", {{"engaged", in.hoist.engaged}, {"height", in.hoist.height}, {"yaw", in.hoist.yaw}}}};
    if (in.base) j["base"] = poseJson(*in.base);
    inputs.push_back(std::move(j));
  }
  const Json root{{"format", "vaw-session"},
                  {"version", kSessionFormatVersion},
                  {"scene", s.scene},
                  {"settings", settingsJson(s.settings)},
                  {"inputs", std::move(inputs)}};
  // nlohmann writes doubles with max_digits10 (round-trip exact).
  out << root.dump() << "\n";
}

Session loadSession(const std::filesystem::path& file) {
  const Json json = detail::readJsonFile(file);
  const std::string fileName = file.string();
  const Node root(json, "", fileName);
  root.requireFormat("vaw-session");
  root.allowOnly({"format", "version", "scene", "settings", "inputs"});
  const Node version = root.get("version");
  if (version.integer() != kSessionFormatVersion) version.fail("version " + std::to_string(kSessionFormatVersion));
  Session s;
  const Node scene = root.get("scene");
  s.scene = scene.string();
  if (s.scene.empty() || s.scene.size() > 4096) scene.fail("a scene file name of 1 to 4096 characters");
  s.settings = settingsFrom(root.get("settings"));
  const Node inputs = root.get("inputs");
  inputs.requireArray();
  if (inputs.size() > limits::kMaxSteps) inputs.fail("at most " + std::to_string(limits::kMaxSteps) + " steps");
  s.inputs.reserve(inputs.size());
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const Node n = inputs.at(i);
    n.allowOnly({"left", "right", "base", "hoist"});
    Input in;
    in.left = handFrom(n.get("left"));
    in.right = handFrom(n.get("right"));
    if (auto b = n.opt("base")) in.base = poseFrom(*b);
    const Node h = n.get("hoist");
    const Node e = h.get("engaged");
    if (!e.json().is_boolean()) e.fail("true or false");
    in.hoist.engaged = e.json().get<bool>();
    in.hoist.height = h.get("height").number(-limits::kMaxCoordinate, limits::kMaxCoordinate, "m");
    in.hoist.yaw = h.get("yaw").number();
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
  return s;
}

World replay(const Assembly& assembly, const Session& s, const std::function<void(const World&)>& afterStep) {
  World w(assembly, s.settings);
  for (const Input& in : s.inputs) {
    w.step(in);
    if (afterStep) afterStep(w);
  }
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
  AtomicFile out(file);
  writeTransitionsCsv(w, out);
  out.commit();
}

void writeTransitionsCsv(const World& w, AtomicFile& out) {
  out << "step,t,part,from,to,event,cause\n";
  char buf[128];
  for (const TransitionRecord& r : w.transitions()) {
    std::snprintf(buf, sizeof buf, "%llu,%.17g,", static_cast<unsigned long long>(r.step), r.t);
    out << buf << csvEscape(w.assembly().parts[r.part].name) << "," << interact::name(r.from) << ","
        << interact::name(r.to) << "," << interact::name(r.event) << "," << csvEscape(r.cause) << "\n";
  }
  for (const Refusal& r : w.refusals()) {
    std::snprintf(buf, sizeof buf, "%llu,%.17g,", static_cast<unsigned long long>(r.step), r.t);
    out << buf << csvEscape(w.assembly().parts[r.part].name) << "," << interact::name(r.state) << ",REFUSED,"
        << interact::name(r.event) << "," << csvEscape(r.reason) << "\n";
  }
}

}  // namespace vaw::sim
