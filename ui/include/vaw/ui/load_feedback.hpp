#pragma once
// What the user sees of a load: a progress dialog with Cancel for loads that take longer than
// ~300 ms, and an error dialog naming the file, field and expectation when a load fails.
#include <QMessageBox>
#include <QObject>
#include <QPointer>
#include <QProgressDialog>

namespace vaw::ui {

class AssemblyController;
struct LoadFailure;

class LoadFeedback : public QObject {
  Q_OBJECT
 public:
  static constexpr int kProgressDelayMs = 300;

  LoadFeedback(AssemblyController& controller, QWidget* dialogParent);
  // The error dialog currently open, if any (object name "loadErrorDialog"). It is window-modal
  // and not blocking (QDialog::open), so tests can read and close it.
  [[nodiscard]] QMessageBox* errorDialog() const { return errorDialog_; }

 private:
  void started(const QString& path);
  void progressed(double fraction, const QString& stage);
  void ended();
  void failed(const LoadFailure& failure);

  AssemblyController& controller_;
  QWidget* dialogParent_ = nullptr;
  QPointer<QProgressDialog> progress_;
  QPointer<QMessageBox> errorDialog_;
};

}  // namespace vaw::ui
