#include "on_cores.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace vaw::detail {

void onCores(std::size_t count, const std::function<void(std::size_t, bool)>& work) {
  std::atomic<std::size_t> next{0};
  std::exception_ptr failed;
  std::mutex failing;
  const auto run = [&](bool onCaller) {
    for (std::size_t i; (i = next.fetch_add(1)) < count;) {
      try {
        work(i, onCaller);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(failing);
        if (!failed) failed = std::current_exception();
        next = count;
      }
    }
  };
  {
    const std::size_t threads = std::min<std::size_t>(std::clamp(std::thread::hardware_concurrency(), 1u, 8u), count);
    std::vector<std::jthread> pool;
    for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(run, false);
    run(true);
  }
  if (failed) std::rethrow_exception(failed);
}

}  // namespace vaw::detail
