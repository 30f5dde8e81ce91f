#pragma once
// Pictures for the evaluation report, drawn without a display or a GPU so that `vaw-sim evaluate --report`
// runs anywhere: the parts' triangles through a depth buffer from one fixed view above the front right,
// flat shaded, written as PNG (zlib) and embedded in the page as base64. Private to the report library.
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "vaw/mesh.hpp"

namespace vaw::report::detail {

struct Drawn {
  const TriMesh* mesh = nullptr;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  Eigen::Vector3f color{0.6f, 0.6f, 0.6f};
  // Below 1: blended over what is drawn and hiding nothing drawn after it (draw such meshes last).
  float alpha = 1.0f;
};

class Picture {
 public:
  // The view frames `bounds` (world) in width x height pixels.
  Picture(int width, int height, const Eigen::AlignedBox3d& bounds);
  void draw(const Drawn& d);
  // An arrow along `direction` (world) ending at `tip`, `length` m long, in `color`, drawn over everything.
  void arrow(const Eigen::Vector3d& tip, const Eigen::Vector3d& direction, double length, const Eigen::Vector3f& color);
  // A line between two world points, drawn over everything.
  void segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3f& color, double width = 1.5);
  // A ring around a world point, `radius` pixels, drawn over everything.
  void ring(const Eigen::Vector3d& at, double radius, const Eigen::Vector3f& color);
  [[nodiscard]] std::string png() const;
  [[nodiscard]] std::string dataUri() const;  // "data:image/png;base64,..."

 private:
  [[nodiscard]] Eigen::Vector3d project(const Eigen::Vector3d& p) const;  // x, y pixels; z depth
  void line(Eigen::Vector2d a, Eigen::Vector2d b, const Eigen::Vector3f& color, double width);
  int w_, h_;
  Eigen::Vector3d right_, up_, forward_, light_;
  double scale_ = 1.0;
  Eigen::Vector2d offset_ = Eigen::Vector2d::Zero();
  std::vector<float> depth_;
  std::vector<std::uint8_t> rgb_;
};

std::string base64(const std::string& bytes);

}  // namespace vaw::report::detail
