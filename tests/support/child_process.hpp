#pragma once
// Test code run in a child process: to check what survives a killed writer, a file-size limit, or two
// processes at one file.
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

namespace vaw::test {

// `body` in a forked child, which exits 0 when it returns; finish() waits for it.
template <class F>
pid_t startChild(F body) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    body();
    ::_exit(0);
  }
  return pid;
}

// The child's exit status, or 128 + the signal that ended it.
inline int finishChild(pid_t pid) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

template <class F>
int inChild(F body) {
  return finishChild(startChild(body));
}

}  // namespace vaw::test
