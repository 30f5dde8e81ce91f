#pragma once
// A JSON value together with the file and the field path it came from, so that every validation error
// names the file, the field and what was expected (docs/architecture.md, "Errors by audience"). Internal
// to the core.
#include <Eigen/Geometry>
#include <filesystem>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "vaw/error.hpp"

namespace vaw::detail {

using Json = nlohmann::json;

// Reads and parses a JSON file; a missing file or a syntax error becomes an InputError with the
// line and column. Files over limits::kMaxJsonBytes and arrays or objects nested deeper than
// limits::kMaxJsonDepth are refused before parsing (nlohmann's parser recurses per level).
Json readJsonFile(const std::filesystem::path& file);
// The first position where `text` nests arrays and objects deeper than maxDepth, as "line L, column C";
// empty when it does not.
std::string deepNesting(const std::string& text, int maxDepth);

class Node {
 public:
  Node(const Json& j, std::string path, const std::string& file) : j_(&j), path_(std::move(path)), file_(&file) {}

  [[nodiscard]] const Json& json() const { return *j_; }
  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] const std::string& file() const { return *file_; }
  [[noreturn]] void fail(const std::string& expected) const;
  [[noreturn]] void failWith(const std::string& expected, const std::string& found) const;

  [[nodiscard]] bool has(const char* key) const;
  [[nodiscard]] Node get(const char* key) const;                 // required member
  [[nodiscard]] std::optional<Node> opt(const char* key) const;  // optional member
  [[nodiscard]] Node at(std::size_t i) const;
  [[nodiscard]] std::size_t size() const;
  // Fails on keys outside `allowed`; keys starting with '_' are comments.
  void allowOnly(std::initializer_list<const char*> allowed) const;

  // The top-level "format" first, so that a file of another kind is named as such ("this is a
  // vaw-properties file, not a scene") instead of failing on a key it does not share.
  void requireFormat(const char* format) const;
  void requireObject() const;
  void requireArray() const;
  [[nodiscard]] std::string string() const;
  [[nodiscard]] double number() const;  // finite
  [[nodiscard]] double positive() const;
  [[nodiscard]] double nonNegative() const;
  [[nodiscard]] int integer() const;
  [[nodiscard]] int integer(int lo, int hi) const;  // within [lo, hi], checked before any conversion
  // Within [lo, hi]; `unit` completes the message ("a number from 0 to 10 m").
  [[nodiscard]] double number(double lo, double hi, const char* unit) const;
  // A point or translation, converted by L (metres per file unit), each coordinate within
  // limits::kMaxCoordinate of the origin.
  [[nodiscard]] Eigen::Vector3d position(double L) const;
  [[nodiscard]] Eigen::Vector3d vec3() const;
  [[nodiscard]] Eigen::Vector3d direction() const;  // non-zero, returned unit length
  // {"quaternion": [w, x, y, z]} (unit within 1e-6) or {"axis": [x, y, z], "angle": degrees}.
  [[nodiscard]] Eigen::Matrix3d rotation() const;

 private:
  const Json* j_;
  std::string path_;
  const std::string* file_;
};

std::string describe(const Json& j);

}  // namespace vaw::detail
