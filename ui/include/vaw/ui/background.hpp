#pragma once
// What the window's background tasks share (an import, the order search, the check at rest, the near
// misses, a sweep with its clearance, an export of the swept volume, a report): each runs on a pool thread
// and any failure it meets, an allocation's included, comes back as a message (docs/architecture.md, "Background work").
#include <QString>
#include <exception>

namespace vaw::ui {

// A failure as the user reads it: an allocation that failed is "not enough memory", anything else says itself.
QString failureText(const std::exception& e);

// Marks a background task's run on its own thread, from its start to its end, with its name: "import",
// "order", "interferences", "near misses", "sweep", "export", "report". The GUI tests make a task fail in
// the middle of its work through it (tests/gui/tst_faults.cpp); only code in the process can set the hook,
// which the application never does, so nothing outside can make a task fail.
class BackgroundTask {
 public:
  explicit BackgroundTask(const char* name);
  ~BackgroundTask();
  BackgroundTask(const BackgroundTask&) = delete;
  BackgroundTask& operator=(const BackgroundTask&) = delete;

  // Called with the task's name and true as it starts, false as it ends, on its thread.
  using Hook = void (*)(const char* task, bool starting);
  static void setHook(Hook hook);

 private:
  const char* name_;
};

}  // namespace vaw::ui
