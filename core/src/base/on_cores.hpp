#pragma once
// Work spread over the machine's cores (private to the core's sources).
#include <cstddef>
#include <functional>

namespace vaw::detail {

// Calls work(i, onCaller) once for every i in [0, count), on as many threads as the machine has cores (at
// most 8), the calling thread among them: `onCaller` is true there, and only there may the work report
// progress to a user's callback. Indices are started in rising order. The first exception a call throws
// stops the others from starting another index and is rethrown here once every thread has finished.
void onCores(std::size_t count, const std::function<void(std::size_t, bool)>& work);

}  // namespace vaw::detail
