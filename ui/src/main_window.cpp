#include "vaw/ui/main_window.hpp"

#include <QAction>
#include <QFileDialog>
#include <QFileInfo>
#include <QKeySequence>
#include <QMenuBar>
#include <QStatusBar>

#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/docks.hpp"
#include "vaw/ui/load_feedback.hpp"
#include "vaw/ui/message_log_model.hpp"
#include "vaw/ui/viewport.hpp"

namespace vaw::ui {

MainWindow::MainWindow(AssemblyController& controller, QWidget* parent)
    : QMainWindow(parent), controller_(controller) {
  setObjectName(QStringLiteral("mainWindow"));
  setWindowTitle(tr("vaw"));
  viewport_ = new Viewport(this);
  setCentralWidget(viewport_);
  sceneDock_ = new SceneDock(this);
  partDock_ = new PartDock(this);
  messagesDock_ = new MessagesDock(this);
  addDockWidget(Qt::LeftDockWidgetArea, sceneDock_);
  addDockWidget(Qt::LeftDockWidgetArea, partDock_);
  addDockWidget(Qt::BottomDockWidgetArea, messagesDock_);
  resizeDocks({sceneDock_, partDock_}, {320, 380}, Qt::Vertical);
  resizeDocks({sceneDock_}, {380}, Qt::Horizontal);
  resizeDocks({messagesDock_}, {110}, Qt::Vertical);
  loadFeedback_ = new LoadFeedback(controller_, this);
  createMenus();

  // Selection: both views speak PartIds; each ignores a selection it already shows, so the echo stops.
  connect(sceneDock_, &SceneDock::partSelected, viewport_, &Viewport::selectPart);
  connect(viewport_, &Viewport::partSelected, sceneDock_, &SceneDock::selectPart);
  connect(viewport_, &Viewport::partSelected, this, &MainWindow::showSelection);

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

  for (const QString& message : controller_.pluginMessages()) {
    messagesDock_->model()->add(MessageLogModel::Severity::Warning, message);
  }
  if (!controller_.pluginMessages().isEmpty()) statusBar()->showMessage(controller_.pluginMessages().last());
}

void MainWindow::createMenus() {
  QMenu* file = menuBar()->addMenu(tr("&File"));
  QAction* open = file->addAction(tr("&Open..."), this, &MainWindow::openFileDialog);
  open->setShortcut(QKeySequence::Open);
  reloadAction_ = file->addAction(tr("&Reload"), &controller_, &AssemblyController::reload);
  reloadAction_->setShortcut(QKeySequence::Refresh);
  reloadAction_->setEnabled(false);
  file->addSeparator();
  QAction* quit = file->addAction(tr("&Quit"), this, &QWidget::close);
  quit->setShortcut(QKeySequence::Quit);

  QMenu* view = menuBar()->addMenu(tr("&View"));
  QAction* fit = view->addAction(tr("&Fit to View"), viewport_, &Viewport::fitToView);
  fit->setObjectName(QStringLiteral("fitAction"));
  fit->setShortcut(Qt::Key_F);  // the viewport handles F itself while its 3D window has focus
  QAction* reset = view->addAction(tr("&Reset View"), viewport_, &Viewport::resetView);
  reset->setShortcut(Qt::Key_Home);
  view->addSeparator();
  view->addAction(sceneDock_->toggleViewAction());
  view->addAction(partDock_->toggleViewAction());
  view->addAction(messagesDock_->toggleViewAction());
}

void MainWindow::openFileDialog() {
  const QString start =
      controller_.currentPath().isEmpty() ? QString() : QFileInfo(controller_.currentPath()).absolutePath();
  const QString path = QFileDialog::getOpenFileName(this, tr("Open scene or mesh"), start,
                                                    controller_.fileDialogFilters().join(QStringLiteral(";;")));
  if (!path.isEmpty()) controller_.open(path);
}

void MainWindow::assemblyLoaded() {
  const vaw::Assembly* assembly = controller_.assembly();
  const std::string keepName = selectedName_;
  const QString keepFrom = selectedFrom_;
  viewport_->setAssembly(assembly);
  sceneDock_->setAssembly(assembly, controller_.collisionInfo());
  partDock_->showPart(assembly, std::nullopt);
  reloadAction_->setEnabled(true);
  if (assembly == nullptr) return;
  // After a reload, the part that was selected stays selected (by name: ids may change).
  if (!keepName.empty() && keepFrom == controller_.currentPath()) viewport_->selectPart(assembly->findPart(keepName));
  for (const auto& warning : assembly->warnings) messagesDock_->model()->add(warning);
  const QString name = QString::fromStdString(assembly->name);
  setWindowTitle(tr("%1 - vaw").arg(name.isEmpty() ? QFileInfo(controller_.currentPath()).fileName() : name));
  const QString summary = tr("Opened %1: %n part(s)", nullptr, static_cast<int>(assembly->parts.size()))
                              .arg(QFileInfo(controller_.currentPath()).fileName()) +
                          tr(", %n triangle(s)", nullptr, static_cast<int>(assembly->totalTriangles())) +
                          (assembly->warnings.empty()
                               ? QString()
                               : tr(", %n warning(s) (see Messages)", nullptr,
                                    static_cast<int>(assembly->warnings.size())));
  messagesDock_->model()->add(MessageLogModel::Severity::Info, summary, controller_.currentPath());
  statusBar()->showMessage(summary);
}

void MainWindow::showSelection(std::optional<vaw::PartId> part) {
  const vaw::Assembly* assembly = controller_.assembly();
  partDock_->showPart(assembly, part, controller_.collisionInfo());
  if (assembly != nullptr && part && *part < assembly->parts.size()) {
    selectedName_ = assembly->parts[*part].name;
    selectedFrom_ = controller_.currentPath();
  } else {
    selectedName_.clear();
  }
}

}  // namespace vaw::ui
