#pragma once
// A file written off the window's thread with a progress window that has Stop (File > Export Video): the
// work is handed a ProgressFn that moves the progress window and says whether to go on; what came of it
// (written, stopped, or failed and why) comes back on the window's thread through finished(). The window
// stays in use meanwhile, and the simulation goes on.
#include <QFutureWatcher>
#include <QObject>
#include <QPointer>
#include <QProgressDialog>
#include <QString>

#include <atomic>
#include <functional>
#include <memory>

#include "vaw/importer.hpp"

namespace vaw::ui {

class BackgroundExport : public QObject {
  Q_OBJECT
 public:
  struct Outcome {
    QString target;      // what was asked for
    QString written;     // what the work said it wrote, when it did
    bool cancelled = false;
    QString error;       // why not, when it failed
  };
  // What runs on the pool thread: writes `target` and says what it wrote, or throws (vaw::LoadCancelled
  // when the ProgressFn said stop).
  using Work = std::function<QString(const ProgressFn&)>;

  // `task`: the BackgroundTask name the work runs under ("video"); `title`: the progress window's.
  BackgroundExport(QWidget* window, const char* task, QString title, QString objectName);
  // Stops the work and waits for it: nothing of it outlives the window.
  ~BackgroundExport() override;

  // Starts `work` with `heading` over the progress window's stage line; false (and nothing started) while
  // another is running.
  bool start(const QString& target, const QString& heading, Work work);
  [[nodiscard]] bool running() const { return cancel_ != nullptr; }
  // The progress window while one runs (it shows after 400 ms), else null.
  [[nodiscard]] QProgressDialog* progress() const { return progress_; }

 signals:
  void finished(const vaw::ui::BackgroundExport::Outcome& outcome);

 private:
  void done();

  QWidget* window_;
  const char* task_;
  QString title_, objectName_, heading_;
  QFutureWatcher<Outcome> watcher_;
  std::shared_ptr<std::atomic<bool>> cancel_;  // set while one runs; true: stop asked
  QPointer<QProgressDialog> progress_;
};

}  // namespace vaw::ui
