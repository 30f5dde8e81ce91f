#include "background_export.hpp"

#include <QtConcurrent/QtConcurrent>

#include <algorithm>

#include "vaw/ui/background.hpp"

namespace vaw::ui {

BackgroundExport::BackgroundExport(QWidget* window, const char* task, QString title, QString objectName)
    : QObject(window), window_(window), task_(task), title_(std::move(title)), objectName_(std::move(objectName)) {
  connect(&watcher_, &QFutureWatcher<Outcome>::finished, this, &BackgroundExport::done);
}

BackgroundExport::~BackgroundExport() {
  if (cancel_) cancel_->store(true);
  watcher_.disconnect(this);
  watcher_.waitForFinished();
}

bool BackgroundExport::start(const QString& target, const QString& heading, Work work) {
  if (running()) return false;
  auto cancel = std::make_shared<std::atomic<bool>>(false);
  cancel_ = cancel;
  heading_ = heading;
  progress_ = new QProgressDialog(heading, tr("Stop"), 0, 1000, window_);
  progress_->setObjectName(objectName_);
  progress_->setWindowTitle(title_);
  progress_->setWindowModality(Qt::NonModal);
  progress_->setAutoClose(false);
  progress_->setAutoReset(false);
  progress_->setMinimumDuration(400);
  connect(progress_, &QProgressDialog::canceled, this, [cancel] { cancel->store(true); });
  // Queued to this object, which waits for the work before it goes.
  const ProgressFn progress = [this, cancel](double fraction, const std::string& what) {
    const int value = static_cast<int>(1000.0 * std::clamp(fraction, 0.0, 1.0));
    const QString text = QString::fromStdString(what);
    QMetaObject::invokeMethod(
        this,
        [this, cancel, value, text] {
          if (cancel != cancel_ || progress_ == nullptr) return;
          progress_->setValue(value);
          progress_->setLabelText(heading_ + QLatin1Char('\n') + text);
        },
        Qt::QueuedConnection);
    return !cancel->load();
  };
  const char* task = task_;
  watcher_.setFuture(QtConcurrent::run([target, work = std::move(work), progress, task] {
    Outcome out;
    out.target = target;
    try {
      const BackgroundTask running(task);
      out.written = work(progress);
    } catch (const LoadCancelled&) {
      out.cancelled = true;
    } catch (const std::exception& e) {  // vaw::OutputError naming the file, vaw::InputError, memory
      out.error = failureText(e);
    }
    return out;
  }));
  return true;
}

void BackgroundExport::done() {
  const Outcome out = watcher_.result();
  if (progress_ != nullptr) {
    progress_->close();
    progress_->deleteLater();
    progress_ = nullptr;
  }
  cancel_.reset();
  emit finished(out);
}

}  // namespace vaw::ui
