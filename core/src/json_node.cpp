#include "json_node.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

namespace vaw::detail {

std::string describe(const Json& j) {
  std::string s = j.dump();
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

Json readJsonFile(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file.string(), "", "an existing, readable file", std::filesystem::exists(file) ? "unreadable" : "no such file");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  try {
    return Json::parse(text);
  } catch (const Json::parse_error& e) {
    std::size_t line = 1, column = 1;
    const std::size_t end = std::min<std::size_t>(e.byte == 0 ? 0 : e.byte - 1, text.size());
    for (std::size_t i = 0; i < end; ++i) {
      if (text[i] == '\n') { ++line; column = 1; } else { ++column; }
    }
    std::string what = e.what();
    if (auto p = what.find("syntax error"); p != std::string::npos) what = what.substr(p);
    fail(file.string(), "line " + std::to_string(line) + ", column " + std::to_string(column), "valid JSON", what);
  } catch (const Json::exception& e) {
    // nlohmann reports a number too large for a double (1e999) without a position.
    fail(file.string(), "numbers", "finite numbers within the range of a double", e.what());
  }
}

void Node::fail(const std::string& expected) const { failWith(expected, describe(*j_)); }

void Node::failWith(const std::string& expected, const std::string& found) const {
  vaw::fail(*file_, path_.empty() ? std::string("(top level)") : path_, expected, found);
}

bool Node::has(const char* key) const { return j_->is_object() && j_->contains(key); }

Node Node::get(const char* key) const {
  requireObject();
  auto it = j_->find(key);
  if (it == j_->end()) {
    vaw::fail(*file_, path_.empty() ? std::string(key) : path_ + "." + key, "a value for required key \"" + std::string(key) + "\"", "nothing");
  }
  return Node(*it, path_.empty() ? std::string(key) : path_ + "." + key, *file_);
}

std::optional<Node> Node::opt(const char* key) const {
  if (!has(key)) return std::nullopt;
  return get(key);
}

Node Node::at(std::size_t i) const { return Node((*j_)[i], path_ + "[" + std::to_string(i) + "]", *file_); }

std::size_t Node::size() const { return j_->size(); }

void Node::allowOnly(std::initializer_list<const char*> allowed) const {
  requireObject();
  for (const auto& [key, value] : j_->items()) {
    if (!key.empty() && key[0] == '_') continue;
    bool ok = false;
    for (const char* a : allowed) ok = ok || key == a;
    if (!ok) {
      std::string list;
      for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      vaw::fail(*file_, path_.empty() ? key : path_ + "." + key, "one of the keys " + list, "unknown key \"" + key + "\"");
    }
  }
}

void Node::requireObject() const {
  if (!j_->is_object()) fail("an object");
}
void Node::requireArray() const {
  if (!j_->is_array()) fail("an array");
}

std::string Node::string() const {
  if (!j_->is_string()) fail("a string");
  return j_->get<std::string>();
}

double Node::number() const {
  if (!j_->is_number()) fail("a number");
  const double v = j_->get<double>();
  if (!std::isfinite(v)) failWith("a finite number", "an infinite or NaN number");
  return v;
}

double Node::positive() const {
  const double v = number();
  if (!(v > 0.0)) fail("a positive number");
  return v;
}

double Node::nonNegative() const {
  const double v = number();
  if (v < 0.0) fail("a number >= 0");
  return v;
}

int Node::integer() const {
  if (!j_->is_number_integer()) fail("an integer");
  return j_->get<int>();
}

Eigen::Vector3d Node::vec3() const {
  if (!j_->is_array() || j_->size() != 3) fail("an array of 3 numbers");
  return {at(0).number(), at(1).number(), at(2).number()};
}

Eigen::Vector3d Node::direction() const {
  const Eigen::Vector3d v = vec3();
  const double n = v.norm();
  if (!(n > 1e-12)) fail("a non-zero direction");
  return v / n;
}

Eigen::Matrix3d Node::rotation() const {
  requireObject();
  if (has("quaternion")) {
    allowOnly({"quaternion"});
    const Node qn = get("quaternion");
    if (!qn.json().is_array() || qn.size() != 4) qn.fail("[w, x, y, z]");
    const Eigen::Quaterniond q(qn.at(0).number(), qn.at(1).number(), qn.at(2).number(), qn.at(3).number());
    if (std::abs(q.norm() - 1.0) > 1e-6) {
      std::ostringstream norm;
      norm << "norm " << q.norm();
      qn.failWith("a unit quaternion (norm within 1e-6 of 1)", norm.str());
    }
    return q.normalized().toRotationMatrix();
  }
  allowOnly({"axis", "angle"});
  const Eigen::Vector3d axis = get("axis").direction();
  return Eigen::AngleAxisd(get("angle").number() * M_PI / 180.0, axis).toRotationMatrix();
}

}  // namespace vaw::detail
