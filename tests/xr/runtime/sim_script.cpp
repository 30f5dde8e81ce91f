#include "sim_script.hpp"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <stdexcept>

namespace vaw::simxr {

namespace {

using Json = nlohmann::json;

struct Reader {
  std::string file;
  [[noreturn]] void fail(const std::string& field, const std::string& expected) const {
    throw std::runtime_error(file + ": " + field + ": expected " + expected);
  }
  double number(const Json& j, const std::string& field) const {
    if (!j.is_number()) fail(field, "a number");
    return j.get<double>();
  }
  bool boolean(const Json& j, const std::string& field) const {
    if (!j.is_boolean()) fail(field, "true or false");
    return j.get<bool>();
  }
  Eigen::Vector3d vec3(const Json& j, const std::string& field) const {
    if (!j.is_array() || j.size() != 3) fail(field, "[x, y, z]");
    return {number(j[0], field), number(j[1], field), number(j[2], field)};
  }
  Eigen::Quaterniond rotation(const Json& j, const std::string& field) const {
    if (j.contains("quaternion")) {
      const Json& q = j["quaternion"];
      if (!q.is_array() || q.size() != 4) fail(field + ".quaternion", "[w, x, y, z]");
      return Eigen::Quaterniond(number(q[0], field), number(q[1], field), number(q[2], field), number(q[3], field)).normalized();
    }
    if (!j.contains("axis") || !j.contains("angle")) fail(field, "{\"axis\": [x, y, z], \"angle\": degrees} or {\"quaternion\": [w, x, y, z]}");
    return Eigen::Quaterniond(Eigen::AngleAxisd(number(j["angle"], field + ".angle") * std::numbers::pi / 180.0,
                                                vec3(j["axis"], field + ".axis").normalized()));
  }
  Eigen::Isometry3d pose(const Json& j, const std::string& field) const {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    if (j.contains("position")) p.translation() = vec3(j["position"], field + ".position");
    if (j.contains("rotation")) p.linear() = rotation(j["rotation"], field + ".rotation").toRotationMatrix();
    return p;
  }
  template <class Key>
  void common(const Json& j, const std::string& field, Key& k, const Key* previous) const {
    if (previous != nullptr) k = *previous;
    if (!j.contains("t")) fail(field + ".t", "a time (s)");
    k.t = number(j["t"], field + ".t");
    if (previous != nullptr && k.t < previous->t) fail(field + ".t", "times in order");
    if (j.contains("position")) k.position = vec3(j["position"], field + ".position");
    if (j.contains("rotation")) k.rotation = rotation(j["rotation"], field + ".rotation");
  }
};

template <class Key>
std::pair<const Key*, double> bracket(const std::vector<Key>& keys, double t, const Key*& next) {
  next = nullptr;
  if (t <= keys.front().t) return {&keys.front(), 0.0};
  if (t >= keys.back().t) return {&keys.back(), 0.0};
  std::size_t i = 1;
  while (keys[i].t < t) ++i;
  next = &keys[i];
  const Key& a = keys[i - 1];
  return {&a, (t - a.t) / (keys[i].t - a.t)};
}

// The hand's shape in its own frame (x across the hand, y out of its back, fingers along -z), the origin at
// the pinch point. s = +1 for the left hand, -1 for the right: the thumb is on the -x side of a right hand.
struct Finger {
  int first;        // the metacarpal's joint index
  int count;        // joints up to and including the tip
  double across;    // x of the metacarpal, in units of s
};
constexpr Finger kFingers[] = {{2, 4, 0.035}, {6, 5, 0.01}, {11, 5, -0.01}, {16, 5, -0.03}, {21, 5, -0.048}};

}  // namespace

std::array<Eigen::Isometry3d, kJoints> handJoints(int hand, const Eigen::Isometry3d& pose, double pinch, double grip) {
  const double s = hand == 0 ? 1.0 : -1.0;
  std::array<Eigen::Vector3d, kJoints> p;
  const Eigen::Vector3d palm(-s * 0.015, 0.03, 0.075);
  p[0] = palm;
  p[1] = palm + Eigen::Vector3d(0.0, -0.005, 0.05);
  for (const Finger& f : kFingers) {
    const Eigen::Vector3d base = palm + Eigen::Vector3d(s * f.across, 0.0, f.first == 2 ? 0.02 : 0.0);
    Eigen::Vector3d tip;
    if (f.first == 2) tip = Eigen::Vector3d(s * 0.5 * pinch, 0.0, 0.0);        // thumb
    else if (f.first == 6) tip = Eigen::Vector3d(-s * 0.5 * pinch, 0.0, 0.0);  // index
    else {
      const Eigen::Vector3d straight = base + Eigen::Vector3d(0.0, 0.0, -0.09);
      const Eigen::Vector3d curled = palm + Eigen::Vector3d(s * f.across, -0.03, -0.015);
      tip = straight + std::clamp(grip, 0.0, 1.0) * (curled - straight);
    }
    for (int i = 0; i < f.count; ++i) p[static_cast<std::size_t>(f.first + i)] = base + (tip - base) * (i / (f.count - 1.0));
  }
  std::array<Eigen::Isometry3d, kJoints> out;
  for (std::size_t j = 0; j < kJoints; ++j) {
    out[j] = pose;
    out[j].translation() = pose * p[j];
  }
  return out;
}

Script Script::load(const std::string& file) {
  const Reader r{file};
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file + ": cannot be read");
  Json j;
  try {
    in >> j;
  } catch (const std::exception& e) {
    throw std::runtime_error(file + ": not JSON: " + e.what());
  }
  Script s;
  if (j.contains("refresh")) s.refresh = r.number(j["refresh"], "refresh");
  if (j.contains("duration")) s.duration = r.number(j["duration"], "duration");
  if (j.contains("eye_size")) {
    const Json& e = j["eye_size"];
    if (!e.is_array() || e.size() != 2) r.fail("eye_size", "[width, height]");
    s.eyeWidth = static_cast<int>(r.number(e[0], "eye_size"));
    s.eyeHeight = static_cast<int>(r.number(e[1], "eye_size"));
  }
  if (j.contains("realtime")) s.realtime = r.boolean(j["realtime"], "realtime");
  if (j.contains("headset")) s.headset = r.boolean(j["headset"], "headset");
  if (j.contains("stage")) s.stage = r.boolean(j["stage"], "stage");
  if (j.contains("hand_tracking")) s.handTracking = r.boolean(j["hand_tracking"], "hand_tracking");
  if (j.contains("joint_velocities")) s.jointVelocities = r.boolean(j["joint_velocities"], "joint_velocities");
  s.localOrigin.translation() = Eigen::Vector3d(0.0, 1.6, 0.0);
  if (j.contains("local_origin")) s.localOrigin = r.pose(j["local_origin"], "local_origin");
  if (j.contains("head")) {
    for (std::size_t i = 0; i < j["head"].size(); ++i) {
      PoseKey k;
      r.common(j["head"][i], "head[" + std::to_string(i) + "]", k, s.head.empty() ? nullptr : &s.head.back());
      s.head.push_back(k);
    }
  }
  const char* handNames[2] = {"left", "right"};
  const char* controllerNames[2] = {"left_controller", "right_controller"};
  for (int h = 0; h < 2; ++h) {
    if (j.contains(handNames[h])) {
      const Json& keys = j[handNames[h]];
      for (std::size_t i = 0; i < keys.size(); ++i) {
        const std::string field = std::string(handNames[h]) + "[" + std::to_string(i) + "]";
        auto& list = s.hands[static_cast<std::size_t>(h)];
        HandKey k;
        r.common(keys[i], field, k, list.empty() ? nullptr : &list.back());
        const Json& kj = keys[i];
        if (kj.contains("pinch")) k.pinch = r.number(kj["pinch"], field + ".pinch");
        if (kj.contains("grip")) k.grip = r.number(kj["grip"], field + ".grip");
        if (kj.contains("tracked")) k.tracked = r.boolean(kj["tracked"], field + ".tracked");
        if (kj.contains("joints")) {
          const Json& js = kj["joints"];
          if (!js.is_array() || js.size() != kJoints) r.fail(field + ".joints", "26 joints");
          std::array<Eigen::Isometry3d, kJoints> joints;
          for (std::size_t n = 0; n < kJoints; ++n) {
            const Json& v = js[n];
            if (!v.is_array() || v.size() != 7) r.fail(field + ".joints", "[x, y, z, qw, qx, qy, qz] per joint");
            joints[n] = Eigen::Isometry3d::Identity();
            joints[n].translation() = Eigen::Vector3d(r.number(v[0], field), r.number(v[1], field), r.number(v[2], field));
            joints[n].linear() = Eigen::Quaterniond(r.number(v[3], field), r.number(v[4], field), r.number(v[5], field),
                                                    r.number(v[6], field)).normalized().toRotationMatrix();
          }
          k.joints = joints;
        }
        list.push_back(k);
      }
    }
    if (j.contains(controllerNames[h])) {
      const Json& keys = j[controllerNames[h]];
      for (std::size_t i = 0; i < keys.size(); ++i) {
        const std::string field = std::string(controllerNames[h]) + "[" + std::to_string(i) + "]";
        auto& list = s.controllers[static_cast<std::size_t>(h)];
        ControllerKey k;
        r.common(keys[i], field, k, list.empty() ? nullptr : &list.back());
        if (keys[i].contains("select")) k.select = r.boolean(keys[i]["select"], field + ".select");
        if (keys[i].contains("active")) k.active = r.boolean(keys[i]["active"], field + ".active");
        list.push_back(k);
      }
    }
  }
  if (j.contains("events")) {
    for (std::size_t i = 0; i < j["events"].size(); ++i) {
      const Json& e = j["events"][i];
      const std::string field = "events[" + std::to_string(i) + "]";
      const double t = r.number(e.value("t", Json()), field + ".t");
      if (e.value("lose_session", false)) s.loseSessionAt = t;
      else if (e.value("lose_instance", false)) s.loseInstanceAt = t;
      else r.fail(field, "\"lose_session\": true or \"lose_instance\": true");
    }
  }
  if (j.contains("capture_at"))
    for (std::size_t i = 0; i < j["capture_at"].size(); ++i) s.captureAt.push_back(r.number(j["capture_at"][i], "capture_at"));
  return s;
}

Eigen::Isometry3d Script::headAt(double t) const {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  if (head.empty()) {
    // Standing at the origin, looking ahead and 25 degrees down at the table.
    out.translation() = Eigen::Vector3d(0.0, 1.65, 0.0);
    out.linear() = Eigen::AngleAxisd(-25.0 * std::numbers::pi / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
    return out;
  }
  const PoseKey* next = nullptr;
  const auto [a, x] = bracket(head, t, next);
  out.translation() = next ? Eigen::Vector3d(a->position + x * (next->position - a->position)) : a->position;
  out.linear() = (next ? a->rotation.slerp(x, next->rotation) : a->rotation).toRotationMatrix();
  return out;
}

HandPose Script::handAt(int hand, double t) const {
  HandPose out;
  const auto& keys = hands[static_cast<std::size_t>(hand)];
  if (keys.empty()) return out;
  const HandKey* next = nullptr;
  const auto [a, x] = bracket(keys, t, next);
  out.tracked = a->tracked;
  out.pose.translation() = next ? Eigen::Vector3d(a->position + x * (next->position - a->position)) : a->position;
  out.pose.linear() = (next ? a->rotation.slerp(x, next->rotation) : a->rotation).toRotationMatrix();
  out.pinch = next ? a->pinch + x * (next->pinch - a->pinch) : a->pinch;
  out.grip = next ? a->grip + x * (next->grip - a->grip) : a->grip;
  if (a->joints) {
    for (std::size_t j = 0; j < kJoints; ++j) {
      const Eigen::Isometry3d& ja = (*a->joints)[j];
      if (next != nullptr && next->joints) {
        const Eigen::Isometry3d& jb = (*next->joints)[j];
        out.joints[j] = Eigen::Isometry3d::Identity();
        out.joints[j].translation() = ja.translation() + x * (jb.translation() - ja.translation());
        out.joints[j].linear() = Eigen::Quaterniond(ja.linear()).slerp(x, Eigen::Quaterniond(jb.linear())).toRotationMatrix();
      } else {
        out.joints[j] = ja;
      }
    }
  } else {
    out.joints = handJoints(hand, out.pose, out.pinch, out.grip);
  }
  for (std::size_t j = 0; j < kJoints; ++j) out.radii[j] = j <= 1 ? 0.012f : (j % 5 == 0 ? 0.007f : 0.009f);
  return out;
}

ControllerPose Script::controllerAt(int hand, double t) const {
  ControllerPose out;
  const auto& keys = controllers[static_cast<std::size_t>(hand)];
  if (keys.empty()) return out;
  const ControllerKey* next = nullptr;
  const auto [a, x] = bracket(keys, t, next);
  out.active = a->active;
  out.select = a->select;
  out.pose.translation() = next ? Eigen::Vector3d(a->position + x * (next->position - a->position)) : a->position;
  out.pose.linear() = (next ? a->rotation.slerp(x, next->rotation) : a->rotation).toRotationMatrix();
  return out;
}

}  // namespace vaw::simxr
