#include "vaw/sim/input_log.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace vaw::sim {

namespace {

template <typename T>
bool sameBits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}
bool sameBits(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return std::memcmp(a.matrix().data(), b.matrix().data(), sizeof(double) * 16) == 0;
}
bool sameBits(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::memcmp(a.data(), b.data(), sizeof(double) * 3) == 0;
}
bool sameBits(const interact::Twist& a, const interact::Twist& b) { return sameBits(a.linear, b.linear) && sameBits(a.angular, b.angular); }
template <typename T>
bool sameBits(const std::optional<T>& a, const std::optional<T>& b) {
  return a.has_value() == b.has_value() && (!a || sameBits(*a, *b));
}
bool sameBits(const HandInput& a, const HandInput& b) {
  return a.grab == b.grab && sameBits(a.pose, b.pose) && a.target == b.target && sameBits(a.velocity, b.velocity);
}

}  // namespace

bool identical(const Input& a, const Input& b) {
  return sameBits(a.left, b.left) && sameBits(a.right, b.right) && sameBits(a.base, b.base) &&
         a.hoist.engaged == b.hoist.engaged && sameBits(a.hoist.height, b.hoist.height) && sameBits(a.hoist.yaw, b.hoist.yaw);
}

InputLog::InputLog(const std::vector<Input>& inputs) {
  for (const Input& in : inputs) push_back(in);
}

const Input& InputLog::operator[](std::size_t step) const {
  if (step >= size_) throw std::out_of_range("InputLog: step " + std::to_string(step) + " of " + std::to_string(size_));
  const auto it = std::upper_bound(runs_.begin(), runs_.end(), step, [](std::size_t s, const Run& r) { return s < r.first; });
  return std::prev(it)->input;
}

void InputLog::push_back(const Input& input) {
  if (runs_.empty() || !identical(runs_.back().input, input)) runs_.push_back({size_, input});
  ++size_;
}

void InputLog::resize(std::size_t n) {
  if (n > size_) throw std::invalid_argument("InputLog::resize: only the future can be dropped");
  while (!runs_.empty() && runs_.back().first >= n) runs_.pop_back();
  size_ = n;
  if (runs_.capacity() > 2 * runs_.size() + 64) runs_.shrink_to_fit();
}

InputLog::const_iterator& InputLog::const_iterator::operator++() {
  ++step_;
  if (run_ + 1 < log_->runs_.size() && step_ >= log_->runs_[run_ + 1].first) ++run_;
  if (step_ >= log_->size_) run_ = log_->runs_.size();
  return *this;
}

}  // namespace vaw::sim
