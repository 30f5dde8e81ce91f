#include "vaw/ui/load_feedback.hpp"

#include <QFileInfo>
#include <QMessageBox>
#include <QProgressDialog>
#include <QStringList>
#include <algorithm>
#include <cmath>

#include "vaw/ui/assembly_controller.hpp"

namespace vaw::ui {

LoadFeedback::LoadFeedback(AssemblyController& controller, QWidget* dialogParent)
    : QObject(dialogParent), controller_(controller), dialogParent_(dialogParent) {
  connect(&controller, &AssemblyController::loadStarted, this, &LoadFeedback::started);
  connect(&controller, &AssemblyController::progress, this, &LoadFeedback::progressed);
  connect(&controller, &AssemblyController::loadFinished, this, &LoadFeedback::ended);
  connect(&controller, &AssemblyController::loadFailed, this, &LoadFeedback::failed);
}

void LoadFeedback::started(const QString& path) {
  if (progress_) progress_->deleteLater();
  progress_ = new QProgressDialog(tr("Opening %1...").arg(QFileInfo(path).fileName()), tr("Cancel"), 0, 1000,
                                  dialogParent_);
  progress_->setObjectName(QStringLiteral("loadProgressDialog"));
  progress_->setWindowTitle(tr("Opening"));
  progress_->setWindowModality(Qt::WindowModal);
  progress_->setMinimumDuration(kProgressDelayMs);  // shown only for loads that take a while
  progress_->setAutoClose(false);
  progress_->setAutoReset(false);
  progress_->setValue(0);
  connect(progress_, &QProgressDialog::canceled, &controller_, &AssemblyController::cancelLoad);
}

void LoadFeedback::progressed(double fraction, const QString& stage) {
  if (!progress_ || !controller_.isLoading()) return;  // late progress of a finished load
  progress_->setLabelText(stage);
  progress_->setValue(static_cast<int>(std::lround(std::clamp(fraction, 0.0, 1.0) * 999.0)));
}

void LoadFeedback::ended() {
  if (!progress_) return;
  progress_->disconnect(this);
  progress_->disconnect(&controller_);
  progress_->hide();
  progress_->deleteLater();
}

void LoadFeedback::failed(const LoadFailure& failure) {
  if (errorDialog_) errorDialog_->close();
  auto* box = new QMessageBox(QMessageBox::Critical, tr("Cannot open %1").arg(QFileInfo(failure.path).fileName()),
                              failure.message, QMessageBox::Ok, dialogParent_);
  box->setObjectName(QStringLiteral("loadErrorDialog"));
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->setInformativeText(tr("The assembly that was open stays open."));
  QStringList detail;
  if (failure.inputError) {
    detail << tr("File: %1").arg(failure.file.isEmpty() ? failure.path : failure.file);
    if (!failure.field.isEmpty()) detail << tr("Field: %1").arg(failure.field);
    if (!failure.expected.isEmpty()) detail << tr("Expected: %1").arg(failure.expected);
    if (!failure.found.isEmpty()) detail << tr("Found: %1").arg(failure.found);
  } else {
    detail << tr("File: %1").arg(failure.path);
  }
  box->setDetailedText(detail.join(QLatin1Char('\n')));
  box->setWindowModality(Qt::WindowModal);
  errorDialog_ = box;
  box->open();
}

}  // namespace vaw::ui
