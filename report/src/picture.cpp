#include "picture.hpp"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace vaw::report::detail {

Picture::Picture(int width, int height, const Eigen::AlignedBox3d& bounds)
    : w_(width), h_(height), depth_(static_cast<std::size_t>(width * height), std::numeric_limits<float>::infinity()),
      rgb_(static_cast<std::size_t>(width * height * 3), 255) {
  const Eigen::Vector3d toEye = Eigen::Vector3d(1.0, -1.4, 1.1).normalized();
  forward_ = -toEye;
  right_ = forward_.cross(Eigen::Vector3d::UnitZ()).normalized();
  up_ = right_.cross(forward_);
  light_ = (toEye + Eigen::Vector3d(-0.3, 0.0, 0.6)).normalized();
  // Frame the box's eight corners with a margin of 6 % each side.
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d c = bounds.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i));
    const Eigen::Vector2d q(c.dot(right_), c.dot(up_));
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  const Eigen::Vector2d size = (hi - lo).cwiseMax(1e-9);
  scale_ = 0.88 * std::min(w_ / size.x(), h_ / size.y());
  offset_ = 0.5 * Eigen::Vector2d(w_, h_) - scale_ * 0.5 * Eigen::Vector2d(lo.x() + hi.x(), -(lo.y() + hi.y()));
}

Eigen::Vector3d Picture::project(const Eigen::Vector3d& p) const {
  return {offset_.x() + scale_ * p.dot(right_), offset_.y() - scale_ * p.dot(up_), p.dot(forward_)};
}

void Picture::draw(const Drawn& d) {
  const TriMesh& m = *d.mesh;
  std::vector<Eigen::Vector3d> world(m.vertices.size()), screen(m.vertices.size());
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    world[i] = d.pose * m.vertices[i];
    screen[i] = project(world[i]);
  }
  for (const auto& t : m.triangles) {
    const Eigen::Vector3d& a = world[static_cast<std::size_t>(t[0])];
    const Eigen::Vector3d n = (world[static_cast<std::size_t>(t[1])] - a).cross(world[static_cast<std::size_t>(t[2])] - a);
    if (n.dot(forward_) >= 0.0 || n.squaredNorm() == 0.0) continue;  // facing away
    const float shade = static_cast<float>(0.35 + 0.65 * std::max(0.0, n.normalized().dot(light_)));
    const Eigen::Vector3d& p0 = screen[static_cast<std::size_t>(t[0])];
    const Eigen::Vector3d& p1 = screen[static_cast<std::size_t>(t[1])];
    const Eigen::Vector3d& p2 = screen[static_cast<std::size_t>(t[2])];
    const double area = (p1.x() - p0.x()) * (p2.y() - p0.y()) - (p1.y() - p0.y()) * (p2.x() - p0.x());
    if (std::abs(area) < 1e-12) continue;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({p0.x(), p1.x(), p2.x()}))));
    const int x1 = std::min(w_ - 1, static_cast<int>(std::ceil(std::max({p0.x(), p1.x(), p2.x()}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({p0.y(), p1.y(), p2.y()}))));
    const int y1 = std::min(h_ - 1, static_cast<int>(std::ceil(std::max({p0.y(), p1.y(), p2.y()}))));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const double px = x + 0.5, py = y + 0.5;
        const double w0 = ((p1.x() - px) * (p2.y() - py) - (p1.y() - py) * (p2.x() - px)) / area;
        const double w1 = ((p2.x() - px) * (p0.y() - py) - (p2.y() - py) * (p0.x() - px)) / area;
        const double w2 = 1.0 - w0 - w1;
        if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0) continue;
        const auto z = static_cast<float>(w0 * p0.z() + w1 * p1.z() + w2 * p2.z());
        const std::size_t i = static_cast<std::size_t>(y * w_ + x);
        if (z >= depth_[i]) continue;
        if (d.alpha >= 1.0f) depth_[i] = z;
        for (int c = 0; c < 3; ++c) {
          std::uint8_t& out = rgb_[3 * i + static_cast<std::size_t>(c)];
          const float lit = std::clamp(255.0f * shade * d.color[c], 0.0f, 255.0f);
          out = static_cast<std::uint8_t>(d.alpha >= 1.0f ? lit : d.alpha * lit + (1.0f - d.alpha) * static_cast<float>(out));
        }
      }
  }
}

void Picture::line(Eigen::Vector2d a, Eigen::Vector2d b, const Eigen::Vector3f& color, double width) {
  const double len = (b - a).norm();
  const int n = std::max(1, static_cast<int>(len * 2.0));
  for (int k = 0; k <= n; ++k) {
    const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(k) / n);
    for (int dy = -static_cast<int>(width); dy <= static_cast<int>(width); ++dy)
      for (int dx = -static_cast<int>(width); dx <= static_cast<int>(width); ++dx) {
        const int x = static_cast<int>(p.x()) + dx, y = static_cast<int>(p.y()) + dy;
        if (x < 0 || y < 0 || x >= w_ || y >= h_ || dx * dx + dy * dy > width * width) continue;
        const std::size_t i = static_cast<std::size_t>(y * w_ + x);
        for (int c = 0; c < 3; ++c) rgb_[3 * i + static_cast<std::size_t>(c)] = static_cast<std::uint8_t>(255.0f * color[c]);
      }
  }
}

void Picture::segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3f& color, double width) {
  line(project(a).head<2>(), project(b).head<2>(), color, width);
}

void Picture::ring(const Eigen::Vector3d& at, double radius, const Eigen::Vector3f& color) {
  const Eigen::Vector2d c = project(at).head<2>();
  constexpr int kSides = 24;
  for (int k = 0; k < kSides; ++k) {
    const double t0 = 2.0 * std::numbers::pi * k / kSides, t1 = 2.0 * std::numbers::pi * (k + 1) / kSides;
    line(c + radius * Eigen::Vector2d(std::cos(t0), std::sin(t0)), c + radius * Eigen::Vector2d(std::cos(t1), std::sin(t1)), color, 1.0);
  }
}

void Picture::arrow(const Eigen::Vector3d& tip, const Eigen::Vector3d& direction, double length, const Eigen::Vector3f& color) {
  const Eigen::Vector3d t = project(tip), s = project(tip - length * direction.normalized());
  const Eigen::Vector2d a = s.head<2>(), b = t.head<2>();
  line(a, b, color, 1.5);
  const Eigen::Vector2d d = (b - a).norm() > 1e-9 ? Eigen::Vector2d((b - a).normalized()) : Eigen::Vector2d(0, 1);
  const Eigen::Vector2d side(-d.y(), d.x());
  line(b, b - 10.0 * d + 6.0 * side, color, 1.5);
  line(b, b - 10.0 * d - 6.0 * side, color, 1.5);
}

std::string Picture::png() const {
  auto be32 = [](std::string& out, std::uint32_t v) {
    for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<char>((v >> s) & 0xff));
  };
  auto chunk = [&](std::string& out, const char* type, const std::string& data) {
    be32(out, static_cast<std::uint32_t>(data.size()));
    const std::string body = std::string(type, 4) + data;
    out += body;
    be32(out, static_cast<std::uint32_t>(crc32(0L, reinterpret_cast<const Bytef*>(body.data()), static_cast<uInt>(body.size()))));
  };
  std::string raw;
  raw.reserve(static_cast<std::size_t>(h_ * (1 + 3 * w_)));
  for (int y = 0; y < h_; ++y) {
    raw.push_back('\0');  // no filter
    raw.append(reinterpret_cast<const char*>(rgb_.data()) + static_cast<std::size_t>(y * w_ * 3), static_cast<std::size_t>(w_ * 3));
  }
  uLongf size = compressBound(static_cast<uLong>(raw.size()));
  std::string z(size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(z.data()), &size, reinterpret_cast<const Bytef*>(raw.data()), static_cast<uLong>(raw.size()), 9) != Z_OK)
    throw std::runtime_error("report picture: zlib could not compress the image");
  z.resize(size);
  std::string out = "\x89PNG\r\n\x1a\n";
  std::string ihdr;
  be32(ihdr, static_cast<std::uint32_t>(w_));
  be32(ihdr, static_cast<std::uint32_t>(h_));
  ihdr += std::string("\x08\x02\x00\x00\x00", 5);  // 8 bits, RGB, deflate, no filter set, no interlace
  chunk(out, "IHDR", ihdr);
  chunk(out, "IDAT", z);
  chunk(out, "IEND", "");
  return out;
}

std::string Picture::dataUri() const { return "data:image/png;base64," + base64(png()); }

std::string base64(const std::string& bytes) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const auto v = (static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i])) << 16) |
                   (static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i + 1])) << 8) | static_cast<unsigned char>(bytes[i + 2]);
    out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], k[v & 63]};
  }
  if (i + 1 == bytes.size()) {
    const auto v = static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i])) << 16;
    out += {k[v >> 18], k[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == bytes.size()) {
    const auto v = (static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i])) << 16) |
                   (static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i + 1])) << 8);
    out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], '='};
  }
  return out;
}

}  // namespace vaw::report::detail
