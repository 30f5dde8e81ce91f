#include "vaw/ui/xr_controller.hpp"
#include "qt_convert.hpp"

#include <Qt3DRender/QCamera>
#include <dlfcn.h>

#include <QAction>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QGuiApplication>
#include <QLabel>
#include <QMenu>
#include <QMenuBar>
#include <QOffscreenSurface>
#include <QOpenGLContext>
#include <QSettings>
#include <QStatusBar>
#include <cmath>
#include <numbers>

#include "vaw/importer.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/viewport.hpp"

namespace vaw::ui {

namespace {

constexpr int kIdlePollMs = 10;  // while the session waits for the runtime (not running yet)


}  // namespace

XrController::XrController(SimulationController& simulation, Viewport* mirror, QObject* parent)
    : QObject(parent), simulation_(&simulation), mirror_(mirror) {
  timer_.setSingleShot(true);
  connect(&timer_, &QTimer::timeout, this, &XrController::loop);
  connect(&simulation, &SimulationController::started, this, &XrController::sceneChanged);
  if (mirror_) connect(mirror_, &Viewport::sweptVolumeChanged, this, &XrController::overlayChanged);
}

XrController::~XrController() {
  if (backend_) {
    QString why;
    makeCurrent(why);
    backend_.reset();
  }
  if (context_) context_->doneCurrent();
  stopDriving();
  if (library_ != nullptr) dlclose(library_);
}

void XrController::install(QMenuBar* bar, QStatusBar* status) {
  QMenu* menu = bar->addMenu(tr("V&R"));
  enterAction_ = menu->addAction(tr("&Enter VR"), this, &XrController::toggle);
  enterAction_->setObjectName(QStringLiteral("enterVrAction"));
  enterAction_->setShortcut(QKeySequence(tr("Ctrl+Shift+V")));
  enterAction_->setCheckable(true);
  recenterAction_ = menu->addAction(tr("&Recenter"), this, &XrController::recenter);
  recenterAction_->setObjectName(QStringLiteral("recenterVrAction"));
  recenterAction_->setShortcut(QKeySequence(tr("Ctrl+Shift+C")));
  recenterAction_->setToolTip(tr("Put the table in front of where you stand and look now, at a comfortable height"));
  status_ = new QLabel(status);
  status_->setObjectName(QStringLiteral("vrStatus"));
  status->addPermanentWidget(status_);
  updateUi();
}

QString XrController::statusText() const {
  const QString runtime = runtime_.name.empty() ? QString() : QString::fromStdString(runtime_.name);
  switch (mode_) {
    case Mode::Desktop: return runtime.isEmpty() ? tr("VR off") : tr("VR off (%1)").arg(runtime);
    case Mode::Starting: return tr("VR starting: %1, %2").arg(runtime, QString::fromLatin1(xr::name(state_).data()));
    case Mode::Headset: break;
  }
  return tr("VR: %1 %2 (%3), %4")
      .arg(runtime, QString::fromStdString(runtime_.version), QString::fromStdString(runtime_.system),
           QString::fromLatin1(xr::name(state_).data()));
}

void XrController::updateUi() {
  if (enterAction_ != nullptr) {
    enterAction_->setText(inHeadset() ? tr("&Leave VR") : tr("&Enter VR"));
    enterAction_->setChecked(inHeadset());
  }
  if (recenterAction_ != nullptr) recenterAction_->setEnabled(mode_ == Mode::Headset);
  if (status_ != nullptr) status_->setText(statusText());
}

void XrController::toggle() { inHeadset() ? leave() : enter(); }

void XrController::recenter() {
  if (!backend_ || mode_ != Mode::Headset) return;
  backend_->recenter();
  emit notice(tr("Recentred: the table is %1 m in front of you, its top %2 m below your eyes")
                  .arg(xr::Placement{}.tableDistance)
                  .arg(xr::Placement{}.tableBelowEyes),
              false);
}

bool XrController::loadPlugin(QString& why) {
  if (create_ != nullptr) return true;
  QStringList looked;
  for (const auto& dir : vaw::ImporterRegistry::defaultPluginDirs()) {
    const QString file = QDir(QString::fromStdString(dir.string())).filePath(QString::fromLatin1(xr::kPluginFile));
    looked << QDir::toNativeSeparators(QFileInfo(file).absolutePath());
    if (!QFileInfo::exists(file)) continue;
    void* handle = dlopen(QFile::encodeName(file).constData(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      why = tr("VR is not available: %1 cannot be loaded: %2").arg(file, QString::fromLocal8Bit(dlerror()));
      return false;
    }
    auto abi = reinterpret_cast<VawXrAbiFn>(dlsym(handle, "vaw_xr_abi_version"));
    auto create = reinterpret_cast<VawXrCreateFn>(dlsym(handle, "vaw_xr_create_backend"));
    if (abi == nullptr || create == nullptr || abi() != xr::kAbiVersion) {
      why = tr("VR is not available: %1 is not a headset plugin for this vaw (ABI %2 needed)").arg(file).arg(xr::kAbiVersion);
      dlclose(handle);
      return false;
    }
    library_ = handle;
    create_ = create;
    return true;
  }
  why = tr("VR is not available: this vaw was built without the OpenXR plugin (%1 is in none of %2); build it with "
           "libopenxr-dev installed and -DVAW_PLUGIN_OPENXR=ON")
            .arg(QString::fromLatin1(xr::kPluginFile), looked.join(QStringLiteral(", ")));
  return false;
}

// The runtime gets the X display, drawable and context of a GLX context: Qt must be on X11 (xcb) with GLX.
bool XrController::makeCurrent(QString& why) {
  if (!context_) {
    if (QGuiApplication::platformName() != QStringLiteral("xcb")) {
      why = tr("VR needs OpenGL through GLX on X11, and this session runs on \"%1\" (Wayland has no GLX binding): "
               "start vaw with --vr, or with QT_QPA_PLATFORM=xcb")
                .arg(QGuiApplication::platformName());
      return false;
    }
    QSurfaceFormat format;
    format.setRenderableType(QSurfaceFormat::OpenGL);
    format.setProfile(QSurfaceFormat::CoreProfile);
    format.setVersion(3, 3);
    format.setDepthBufferSize(24);
    auto context = std::make_unique<QOpenGLContext>();
    context->setFormat(format);
    if (!context->create()) {
      why = tr("VR needs an OpenGL 3.3 context, and none could be created");
      return false;
    }
    if (context->nativeInterface<QNativeInterface::QGLXContext>() == nullptr) {
      why = tr("VR needs OpenGL through GLX, and Qt made an EGL context (QT_XCB_GL_INTEGRATION=%1): unset it or set "
               "it to xcb_glx")
                .arg(qEnvironmentVariable("QT_XCB_GL_INTEGRATION"));
      return false;
    }
    auto surface = std::make_unique<QOffscreenSurface>();
    surface->setFormat(context->format());
    surface->create();
    context_ = std::move(context);
    surface_ = std::move(surface);
  }
  if (!context_->makeCurrent(surface_.get())) {
    why = tr("VR cannot make its OpenGL context current");
    return false;
  }
  return true;
}

void XrController::enter() {
  if (inHeadset() || !simulation_) return;
  QString why;
  if (!loadPlugin(why)) return finish(xr::Event{xr::Event::Kind::Failure, {}, xr::Failure::NotInstalled, false, why.toStdString()});
  if (!makeCurrent(why)) return finish(xr::Event{xr::Event::Kind::Failure, {}, xr::Failure::OpenGLContext, false, why.toStdString()});
  QSettings settings;
  settings.beginGroup(QStringLiteral("vr"));
  const xr::InputSettings defaults;
  inputSettings_.pinchClose = settings.value(QStringLiteral("pinch_close"), defaults.pinchClose).toDouble();
  inputSettings_.pinchOpen = settings.value(QStringLiteral("pinch_open"), defaults.pinchOpen).toDouble();
  inputSettings_.gripClose = settings.value(QStringLiteral("grip_close"), defaults.gripClose).toDouble();
  inputSettings_.gripOpen = settings.value(QStringLiteral("grip_open"), defaults.gripOpen).toDouble();
  inputSettings_.baseReach = settings.value(QStringLiteral("base_reach"), defaults.baseReach).toDouble();

  backend_.reset(create_());
  const xr::Event started = backend_->start(xr::StartOptions{});
  if (started.kind == xr::Event::Kind::Failure) {
    backend_.reset();
    context_->doneCurrent();
    return finish(started);
  }
  runtime_ = backend_->runtime();
  mode_ = Mode::Starting;
  state_ = xr::SessionState::Unknown;
  framesShown_ = 0;
  sceneChanged();
  if (mirror_ && mirror_->camera() != nullptr) {
    const Qt3DRender::QCamera* c = mirror_->camera();
    desktopCamera_ = Camera{c->position(), c->viewCenter(), c->upVector(), c->fieldOfView()};
  }
  emit modeChanged(true);
  updateUi();
  timer_.start(0);
}

void XrController::leave() {
  if (!backend_) return;
  QString why;
  if (makeCurrent(why)) backend_->requestExit();
  timer_.start(0);
}

void XrController::sceneChanged() {
  anchored_ = false;
  if (!backend_ || !simulation_ || !simulation_->hasWorld()) return;
  QString why;
  if (!makeCurrent(why)) return;
  backend_->setScene(simulation_->description());
  hands_.emplace(simulation_->world().assembly(), inputSettings_);
  overlayChanged();
}

void XrController::overlayChanged() {
  if (!backend_ || !mirror_) return;
  QString why;
  if (!makeCurrent(why)) return;
  backend_->setOverlay(mirror_->sweptVolume(), vaw::view::kSweptColor, vaw::view::kSweptAlpha);
}

void XrController::loop() {
  if (!backend_) return;
  QString why;
  if (!makeCurrent(why)) return finish(xr::Event{xr::Event::Kind::Failure, {}, xr::Failure::OpenGLContext, false, why.toStdString()});
  std::optional<xr::Event> failure;
  for (xr::Event& e : backend_->poll()) {
    switch (e.kind) {
      case xr::Event::Kind::State:
        state_ = e.state;
        if (state_ == xr::SessionState::Focused) mode_ = Mode::Headset;
        emit sessionStateChanged(state_);
        updateUi();
        break;
      case xr::Event::Kind::Failure:
        failure = std::move(e);
        break;
      case xr::Event::Kind::Message:
        // Validation errors are warnings: they fail the tests, which treat any Qt warning as a failure.
        if (e.warning) qWarning("%s", e.text.c_str());
        emit notice(QString::fromStdString(e.text), e.warning);
        break;
    }
  }
  if (failure || backend_->finished()) return finish(std::move(failure));
  if (!backend_->running()) {
    stopDriving();
    timer_.start(kIdlePollMs);
    return;
  }
  if (!driving_) startDriving();
  const xr::FrameResult result = backend_->frame([this](const xr::FrameTiming& t) { return simulate(t); });
  if (result.submitted) {
    lastFrame_ = result;
    ++framesShown_;
    mirror(result);
    emit frameShown();
  }
  timer_.start(0);
}

void XrController::startDriving() {
  if (!simulation_) return;
  driving_ = true;
  anchored_ = false;
  handsClosed_ = {};
  simulation_->setExternalPacing(true);
  simulation_->setInputSource([this](double stepEndTime) { return inputAt(stepEndTime); });
  if (simulation_->hasWorld() && !simulation_->isPlaying() && !simulation_->isPlayback()) simulation_->play();
}

void XrController::stopDriving() {
  if (!driving_) return;
  driving_ = false;
  if (!simulation_) return;
  simulation_->setInputSource({});
  simulation_->setExternalPacing(false);
}

// Runs the steps that end by the frame's display time: at 90 Hz on a 90 Hz headset one a frame, each ending
// exactly when the frame is shown; at 72 Hz one or two; at 120 Hz none on every fourth frame. The clock is
// re-anchored whenever the simulation's own timeline moved (pause, seek, reset, speed or rate change), and a
// stall runs at most kMaxCatchUp steps, the rest dropped, as the desktop's timer does.
const vaw::view::Frame* XrController::simulate(const xr::FrameTiming& timing) {
  if (!simulation_ || !simulation_->hasWorld() || !hands_) return nullptr;
  const vaw::sim::World& world = simulation_->world();
  if (!simulation_->isPlaying()) {
    anchored_ = false;
    return &simulation_->frame();
  }
  const double speed = simulation_->speed(), rate = world.settings().rate;
  if (!anchored_ || world.stepCount() != expectedStep_ || speed != anchorSpeed_ || rate != anchorRate_) {
    anchored_ = true;
    anchorXr_ = timing.displayTime;
    anchorStep_ = expectedStep_ = world.stepCount();
    anchorSim_ = world.time();
    anchorSpeed_ = speed;
    anchorRate_ = rate;
  }
  // A step "ends by" the display time within a thousandth of a step: the runtime's nanosecond clock does not
  // divide a second by 90 exactly.
  const double owed = static_cast<double>(timing.displayTime - anchorXr_) * 1e-9 * speed * rate;
  const auto target = anchorStep_ + static_cast<std::uint64_t>(std::floor(owed + 1e-3));
  auto steps = static_cast<std::int64_t>(target) - static_cast<std::int64_t>(world.stepCount());
  const bool stalled = steps > SimulationController::kMaxCatchUp;
  steps = std::clamp<std::int64_t>(steps, 0, SimulationController::kMaxCatchUp);
  simulation_->advance(static_cast<int>(steps));
  if (!simulation_ || !simulation_->hasWorld()) return nullptr;
  expectedStep_ = simulation_->world().stepCount();
  if (stalled) {
    anchorXr_ = timing.displayTime;
    anchorStep_ = expectedStep_;
    anchorSim_ = simulation_->world().time();
  }
  return &simulation_->frame();
}

vaw::sim::Input XrController::inputAt(double stepEndTime) {
  const auto time = anchorXr_ + static_cast<std::int64_t>(std::llround((stepEndTime - anchorSim_) / anchorSpeed_ * 1e9));
  const xr::HandsSample sample = backend_ ? backend_->sampleHands(time) : xr::HandsSample{};
  vaw::sim::Input input = hands_->next(sample, simulation_->world(), simulation_->hoist());
  for (int k = 0; k < 2; ++k) {
    const bool closed = hands_->closed(k);
    if (closed && !handsClosed_[static_cast<std::size_t>(k)]) emit handClosed(k);
    handsClosed_[static_cast<std::size_t>(k)] = closed;
  }
  return input;
}

void XrController::mirror(const xr::FrameResult& frame) {
  if (!mirror_ || mirror_->camera() == nullptr || !(frame.fovUp > frame.fovDown)) return;
  Qt3DRender::QCamera* c = mirror_->camera();
  const Eigen::Vector3d eye = frame.head.translation();
  c->setPosition(toQ(eye));
  c->setUpVector(toQ(frame.head.linear() * Eigen::Vector3d::UnitY()));
  c->setViewCenter(toQ(eye - frame.head.linear() * Eigen::Vector3d::UnitZ()));
  c->setFieldOfView(static_cast<float>((frame.fovUp - frame.fovDown) * 180.0 / std::numbers::pi));
}

// Back to the desktop. A session that ended by itself (lost, runtime gone) leaves the world paused exactly as
// the last step left it: a part in mid-throw stays in the hand that held it, nothing is decided for the wearer.
void XrController::finish(std::optional<xr::Event> failure) {
  timer_.stop();
  const bool wasDriving = driving_;
  stopDriving();
  if (backend_) {
    QString why;
    makeCurrent(why);
    backend_.reset();
  }
  if (context_) context_->doneCurrent();
  hands_.reset();
  if (desktopCamera_ && mirror_ && mirror_->camera() != nullptr) {
    Qt3DRender::QCamera* c = mirror_->camera();
    c->setPosition(desktopCamera_->position);
    c->setViewCenter(desktopCamera_->viewCenter);
    c->setUpVector(desktopCamera_->up);
    c->setFieldOfView(desktopCamera_->fov);
  }
  desktopCamera_.reset();
  const bool wasInHeadset = inHeadset();
  mode_ = Mode::Desktop;
  QString text;
  if (failure) {
    text = QString::fromStdString(failure->text);
    if (wasDriving && simulation_ && simulation_->hasWorld()) {
      simulation_->pause();
      text += tr(". Back on the desktop, paused at %1 s with the world as the headset left it.")
                  .arg(QString::number(simulation_->world().time(), 'f', 3));
    }
  }
  if (wasInHeadset) emit modeChanged(false);
  updateUi();
  if (failure) emit failed(failure->failure, text);
}

}  // namespace vaw::ui
