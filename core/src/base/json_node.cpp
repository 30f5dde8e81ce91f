#include "json_node.hpp"

#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <sstream>
#include <string_view>
#include <utility>

#include "vaw/limits.hpp"
#include "vaw/paths.hpp"

namespace vaw::detail {

std::string describe(const Json& j) {
  std::string s = j.dump();
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

std::string deepNesting(const std::string& text, int maxDepth) {
  int depth = 0;
  bool inString = false, escaped = false;
  std::size_t line = 1, column = 0;
  for (const char c : text) {
    ++column;
    if (c == '\n') {
      ++line;
      column = 0;
    }
    if (inString) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') inString = false;
    } else if (c == '"') {
      inString = true;
    } else if (c == '[' || c == '{') {
      if (++depth > maxDepth) return "line " + std::to_string(line) + ", column " + std::to_string(column);
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return {};
}

Json readJsonFile(const std::filesystem::path& file) {
  if (const std::string problem = fileProblem(file); !problem.empty())
    fail(file.string(), "", "an existing, readable file", problem);
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(file, ec);
  if (!ec && bytes > limits::kMaxJsonBytes)
    fail(file.string(), "", "a file of at most 1 GiB", std::to_string(bytes) + " bytes");
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file.string(), "", "an existing, readable file", "unreadable");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  if (const std::string where = deepNesting(text, limits::kMaxJsonDepth); !where.empty())
    fail(file.string(), where, "arrays and objects nested at most " + std::to_string(limits::kMaxJsonDepth) + " deep",
         "deeper nesting");
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

void Node::requireFormat(const char* format) const {
  requireObject();
  static constexpr std::pair<std::string_view, std::string_view> kKinds[] = {{"vaw-scene", "a scene"},
                                                                            {"vaw-properties", "a property file"},
                                                                            {"vaw-inputs", "an input script"},
                                                                            {"vaw-session", "a session"}};
  std::string_view wanted = "a vaw file";
  for (const auto& [f, kind] : kKinds)
    if (f == format) wanted = kind;
  const std::string expected = "\"" + std::string(format) + "\" (" + std::string(wanted) + ")";
  const Node f = get("format");
  if (!f.json().is_string()) f.fail(expected);
  const std::string found = f.json().get<std::string>();
  if (found == format) return;
  for (const auto& [other, kind] : kKinds)
    if (other == found)
      f.failWith(expected, "\"" + found + "\" (this is a " + found + " file, not " + std::string(wanted) + ")");
  f.fail(expected);
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

int Node::integer() const { return integer(std::numeric_limits<int>::min(), std::numeric_limits<int>::max()); }

int Node::integer(int lo, int hi) const {
  const std::string range = "an integer from " + std::to_string(lo) + " to " + std::to_string(hi);
  if (!j_->is_number_integer()) fail(range);
  // Read at full width first: a narrowing conversion would wrap 2^32 + 3 to 3.
  if (j_->is_number_unsigned()) {
    if (j_->get<std::uint64_t>() > static_cast<std::uint64_t>(hi)) fail(range);
  } else {
    const auto v = j_->get<std::int64_t>();
    if (v < lo || v > hi) fail(range);
  }
  return static_cast<int>(j_->get<std::int64_t>());
}

double Node::number(double lo, double hi, const char* unit) const {
  const double v = number();
  if (v < lo || v > hi) {
    std::ostringstream range;
    range << "a number from " << lo << " to " << hi << (*unit ? " " : "") << unit;
    fail(range.str());
  }
  return v;
}

Eigen::Vector3d Node::position(double L) const {
  const Eigen::Vector3d p = vec3() * L;
  if (!(p.cwiseAbs().maxCoeff() <= limits::kMaxCoordinate)) {
    std::ostringstream m;
    m << "coordinates within " << limits::kMaxCoordinate << " m of the origin (the world bound)";
    fail(m.str());
  }
  return p;
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
