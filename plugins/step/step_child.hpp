#pragma once
// What the STEP plugin's children (vaw-step-import, vaw-step-write) do first: each ends with the process that
// started it, even when that one is killed, and keeps to a memory limit, so that a hostile file or a solid
// too large neither outlives the window nor makes the machine's OOM killer choose the window.
#include <sys/prctl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>

#if defined(__SANITIZE_ADDRESS__)
#define VAW_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define VAW_ADDRESS_SANITIZER 1
#endif
#endif

namespace vaw::step {

// AddressSanitizer reserves terabytes of address space for its shadow memory, so under it an address-space
// limit would end the child at its first allocation: it runs without one there.
#ifdef VAW_ADDRESS_SANITIZER
inline constexpr bool kAddressSanitizer = true;
#else
inline constexpr bool kAddressSanitizer = false;
#endif

// Dies with `parent` (when > 0) and limits its address space to `memoryMB` (when > 0). False when the parent
// is gone already: the child should exit at once (code 6).
inline bool containChild(long parent, double memoryMB) {
  if (parent > 0) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != static_cast<pid_t>(parent)) return false;
  }
  if (memoryMB > 0.0 && !kAddressSanitizer) {
    const auto bytes = static_cast<rlim_t>(memoryMB * 1048576.0);
    const rlimit limit{bytes, bytes};
    setrlimit(RLIMIT_AS, &limit);
  }
  return true;
}

}  // namespace vaw::step
