// Opening and saving: what a loaded file starts, File > Save (the scene with its tuning), the session, the
// evaluation report, and asking before unsaved tuning is dropped.
#include "vaw/ui/main_window.hpp"

#include <Qt3DRender/QCamera>
#include <QAction>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QDialog>
#include <QComboBox>
#include <QDialogButtonBox>
#include <QSpinBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QMessageBox>
#include <QMimeData>
#include <QProgressDialog>
#include <QSettings>
#include <QStatusBar>
#include <QUndoStack>
#include <QUrl>
#include <QtConcurrent/QtConcurrentRun>
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <thread>

#include "background_export.hpp"
#include "format.hpp"
#include "qt_convert.hpp"
#include "vaw/error.hpp"
#include "vaw/report/gltf.hpp"
#include "vaw/report/report.hpp"
#include "vaw/evaluation/session_stats.hpp"
#include "vaw/sim/scene_file.hpp"
#include "vaw/sim/session.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/background.hpp"
#include "vaw/ui/docks.hpp"
#include "vaw/ui/timeline.hpp"
#include "vaw/ui/message_log_model.hpp"
#include "vaw/ui/sequence_dock.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/trials_panel.hpp"
#include "vaw/ui/viewport.hpp"

namespace vaw::ui {

namespace {
bool isSceneFile(const QString& path) { return path.endsWith(QStringLiteral(".json"), Qt::CaseInsensitive) && !path.endsWith(QStringLiteral(".vaw-session.json")); }
}

void MainWindow::wireLoading() {
  connect(&controller_, &AssemblyController::assemblyLoaded, this, &MainWindow::assemblyLoaded);
  connect(&controller_, &AssemblyController::loadStarted, this, [this](const QString& path) {
    statusBar()->showMessage(tr("Opening %1...").arg(path));
  });
  connect(&controller_, &AssemblyController::loadFailed, this, [this](const LoadFailure& failure) {
    QStringList detail{tr("File: %1").arg(failure.file.isEmpty() ? failure.path : failure.file)};
    if (!failure.field.isEmpty()) detail << tr("Field: %1").arg(failure.field);
    if (!failure.expected.isEmpty()) detail << tr("Expected: %1").arg(failure.expected);
    if (!failure.found.isEmpty()) detail << tr("Found: %1").arg(failure.found);
    messagesDock_->model()->add(MessageLogModel::Severity::Error, failure.message, detail.join(QLatin1Char('\n')));
    statusBar()->showMessage(tr("Could not open %1").arg(QFileInfo(failure.path).fileName()));
  });
  connect(&controller_, &AssemblyController::loadCancelled, this, [this](const QString& path) {
    statusBar()->showMessage(tr("Opening %1 cancelled").arg(QFileInfo(path).fileName()));
  });
}

void MainWindow::assemblyLoaded() {
  const vaw::Assembly* assembly = controller_.assembly();
  const bool edited = controller_.isEditReload();  // its constraints changed: the same file, already announced
  const bool wasPlaying = simulation_->isPlaying();
  const std::string keepName = selectedName_;
  const QString keepFrom = selectedFrom_;
  reloadAction_->setEnabled(true);
  std::optional<vaw::sim::Session> session = controller_.takeSession();
  bool playback = false;
  if (session) {
    try {
      simulation_->startPlayback(controller_.scene(), std::move(*session));
      playback = true;
    } catch (const vaw::InputError& e) {
      message(static_cast<int>(MessageLogModel::Severity::Error), tr("The session cannot be played: %1").arg(e.what()));
    }
  }
  // A scene starts with the tuning its settings block saved.
  if (!playback)
    simulation_->start(controller_.scene(), controller_.sceneReference(), vaw::sim::settingsFor(controller_.scene()->assembly()));
  sceneDock_->setAssembly(assembly, controller_.collisionInfo());
  partDock_->showPart(assembly, std::nullopt);
  if (assembly == nullptr) return;
  // After a reload, the part that was selected stays selected (by name: ids may change).
  if (!keepName.empty() && keepFrom == controller_.currentPath()) viewport_->selectPart(assembly->findPart(keepName));
  if (!edited) scenePath_ = isSceneFile(controller_.currentPath()) ? controller_.currentPath() : QString();
  saveAction_->setEnabled(true);
  saveAsAction_->setEnabled(true);
  if (edited) {
    updateTitle();
    if (wasPlaying) simulation_->play();
    return;
  }
  addRecent(controller_.currentPath());
  for (const auto& warning : assembly->warnings) messagesDock_->model()->add(warning);
  updateTitle();
  const QString summary = tr("Opened %1: %n part(s)", nullptr, static_cast<int>(assembly->parts.size()))
                              .arg(QFileInfo(controller_.currentPath()).fileName()) +
                          tr(", %n triangle(s)", nullptr, static_cast<int>(assembly->totalTriangles())) +
                          (assembly->warnings.empty()
                               ? QString()
                               : tr(", %n warning(s) (see Messages)", nullptr,
                                    static_cast<int>(assembly->warnings.size())));
  messagesDock_->model()->add(MessageLogModel::Severity::Info, summary, controller_.currentPath());
  statusBar()->showMessage(playback ? tr("Opened a session of %1 s: press Play to watch it")
                                          .arg(format::number(simulation_->recorder().endTime()))
                                    : summary);
  if (!playback && autoPlay_) simulation_->play();
}

void MainWindow::openFileDialog() {
  const QString start =
      controller_.currentPath().isEmpty() ? QString() : QFileInfo(controller_.currentPath()).absolutePath();
  QStringList filters = controller_.fileDialogFilters();
  filters.insert(1, tr("Sessions (*.vaw-session.json)"));
  const QString path = QFileDialog::getOpenFileName(this, tr("Open scene, mesh or session"), start,
                                                    filters.join(QStringLiteral(";;")));
  if (!path.isEmpty()) openFile(path);
}

void MainWindow::openFile(const QString& path) {
  if (!maybeSave()) return;
  controller_.open(path);
}

void MainWindow::dragEnterEvent(QDragEnterEvent* event) {
  const QList<QUrl> urls = event->mimeData()->urls();
  if (!urls.isEmpty() && urls.front().isLocalFile()) event->acceptProposedAction();
}

// A file dropped on the window opens as File > Open would open it (a scene, a mesh, a STEP file, a session).
void MainWindow::dropEvent(QDropEvent* event) {
  const QList<QUrl> urls = event->mimeData()->urls();
  if (urls.isEmpty() || !urls.front().isLocalFile()) return;
  event->acceptProposedAction();
  openFile(urls.front().toLocalFile());
}

// File > STEP Settings: the tessellation and the reader's limits in one form; OK applies and keeps them.
void MainWindow::stepSettingsDialog() {
  const vaw::ImportOptions current = controller_.loadOptions().import;
  QDialog dialog(this);
  dialog.setWindowTitle(tr("STEP settings"));
  auto* form = new QFormLayout(&dialog);
  const auto field = [&](const char* name, const QString& label, int decimals, double least, double most, double value,
                         const QString& suffix, const QString& tip) {
    auto* box = new QDoubleSpinBox(&dialog);
    box->setObjectName(QString::fromLatin1(name));
    box->setDecimals(decimals);
    box->setRange(least, most);
    box->setSuffix(suffix);
    box->setValue(value);
    box->setToolTip(tip);
    form->addRow(label, box);
    return box;
  };
  auto* deflection = field("stepDeflection", tr("Tessellation (fraction of part size)"), 4, 0.0001, 0.05, current.relativeDeflection, {},
                           tr("Chordal deflection as a fraction of each part's size: smaller is finer (more triangles, slower collision)"));
  deflection->setSingleStep(0.0005);
  auto* timeout = field("stepTimeout", tr("Time limit"), 0, 5, 86400, current.timeoutSeconds, tr(" s"),
                        tr("A file Open CASCADE has not read by then is given up with an error"));
  auto* memory = field("stepMemory", tr("Reader memory"), 0, 0, 1e7, current.readerMemoryMB, tr(" MB"),
                       tr("The reader's memory limit: a file that needs more ends with an error, never the window"));
  memory->setSpecialValueText(tr("half the machine's memory"));
  auto* instances = field("stepMaxInstances", tr("Most part instances"), 0, 1, 1e9, current.maxInstances, {},
                          tr("Part instances a file may declare, its assembly tree expanded; more is refused before reading"));
  auto* kept = field("stepResultCache", tr("Reads kept for reopening"), 0, 0, 1e6, current.resultCacheMB, tr(" MB"),
                     tr("An unchanged file opens again without Open CASCADE reading it; the least recently used go first past this size"));
  kept->setSpecialValueText(tr("none"));
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel, &dialog);
  connect(buttons, &QDialogButtonBox::accepted, &dialog, &QDialog::accept);
  connect(buttons, &QDialogButtonBox::rejected, &dialog, &QDialog::reject);
  form->addRow(buttons);
  if (dialog.exec() != QDialog::Accepted) return;
  vaw::ImportOptions chosen = current;
  chosen.relativeDeflection = deflection->value();
  chosen.timeoutSeconds = timeout->value();
  chosen.readerMemoryMB = memory->value();
  chosen.maxInstances = instances->value();
  chosen.resultCacheMB = kept->value();
  setStepSettings(chosen);
}

void MainWindow::setStepSettings(const vaw::ImportOptions& import) {
  vaw::LoadOptions options = controller_.loadOptions();
  const bool finer = options.import.relativeDeflection != import.relativeDeflection;
  options.import = import;
  controller_.setLoadOptions(options);
  QSettings settings;
  settings.setValue(QStringLiteral("import/relativeDeflection"), import.relativeDeflection);
  settings.setValue(QStringLiteral("import/timeoutSeconds"), import.timeoutSeconds);
  settings.setValue(QStringLiteral("import/readerMemoryMB"), import.readerMemoryMB);
  settings.setValue(QStringLiteral("import/maxInstances"), import.maxInstances);
  settings.setValue(QStringLiteral("import/resultCacheMB"), import.resultCacheMB);
  const QString text = tr("STEP: tessellation %1 of each part's size, time limit %2 s, reader memory %3, at most %4 part instances, "
                          "reads kept for reopening %5")
                           .arg(import.relativeDeflection)
                           .arg(import.timeoutSeconds)
                           .arg(import.readerMemoryMB > 0.0 ? tr("%1 MB").arg(import.readerMemoryMB) : tr("half the machine's"))
                           .arg(import.maxInstances)
                           .arg(import.resultCacheMB > 0.0 && !import.resultCache.empty() ? tr("up to %1 MB in %2").arg(import.resultCacheMB).arg(QString::fromStdString(import.resultCache.string()))
                                                                                       : tr("none"));
  message(static_cast<int>(MessageLogModel::Severity::Info), text);
  statusBar()->showMessage(text, 8000);
  // A new tessellation reads the open STEP assembly anew, asking first about unsaved changes; the limits
  // only matter for the next file.
  const vaw::Assembly* a = controller_.assembly();
  if (finer && a != nullptr && !a->cadFile.empty() && maybeSave()) controller_.reload();
}

bool MainWindow::save() {
  if (savingWaitsForTrials()) return false;
  if (scenePath_.isEmpty()) return saveAs();
  return saveScene(scenePath_);
}

bool MainWindow::saveAs() {
  if (!simulation_->hasWorld() || savingWaitsForTrials()) return false;
  const vaw::Assembly& loaded = simulation_->world().assembly();
  // A CAD file is saved as a scene that refers to it (vaw::sim::saveScene).
  const bool cad = !loaded.cadFile.empty();
  if (!cad && !isSceneFile(QFile::decodeName(loaded.source.string().c_str()))) {
    const QString text = tr("Only a scene (.vaw.json) can be saved with its tuning; %1 is not one. Save the session instead.")
                             .arg(QFile::decodeName(loaded.source.filename().string().c_str()));
    message(static_cast<int>(MessageLogModel::Severity::Warning), text);
    statusBar()->showMessage(text, 10000);
    return false;
  }
  QString start = scenePath_.isEmpty() ? QFile::decodeName(loaded.source.string().c_str()) : scenePath_;
  if (cad && scenePath_.isEmpty()) {
    std::filesystem::path next = loaded.cadFile;
    start = QFile::decodeName(next.replace_extension(".vaw.json").string().c_str());
  }
  QString file = QFileDialog::getSaveFileName(this, tr("Save scene with its tuning"), start, tr("Scenes (*.vaw.json)"));
  if (file.isEmpty()) return false;
  if (!file.endsWith(QStringLiteral(".json"))) file += QStringLiteral(".vaw.json");
  return saveScene(file);
}

bool MainWindow::saveScene(const QString& file) {
  if (!simulation_->hasWorld()) return false;
  try {
    vaw::sim::saveScene(simulation_->world().assembly(), simulation_->world(),
                        std::filesystem::path(QFile::encodeName(file).toStdString()));
  } catch (const std::exception& e) {  // vaw::InputError, or vaw::OutputError when the disk refuses it
    const QString text = tr("Could not save the scene: %1").arg(QString::fromUtf8(e.what()));
    message(static_cast<int>(MessageLogModel::Severity::Error), text);
    statusBar()->showMessage(text, 10000);
    return false;
  }
  scenePath_ = file;
  undoStack_->setClean();
  addRecent(file);
  const QString text = tr("Saved the scene with its tuning to %1").arg(file);
  message(static_cast<int>(MessageLogModel::Severity::Info), text);
  statusBar()->showMessage(text, 8000);
  updateTitle();
  return true;
}

bool MainWindow::maybeSave() {
  if (!hasUnsavedChanges()) return true;
  QMessageBox box(QMessageBox::Warning, tr("Unsaved tuning"),
                  tr("The gravity, friction or method settings were changed and not saved."),
                  QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel, this);
  box.setObjectName(QStringLiteral("unsavedChangesBox"));
  box.setInformativeText(tr("Save them with the scene?"));
  box.setDefaultButton(QMessageBox::Save);
  switch (box.exec()) {
    case QMessageBox::Save: return save();
    case QMessageBox::Discard: return true;
    default: return false;
  }
}

bool MainWindow::hasUnsavedChanges() const { return !undoStack_->isClean(); }

void MainWindow::updateTitle() {
  const vaw::Assembly* assembly = controller_.assembly();
  QString name = assembly == nullptr ? QString() : QString::fromStdString(assembly->name);
  if (name.isEmpty()) name = QFileInfo(controller_.currentPath()).fileName();
  setWindowTitle(name.isEmpty() ? tr("vaw") : tr("%1[*] - vaw").arg(name));
  setWindowModified(hasUnsavedChanges());
}

bool MainWindow::savingWaitsForTrials() {
  if (!trialsDock_->running()) return false;
  const QString text = tr("Nothing was saved: a trials session is running, and the world plays the trial's scale, not the "
                          "scene's. Stop the session first (its answers are on disk, and Start resumes it).");
  message(static_cast<int>(MessageLogModel::Severity::Warning), text);
  statusBar()->showMessage(text, 10000);
  return true;
}

void MainWindow::saveSessionDialog() {
  if (!simulation_->hasWorld() || savingWaitsForTrials()) return;
  const QString file = QFileDialog::getSaveFileName(this, tr("Save session"), QStringLiteral("session.vaw-session.json"),
                                                    tr("Sessions (*.vaw-session.json)"));
  if (!file.isEmpty()) saveSession(file);
}

bool MainWindow::saveSession(const QString& file) {
  if (!simulation_->hasWorld()) return false;
  try {
    vaw::sim::saveSession(simulation_->recorder().session(), std::filesystem::path(QFile::encodeName(file).toStdString()));
    const QString text = tr("Saved the session (%1 s, %2 steps) to %3")
                             .arg(format::number(simulation_->recorder().endTime()))
                             .arg(simulation_->recorder().length())
                             .arg(file);
    message(static_cast<int>(MessageLogModel::Severity::Info), text);
    statusBar()->showMessage(text, 8000);
    return true;
  } catch (const std::exception& e) {  // vaw::OutputError too: a full disk must not take the window down
    message(static_cast<int>(MessageLogModel::Severity::Error), tr("Could not save the session: %1").arg(e.what()));
    return false;
  }
}

void MainWindow::exportReportDialog() {
  if (controller_.assembly() == nullptr) return;
  const QString dir =
      QFileDialog::getExistingDirectory(this, tr("Export the report into"), QFileInfo(controller_.currentPath()).absolutePath());
  if (!dir.isEmpty()) exportReport(dir);
}

void MainWindow::exportReport(const QString& dir) {
  if (controller_.assembly() == nullptr) return;
  if (sequenceDock_->plan() != nullptr) {
    writeReport(dir);
    return;
  }
  pendingReport_ = dir;
  // Where the search's progress and any reason it finds no order show.
  sequenceDock_->show();
  sequenceDock_->raise();
  if (!sequenceDock_->finding()) sequenceDock_->findOrder();
  statusBar()->showMessage(tr("Finding the order for the report..."));
}

void MainWindow::writeReport(const QString& dir) {
  const vaw::eval::SequencePlan* plan = sequenceDock_->plan();
  std::shared_ptr<const vaw::sim::Scene> scene = controller_.scene();
  if (plan == nullptr || !scene) return;
  if (writingReport()) {
    const QString text = tr("No report written to %1: another is being written; stop it or wait for it").arg(dir);
    message(static_cast<int>(MessageLogModel::Severity::Error), text);
    statusBar()->showMessage(text, 15000);
    return;
  }
  // What the worker reads, copied: the window goes on simulating, recording and editing meanwhile.
  auto order = std::make_shared<const vaw::eval::SequencePlan>(*plan);
  // The ways home as the Sequence panel walked them (without swept volumes: the pictures show arrows).
  auto ways = std::make_shared<vaw::report::WaysHome>();
  ways->ways = sequenceDock_->ways();
  ways->options = sequenceDock_->wayOptions();
  std::shared_ptr<const vaw::sim::Scene> recordedOn;
  auto session = std::make_shared<vaw::sim::Session>();
  if (simulation_->hasWorld() && simulation_->recorder().length() > 0) {
    recordedOn = simulation_->recorder().scenePtr();
    *session = simulation_->recorder().session();
  }
  const std::string label = tr("this session").toStdString();
  const std::filesystem::path where(QFile::encodeName(dir).toStdString());

  auto cancel = std::make_shared<std::atomic<bool>>(false);
  reportCancel_ = cancel;
  reportHeading_ = tr("Writing the report into %1").arg(dir);
  reportProgress_ = new QProgressDialog(reportHeading_, tr("Stop"), 0, 1000, this);
  reportProgress_->setObjectName(QStringLiteral("reportProgress"));
  reportProgress_->setWindowTitle(tr("Export Report"));
  // The window stays in use while the report is written.
  reportProgress_->setWindowModality(Qt::NonModal);
  reportProgress_->setAutoClose(false);
  reportProgress_->setAutoReset(false);
  reportProgress_->setMinimumDuration(400);
  connect(reportProgress_, &QProgressDialog::canceled, this, [cancel] { cancel->store(true); });
  // The replay takes most of the time when there is a session; the pictures the rest.
  const double replayShare = recordedOn ? 0.8 : 0.0;
  const int pace = reportPaceMs_;  // setReportPace: the GUI tests
  const auto stage = [this, cancel, pace](double from, double share) -> vaw::ProgressFn {
    return [this, cancel, from, share, pace](double fraction, const std::string& what) {
      if (pace > 0) std::this_thread::sleep_for(std::chrono::milliseconds(pace));
      const int value = static_cast<int>(1000.0 * (from + share * std::clamp(fraction, 0.0, 1.0)));
      const QString text = QString::fromStdString(what);
      // "Writing the report into DIR" and under it the stage: "replaying this session", "drawing picture 3 of 9".
      // Queued to this window, which waits for the worker before it goes (~MainWindow).
      QMetaObject::invokeMethod(
          this,
          [this, cancel, value, text] {
            if (cancel != reportCancel_ || reportProgress_ == nullptr) return;
            reportProgress_->setValue(value);
            reportProgress_->setLabelText(reportHeading_ + QLatin1Char('\n') + text);
          },
          Qt::QueuedConnection);
      return !cancel->load();
    };
  };
  statusBar()->showMessage(tr("Writing the report into %1...").arg(dir));
  reportWatcher_.setFuture(QtConcurrent::run([=] {
    ReportOutcome out;
    out.dir = dir;
    try {
      const BackgroundTask task("report");
      std::vector<vaw::eval::SessionStats> sessions;
      // The session replayed on the scene it was recorded on: a trial's scale is not the scene's.
      if (recordedOn) sessions.push_back(vaw::eval::sessionStats(recordedOn, *session, label, stage(0.0, replayShare)));
      const vaw::report::ReportFiles files =
          vaw::report::writeReport(scene->assembly(), *order, sessions, where, stage(replayShare, 1.0 - replayShare),
                                   ways->ways.empty() ? nullptr : ways.get());
      out.html = QFile::decodeName(files.html.string().c_str());
      if (!sessions.empty()) out.session = QString::number(sessions.front().duration_s, 'f', 2);
    } catch (const vaw::LoadCancelled&) {
      out.cancelled = true;
    } catch (const std::exception& e) {  // vaw::OutputError naming the file; a failed replay too
      out.error = failureText(e);
    }
    return out;
  }));
}

void MainWindow::reportFinished() {
  const ReportOutcome out = reportWatcher_.result();
  if (reportProgress_ != nullptr) {
    reportProgress_->close();
    reportProgress_->deleteLater();
    reportProgress_ = nullptr;
  }
  reportCancel_.reset();
  QString text;
  if (out.cancelled) {
    text = tr("Stopped: no report written to %1").arg(out.dir);
    message(static_cast<int>(MessageLogModel::Severity::Info), text);
  } else if (!out.error.isEmpty()) {
    text = tr("Could not write the report into %1: %2").arg(out.dir, out.error);
    message(static_cast<int>(MessageLogModel::Severity::Error), text);
  } else {
    text = tr("Wrote the report to %1").arg(out.html);
    message(static_cast<int>(MessageLogModel::Severity::Info), text,
            out.session.isEmpty() ? tr("No session: nothing was simulated yet.") : tr("With this session (%1 s).").arg(out.session));
  }
  statusBar()->showMessage(text, 15000);
}

bool MainWindow::exportingVideo() const { return videoExport_ != nullptr && videoExport_->running(); }
QProgressDialog* MainWindow::videoProgress() const { return videoExport_ != nullptr ? videoExport_->progress() : nullptr; }

void MainWindow::exportVideoDialog() {
  if (!simulation_->hasWorld() || simulation_->recorder().length() == 0) {
    statusBar()->showMessage(tr("No video: nothing is recorded yet (play the simulation first)"), 15000);
    return;
  }
  QDialog d(this);
  d.setObjectName(QStringLiteral("videoDialog"));
  d.setWindowTitle(tr("Export Video"));
  auto* form = new QFormLayout(&d);
  auto* size = new QComboBox(&d);
  size->setObjectName(QStringLiteral("videoSize"));
  for (const QSize s : {QSize(1920, 1080), QSize(1280, 720), QSize(854, 480), QSize(640, 360)})
    size->addItem(tr("%1 × %2").arg(s.width()).arg(s.height()), s);
  size->setCurrentIndex(1);
  form->addRow(tr("Size"), size);
  auto* fps = new QSpinBox(&d);
  fps->setObjectName(QStringLiteral("videoFps"));
  fps->setRange(1, 60);
  fps->setValue(30);
  fps->setSuffix(tr(" frames/s"));
  form->addRow(tr("Frame rate"), fps);
  auto* camera = new QComboBox(&d);
  camera->setObjectName(QStringLiteral("videoCamera"));
  camera->addItem(tr("Following the work"), QStringLiteral("auto"));
  if (const auto selected = viewport_->selectedPart())
    camera->addItem(tr("Close on %1").arg(QString::fromStdString(controller_.assembly()->parts[*selected].name)),
                    QStringLiteral("follow ") + QString::fromStdString(controller_.assembly()->parts[*selected].name));
  for (const auto& [label, view] : {std::pair{tr("From the home view"), QStringLiteral("iso")}, {tr("From the front"), QStringLiteral("front")},
                                    {tr("From above"), QStringLiteral("top")}})
    camera->addItem(label, view);
  camera->addItem(tr("As the viewport shows it now"), QStringLiteral("viewport"));
  form->addRow(tr("Camera"), camera);
  // The whole recording, or the part of it the timeline shows when that is less (zoomed or panned).
  auto* span = new QComboBox(&d);
  span->setObjectName(QStringLiteral("videoSpan"));
  const double end = static_cast<double>(simulation_->recorder().length()) * simulation_->recorder().session().settings.step();
  span->addItem(tr("The whole recording (%1 s)").arg(format::number(end, 1)), QPointF(0.0, end));
  const double shownFrom = std::clamp(timelineDock_->view()->visibleStart(), 0.0, end);
  const double shownTo = std::clamp(timelineDock_->view()->visibleEnd(), 0.0, end);
  if (shownTo - shownFrom > 0.05 && (shownFrom > 0.05 || shownTo < end - 0.05))
    span->addItem(tr("What the timeline shows (%1 to %2 s)").arg(format::number(shownFrom, 1), format::number(shownTo, 1)), QPointF(shownFrom, shownTo));
  form->addRow(tr("Span"), span);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel, &d);
  connect(buttons, &QDialogButtonBox::accepted, &d, &QDialog::accept);
  connect(buttons, &QDialogButtonBox::rejected, &d, &QDialog::reject);
  form->addRow(buttons);
  if (d.exec() != QDialog::Accepted) return;
  vaw::video::VideoOptions options;
  options.width = size->currentData().toSize().width();
  options.height = size->currentData().toSize().height();
  options.fps = fps->value();
  if (camera->currentData().toString() == QStringLiteral("viewport")) {
    const Qt3DRender::QCamera* eye = viewport_->camera();
    options.camera.kind = vaw::video::Camera::Kind::Eye;
    options.camera.position = toEigen(eye->position());
    options.camera.target = toEigen(eye->viewCenter());
    options.camera.up = toEigen(eye->upVector());
    options.camera.verticalFovDeg = eye->fieldOfView();
  } else {
    options.camera = vaw::video::parseCamera(camera->currentData().toString().toStdString()).value_or(vaw::video::Camera{});
  }
  if (span->currentIndex() > 0) {
    options.from = span->currentData().toPointF().x();
    options.to = span->currentData().toPointF().y();
  }
  const QString suggested = QFileInfo(controller_.currentPath()).absolutePath() + QLatin1Char('/') +
                            QFileInfo(controller_.currentPath()).completeBaseName() + QStringLiteral(".mp4");
  QString file = QFileDialog::getSaveFileName(this, tr("Export Video"), suggested, tr("MP4 video (*.mp4)"));
  if (file.isEmpty()) return;
  if (!file.endsWith(QStringLiteral(".mp4"), Qt::CaseInsensitive)) file += QStringLiteral(".mp4");
  exportVideo(file, options);
}

BackgroundExport* MainWindow::exporter(BackgroundExport*& slot, const char* task, const QString& title, const QString& what) {
  if (slot != nullptr) return slot;
  slot = new BackgroundExport(this, task, title, QStringLiteral("%1Progress").arg(QLatin1String(task)));
  connect(slot, &BackgroundExport::finished, this, [this, what](const BackgroundExport::Outcome& out) {
    QString text;
    if (out.cancelled) {
      text = tr("Stopped: no %1 written to %2").arg(what, out.target);
      message(static_cast<int>(MessageLogModel::Severity::Info), text);
    } else if (!out.error.isEmpty()) {
      text = tr("Could not write the %1 %2: %3").arg(what, out.target, out.error);
      message(static_cast<int>(MessageLogModel::Severity::Error), text);
    } else {
      text = tr("Wrote the %1 to %2 (%3)").arg(what, out.target, out.written);
      message(static_cast<int>(MessageLogModel::Severity::Info), text);
    }
    statusBar()->showMessage(text, 15000);
  });
  return slot;
}

void MainWindow::exportVideo(const QString& file, const vaw::video::VideoOptions& options) {
  if (!simulation_->hasWorld() || simulation_->recorder().length() == 0) return;
  exporter(videoExport_, "video", tr("Export Video"), tr("video"));
  // What the worker reads, copied: the window goes on simulating and recording meanwhile.
  const std::shared_ptr<const vaw::sim::Scene> scene = simulation_->recorder().scenePtr();
  auto session = std::make_shared<const vaw::sim::Session>(simulation_->recorder().session());
  const std::filesystem::path where(QFile::encodeName(file).toStdString());
  const bool started = videoExport_->start(file, tr("Writing the video %1").arg(file), [scene, session, where, options](const vaw::ProgressFn& progress) {
    const vaw::video::VideoResult r = vaw::video::writeSessionVideo(scene, *session, where, options, progress);
    return tr("%1 frames, %2 s at %3 × %4").arg(r.frames).arg(r.seconds, 0, 'f', 1).arg(options.width).arg(options.height);
  });
  const QString text = started ? tr("Writing the video %1...").arg(file)
                               : tr("No video written to %1: another is being written; stop it or wait for it").arg(file);
  if (!started) message(static_cast<int>(MessageLogModel::Severity::Error), text);
  statusBar()->showMessage(text, started ? 0 : 15000);
}

bool MainWindow::exportingGltf() const { return gltfExport_ != nullptr && gltfExport_->running(); }

void MainWindow::exportGltfDialog() {
  if (controller_.assembly() == nullptr || !simulation_->hasWorld()) return;
  const QString suggested = QFileInfo(controller_.currentPath()).absolutePath() + QLatin1Char('/') +
                            QFileInfo(controller_.currentPath()).completeBaseName() + QStringLiteral(".glb");
  QString file = QFileDialog::getSaveFileName(this, tr("Export glTF"), suggested, tr("glTF 2.0 binary (*.glb)"));
  if (file.isEmpty()) return;
  if (!file.endsWith(QStringLiteral(".glb"), Qt::CaseInsensitive)) file += QStringLiteral(".glb");
  exportGltf(file);
}

void MainWindow::exportGltf(const QString& file) {
  if (!simulation_->hasWorld()) return;
  BackgroundExport* job = exporter(gltfExport_, "gltf", tr("Export glTF"), tr("glTF file"));
  const std::shared_ptr<const vaw::sim::Scene> scene = simulation_->recorder().scenePtr();
  const bool recorded = simulation_->recorder().length() > 0;
  auto session = std::make_shared<const vaw::sim::Session>(simulation_->recorder().session());
  const std::filesystem::path where(QFile::encodeName(file).toStdString());
  const bool started = job->start(file, tr("Writing %1").arg(file), [scene, session, recorded, where](const vaw::ProgressFn& progress) {
    if (progress && !progress(0.0, "replaying the recording")) throw vaw::LoadCancelled();
    // The recording sampled as `vaw-sim export` samples it (30 a second, thinned within 0.1 mm).
    const vaw::report::Motion motion = recorded ? vaw::report::sessionMotion(scene, *session, 30.0) : vaw::report::Motion{};
    if (progress && !progress(0.8, "writing the file")) throw vaw::LoadCancelled();
    vaw::report::writeGlb(where, scene->assembly(), motion);
    std::error_code ec;
    const auto bytes = std::filesystem::file_size(where, ec);
    return (recorded ? tr("%1 s of the recording").arg(motion.duration, 0, 'f', 1) : tr("the scene at rest")) +
           tr(", %1 kB").arg(static_cast<double>(ec ? 0 : bytes) / 1e3, 0, 'f', 1);
  });
  const QString text = started ? tr("Writing %1...").arg(file) : tr("No glTF file written to %1: another is being written").arg(file);
  if (!started) message(static_cast<int>(MessageLogModel::Severity::Error), text);
  statusBar()->showMessage(text, started ? 0 : 15000);
}

}  // namespace vaw::ui
