#include "vaw/sim/session.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>

#include "../json_node.hpp"
#include "vaw/dynamics/hinge.hpp"

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
  pose.translation() = n.get("position").vec3() * L;
  if (auto r = n.opt("rotation")) pose.linear() = r->rotation();
  return pose;
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
  s.rate = n.get("rate").positive();
  const Node g = n.get("gravity_scale");
  s.gravity.freeFlight = g.get("free_flight").nonNegative();
  s.gravity.slide = g.get("slide").nonNegative();
  s.gravity.rotation = g.get("rotation").nonNegative();
  const Node m = n.get("rotation_method");
  const auto method = dyn::parseMethod(m.string(), dyn::Hinge::kMethods);
  if (!method) m.fail("a method a rotation about an axis supports: " + dyn::describe(dyn::Hinge::kMethods));
  s.rotationMethod = *method;
  const Node r = n.get("release");
  const Node est = r.get("estimator");
  if (est.string() == "windowed-fit") s.release.estimator = interact::ReleaseEstimator::WindowedFit;
  else if (est.string() == "two-instance") s.release.estimator = interact::ReleaseEstimator::TwoInstance;
  else est.fail("windowed-fit or two-instance");
  s.release.window = r.get("window").positive();
  s.recognizeDistance = n.get("recognize").get("distance").nonNegative();
  s.recognizeAngle = n.get("recognize").get("angle").nonNegative();
  s.placeDistance = n.get("place").get("distance").nonNegative();
  s.placeAngle = n.get("place").get("angle").nonNegative();
  s.grabReach = n.get("grab_reach").nonNegative();
  const Node inertial = n.get("inertial_forces");
  if (!inertial.json().is_boolean()) inertial.fail("true or false");
  s.inertialForces = inertial.json().get<bool>();
  s.rotationModelTolerance = n.get("rotation_model_tolerance").positive();
  s.hoistXY = {n.get("hoist").get("x").number(), n.get("hoist").get("y").number()};
  s.hoistReach = n.get("hoist").get("reach").nonNegative();
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
  root.requireObject();
  root.allowOnly({"format", "version", "units", "rate", "duration", "keyframes", "description", "hoist_at"});
  const Node format = root.get("format");
  if (format.string() != "vaw-inputs") format.fail("\"vaw-inputs\"");
  const Node version = root.get("version");
  if (version.integer() != kInputsFormatVersion) version.fail("version " + std::to_string(kInputsFormatVersion));
  double L = 1.0;
  if (auto u = root.opt("units")) {
    if (u->string() == "mm") L = 1e-3;
    else if (u->string() != "m") u->fail("\"m\" or \"mm\"");
  }
  if (auto r = root.opt("rate")) settings.rate = r->positive();
  if (auto ha = root.opt("hoist_at")) {
    if (!ha->json().is_array() || ha->size() != 2) ha->fail("[x, y]: where the hoist's vertical line stands");
    settings.hoistXY = Eigen::Vector2d(ha->at(0).number(), ha->at(1).number()) * L;
  }
  const double duration = root.get("duration").positive();
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
    const double t = tn.nonNegative();
    if (t < last) tn.fail("a time not before the previous keyframe's (" + std::to_string(last) + " s)");
    last = t;
    const char* handNames[2] = {"left", "right"};
    for (int h = 0; h < 2; ++h) {
      if (auto hn = k.opt(handNames[h])) {
        hn->requireObject();
        if (hn->has("position")) pose[h].push_back({t, readPose(*hn, L, true)});
        else hn->allowOnly({"grab"});
        if (auto g = hn->opt("grab")) {
          if (!g->json().is_boolean()) g->fail("true or false");
          grab[h].push_back({t, g->json().get<bool>()});
        }
      }
    }
    if (auto b = k.opt("base")) pose[2].push_back({t, readPose(*b, L, false)});
    if (auto hn = k.opt("hoist")) {
      hn->allowOnly({"engaged", "height", "yaw"});
      if (auto e = hn->opt("engaged")) {
        if (!e->json().is_boolean()) e->fail("true or false");
        engaged.push_back({t, e->json().get<bool>()});
      }
      if (auto hh = hn->opt("height")) height.push_back({t, hh->number() * L});
      if (auto y = hn->opt("yaw")) yaw.push_back({t, y->number() * kDeg});
    }
  }
  const double h = settings.step();
  const auto steps = static_cast<std::size_t>(std::llround(duration / h));
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
  std::ofstream out(file, std::ios::binary);
  if (!out) fail(file.string(), "", "a writable file");
  // nlohmann writes doubles with max_digits10 (round-trip exact).
  out << root.dump() << "\n";
  if (!out) fail(file.string(), "", "a writable file (write failed)");
}

Session loadSession(const std::filesystem::path& file) {
  const Json json = detail::readJsonFile(file);
  const std::string fileName = file.string();
  const Node root(json, "", fileName);
  root.requireObject();
  root.allowOnly({"format", "version", "scene", "settings", "inputs"});
  const Node format = root.get("format");
  if (format.string() != "vaw-session") format.fail("\"vaw-session\"");
  const Node version = root.get("version");
  if (version.integer() != kSessionFormatVersion) version.fail("version " + std::to_string(kSessionFormatVersion));
  Session s;
  s.scene = root.get("scene").string();
  s.settings = settingsFrom(root.get("settings"));
  const Node inputs = root.get("inputs");
  inputs.requireArray();
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
    in.hoist.height = h.get("height").number();
    in.hoist.yaw = h.get("yaw").number();
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

void writeTrajectoriesCsv(const World& w, const std::vector<TrajectoryRow>& rows, const std::filesystem::path& file) {
  std::ofstream out(file, std::ios::binary);
  if (!out) fail(file.string(), "", "a writable file");
  out << "step,t,part,state,x,y,z,qw,qx,qy,qz\n";
  char buf[512];
  for (const TrajectoryRow& r : rows) {
    std::snprintf(buf, sizeof buf, "%llu,%.17g,%s,%s,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n",
                  static_cast<unsigned long long>(r.step), r.t, csvEscape(w.assembly().parts[r.part].name).c_str(),
                  std::string(interact::name(r.state)).c_str(), r.position.x(), r.position.y(), r.position.z(),
                  r.orientation.w(), r.orientation.x(), r.orientation.y(), r.orientation.z());
    out << buf;
  }
}

void writeTransitionsCsv(const World& w, const std::filesystem::path& file) {
  std::ofstream out(file, std::ios::binary);
  if (!out) fail(file.string(), "", "a writable file");
  out << "step,t,part,from,to,event,cause\n";
  char buf[128];
  for (const TransitionRecord& r : w.transitions()) {
    std::snprintf(buf, sizeof buf, "%llu,%.17g,", static_cast<unsigned long long>(r.step), r.t);
    out << buf << csvEscape(w.assembly().parts[r.part].name) << ',' << interact::name(r.from) << ','
        << interact::name(r.to) << ',' << interact::name(r.event) << ',' << csvEscape(r.cause) << '\n';
  }
  for (const Refusal& r : w.refusals()) {
    std::snprintf(buf, sizeof buf, "%llu,%.17g,", static_cast<unsigned long long>(r.step), r.t);
    out << buf << csvEscape(w.assembly().parts[r.part].name) << ',' << interact::name(r.state) << ",REFUSED,"
        << interact::name(r.event) << ',' << csvEscape(r.reason) << '\n';
  }
}

}  // namespace vaw::sim
