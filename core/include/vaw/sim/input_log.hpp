#pragma once
// Every step's input of a session, stored as runs of identical inputs. A person at the workbench holds
// still far more often than not (a part resting, the mouse at rest, the base not turning), so an hour at
// 90 Hz (324,000 steps) keeps one copy per change instead of one per step: an hour of the gearbox's
// recording fits in a few megabytes (docs/benchmarks.md, "Recording an hour"). Reads like the vector it
// replaces: size, indexing (O(log runs)), iteration in step order, appending, and truncating the future.
// Two inputs are identical when every bit of them is: replays stay bit-identical.
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <vector>

#include "vaw/sim/world.hpp"

namespace vaw::sim {

// Bit for bit (so 0.0 and -0.0 differ, and a NaN equals itself).
bool identical(const Input& a, const Input& b);

class InputLog {
 public:
  InputLog() = default;
  InputLog(const std::vector<Input>& inputs);  // NOLINT(google-explicit-constructor): a script's inputs become a session's
  InputLog& operator=(const std::vector<Input>& inputs) { return *this = InputLog(inputs); }

  [[nodiscard]] std::size_t size() const { return size_; }
  [[nodiscard]] bool empty() const { return size_ == 0; }
  [[nodiscard]] const Input& operator[](std::size_t step) const;
  [[nodiscard]] const Input& back() const { return runs_.back().input; }
  void push_back(const Input& input);
  // Keeps the first n steps (n <= size()).
  void resize(std::size_t n);
  void reserve(std::size_t) {}  // runs are not known in advance
  [[nodiscard]] std::size_t runs() const { return runs_.size(); }
  // Heap bytes held (the runs' storage).
  [[nodiscard]] std::size_t bytes() const { return runs_.capacity() * sizeof(Run); }

  class const_iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = Input;
    using difference_type = std::ptrdiff_t;
    using pointer = const Input*;
    using reference = const Input&;
    const_iterator() = default;
    reference operator*() const { return log_->runs_[run_].input; }
    pointer operator->() const { return &**this; }
    const_iterator& operator++();
    const_iterator operator++(int) {
      const_iterator old = *this;
      ++*this;
      return old;
    }
    friend bool operator==(const const_iterator& a, const const_iterator& b) { return a.step_ == b.step_; }

   private:
    friend class InputLog;
    const_iterator(const InputLog* log, std::size_t step, std::size_t run) : log_(log), step_(step), run_(run) {}
    const InputLog* log_ = nullptr;
    std::size_t step_ = 0, run_ = 0;
  };
  [[nodiscard]] const_iterator begin() const { return {this, 0, 0}; }
  [[nodiscard]] const_iterator end() const { return {this, size_, runs_.size()}; }

 private:
  struct Run {
    std::uint64_t first;  // the run's first step; it lasts until the next run's first (or size_)
    Input input;
  };
  std::vector<Run> runs_;
  std::size_t size_ = 0;
};

}  // namespace vaw::sim
