#include "vaw/ui/background.hpp"

#include <atomic>
#include <new>

#include <QCoreApplication>

namespace vaw::ui {

namespace {
std::atomic<BackgroundTask::Hook> hook{nullptr};
}

QString failureText(const std::exception& e) {
  if (dynamic_cast<const std::bad_alloc*>(&e) != nullptr) return QCoreApplication::translate("vaw::ui", "not enough memory");
  return QString::fromUtf8(e.what());
}

BackgroundTask::BackgroundTask(const char* name) : name_(name) {
  if (const Hook h = hook.load()) h(name_, true);
}

BackgroundTask::~BackgroundTask() {
  if (const Hook h = hook.load()) h(name_, false);
}

void BackgroundTask::setHook(Hook h) { hook.store(h); }

}  // namespace vaw::ui
