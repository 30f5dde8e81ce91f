#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/background.hpp"

#include <QFile>
#include <QFileInfo>
#include <QMetaObject>
#include <QtConcurrent/QtConcurrentRun>
#include <chrono>
#include <exception>
#include <mutex>
#include <string>

#include "vaw/error.hpp"
#include "vaw/paths.hpp"

namespace vaw::ui {

namespace {

QString fromStd(const std::string& s) { return QString::fromStdString(s); }

std::filesystem::path toPath(const QString& path) {
  return std::filesystem::path(QFile::encodeName(path).toStdString());
}

// A session names its scene as it was given when recording: a path (absolute, or relative to where vaw
// ran or to the session's folder) or a bundled scene's name.
std::filesystem::path sessionScene(const vaw::sim::Session& s, const std::filesystem::path& sessionFile) {
  const std::filesystem::path named(s.scene);
  for (const auto& candidate : {named, sessionFile.parent_path() / named, vaw::resourceDir() / "scenes" / named})
    if (std::filesystem::is_regular_file(candidate)) return candidate;
  vaw::fail(sessionFile.string(), "scene",
            "a scene file at that path, next to the session, or among the bundled scenes (" +
                (vaw::resourceDir() / "scenes").string() + ")",
            s.scene);
}

}  // namespace

AssemblyController::AssemblyController(QObject* parent)
    : AssemblyController(vaw::ImporterRegistry::defaultPluginDirs(), parent) {}

AssemblyController::AssemblyController(const std::vector<std::filesystem::path>& pluginDirs,
                                       QObject* parent)
    : QObject(parent) {
  qRegisterMetaType<vaw::ui::LoadFailure>();
  for (const auto& dir : pluginDirs) {
    try {
      for (const auto& message : registry_.loadPlugins(dir)) pluginMessages_ << fromStd(message);
    } catch (const std::exception& e) {
      pluginMessages_ << tr("Cannot load plugins from %1: %2")
                             .arg(QString::fromStdString(dir.string()), QString::fromUtf8(e.what()));
    }
  }
  if (registry_.importerNames().empty()) {
    QStringList searched;
    for (const auto& dir : pluginDirs) searched << QString::fromStdString(dir.string());
    pluginMessages_ << tr("No mesh importer plugin found (searched: %1); only scenes made of "
                          "primitives can be opened. Set VAW_PLUGIN_PATH to the plugin folder.")
                           .arg(searched.isEmpty() ? tr("nothing") : searched.join(QStringLiteral(", ")));
  }
  setLoader({});
  connect(&watcher_, &QFutureWatcher<Outcome>::finished, this, &AssemblyController::finished);
}

AssemblyController::~AssemblyController() {
  // The worker posts progress to this object: it must stop before we go.
  pendingPath_.reset();
  if (cancel_) cancel_->store(true);
  watcher_.disconnect(this);
  watcher_.waitForFinished();
}

const std::vector<vaw::collision::ObjectInfo>& AssemblyController::collisionInfo() const {
  static const std::vector<vaw::collision::ObjectInfo> none;
  return scene_ ? scene_->collisionInfo() : none;
}

std::optional<vaw::sim::Session> AssemblyController::takeSession() {
  std::optional<vaw::sim::Session> s = std::move(session_);
  session_.reset();
  return s;
}

void AssemblyController::setLoader(Loader loader) {
  loader_ = loader ? std::move(loader) : Loader(&vaw::loadAny);
}

QStringList AssemblyController::fileDialogFilters() const {
  QStringList meshPatterns;
  for (const auto& ext : registry_.extensions()) meshPatterns << QStringLiteral("*.") + fromStd(ext);
  QStringList filters;
  QStringList everything{QStringLiteral("*.vaw.json"), QStringLiteral("*.json")};
  everything << meshPatterns;
  filters << tr("Scenes and meshes (%1)").arg(everything.join(QLatin1Char(' ')));
  filters << tr("Scenes (*.vaw.json *.json)");
  QStringList cadPatterns;
  for (const char* ext : {"stp", "step", "p21"})
    if (meshPatterns.contains(QStringLiteral("*.") + QLatin1String(ext))) cadPatterns << QStringLiteral("*.") + QLatin1String(ext);
  if (!cadPatterns.isEmpty()) filters << tr("CAD assemblies (%1)").arg(cadPatterns.join(QLatin1Char(' ')));
  if (!meshPatterns.isEmpty()) filters << tr("Meshes (%1)").arg(meshPatterns.join(QLatin1Char(' ')));
  filters << tr("All files (*)");
  return filters;
}

void AssemblyController::open(const QString& path) {
  if (watcher_.isRunning()) {
    pendingPath_ = path;
    cancelLoad();
    return;
  }
  start(path);
}

void AssemblyController::reload() {
  if (!currentPath_.isEmpty()) open(currentPath_);
}

void AssemblyController::cancelLoad() {
  if (cancel_) cancel_->store(true);
}

void AssemblyController::openWithBase(const QString& path, const std::string& base) {
  chosenBase_ = ChosenBase{QFileInfo(path).absoluteFilePath(), base};
  open(path);
}

void AssemblyController::openWithUp(const QString& path, const std::string& up) {
  chosenUp_ = ChosenBase{QFileInfo(path).absoluteFilePath(), up};
  open(path);
}

void AssemblyController::openWithUnit(const QString& path, const std::string& name, bool asOne) {
  const QString absolute = QFileInfo(path).absoluteFilePath();
  if (!chosenUnits_ || chosenUnits_->path != absolute) chosenUnits_ = ChosenUnits{absolute, {}, {}};
  (asOne ? chosenUnits_->join : chosenUnits_->split).insert(name);
  (asOne ? chosenUnits_->split : chosenUnits_->join).erase(name);
  open(path);
}

bool AssemblyController::setConstraints(std::vector<vaw::Constraint> constraints, const vaw::sim::World* keepTuningOf,
                                        QString* why) {
  if (!scene_) return false;
  vaw::Assembly assembly = scene_->assembly();
  assembly.constraints = std::move(constraints);
  if (keepTuningOf != nullptr) {
    const vaw::sim::Settings& s = keepTuningOf->settings();
    assembly.settings.rate = s.rate;
    assembly.settings.freeFlightScale = s.gravity.freeFlight;
    assembly.settings.slideScale = s.gravity.slide;
    assembly.settings.rotationScale = s.gravity.rotation;
    assembly.settings.rotationMethod = std::string(vaw::dyn::name(s.rotationMethod));
    for (auto& [name, material] : assembly.materials) {
      const vaw::FrictionValues f = keepTuningOf->materialFriction(name);
      material.staticFriction = f.staticFriction;
      material.kineticFriction = f.kineticFriction;
      material.rotationalFriction = f.rotationalFriction;
    }
    assembly.settings.partFriction.clear();
    for (vaw::PartId id = 0; id < assembly.parts.size(); ++id)
      if (const auto f = keepTuningOf->frictionOverride(id)) assembly.settings.partFriction[id] = *f;
  }
  // The warnings were reported when the file was read; the rebuild would only add the collision's again.
  assembly.warnings.clear();
  try {
    scene_ = vaw::sim::Scene::build(std::move(assembly));
  } catch (const std::exception& e) {
    if (why != nullptr) *why = QString::fromUtf8(e.what());
    return false;
  }
  session_.reset();
  editReload_ = true;
  emit assemblyLoaded();
  editReload_ = false;
  return true;
}

void AssemblyController::start(const QString& path) {
  loadingPath_ = path;
  cancel_ = std::make_shared<std::atomic<bool>>(false);
  emit loadStarted(path);
  auto cancel = cancel_;
  vaw::LoadOptions options = options_;
  if (chosenBase_ && chosenBase_->path == QFileInfo(path).absoluteFilePath()) options.cadBase = chosenBase_->base;
  else chosenBase_.reset();
  if (chosenUp_ && chosenUp_->path == QFileInfo(path).absoluteFilePath()) options.cadUp = chosenUp_->base;
  else chosenUp_.reset();
  if (chosenUnits_ && chosenUnits_->path == QFileInfo(path).absoluteFilePath()) {
    options.cadSplit = chosenUnits_->split;
    options.cadJoin = chosenUnits_->join;
  } else {
    chosenUnits_.reset();
  }
  watcher_.setFuture(QtConcurrent::run([this, path, loader = loader_, options, cancel] {
    return runLoad(path, loader, options, cancel);
  }));
}

// Runs on the worker thread. Touches only its arguments and the registry (const); progress reaches
// the GUI thread through queued calls.
AssemblyController::Outcome AssemblyController::runLoad(const QString& path, const Loader& loader,
                                                        const vaw::LoadOptions& options,
                                                        const std::shared_ptr<std::atomic<bool>>& cancel) {
  Outcome out;
  // The loader asks thousands of times on a large product (each part and pair of parts it works on is
  // named, "recognising constraints: bolt-3 and plate"): the dialog hears of it at most every 50 ms, and
  // at once of a new stage (the text before the colon) and of the end.
  struct Throttle {
    std::mutex mutex;
    std::chrono::steady_clock::time_point last{};
    std::string lastKind;
  };
  auto throttle = std::make_shared<Throttle>();
  const vaw::ProgressFn progressFn = [this, cancel, throttle](double fraction, const std::string& stage) {
    {
      const std::lock_guard lock(throttle->mutex);
      const auto now = std::chrono::steady_clock::now();
      const std::string kind = stage.substr(0, stage.find(':'));
      if (now - throttle->last >= std::chrono::milliseconds(50) || kind != throttle->lastKind || fraction >= 1.0) {
        throttle->last = now;
        throttle->lastKind = kind;
        const QString qstage = QString::fromStdString(stage);
        QMetaObject::invokeMethod(
            this, [this, fraction, qstage] { emit progress(fraction, qstage); }, Qt::QueuedConnection);
      }
    }
    return !cancel->load();
  };
  const auto fail = [&](LoadFailure f) {
    if (cancel->load()) {
      out.cancelled = true;
    } else {
      f.path = path;
      out.failure = std::move(f);
    }
  };
  try {
    const BackgroundTask task("import");
    std::filesystem::path file = toPath(path);
    out.sceneReference = path;
    if (path.endsWith(QStringLiteral(".vaw-session.json"))) {
      out.session = vaw::sim::loadSession(file);
      file = sessionScene(*out.session, file);
      out.sceneReference = QString::fromStdString(out.session->scene);
    }
    out.scenePath = QFile::decodeName(file.string().c_str());
    // The collision geometry (hierarchies, surface patches, proxies) is built once per load, here, and
    // shared by everything that needs it; its problems join the load's warnings.
    out.scene = vaw::sim::Scene::build(loader(file, registry_, options, progressFn), progressFn);
    if (out.session) vaw::sim::checkScene(*out.session, *out.scene);
  } catch (const vaw::LoadCancelled&) {
    out.cancelled = true;
  } catch (const vaw::InputError& e) {
    const auto& d = e.diagnostic();
    LoadFailure f;
    f.message = fromStd(d.message());
    f.inputError = true;
    f.file = fromStd(d.file);
    f.field = fromStd(d.field);
    f.expected = fromStd(d.expected);
    f.found = fromStd(d.found);
    fail(std::move(f));
  } catch (const std::exception& e) {
    LoadFailure f;
    f.message = tr("%1: %2").arg(path, failureText(e));
    fail(std::move(f));
  } catch (...) {
    LoadFailure f;
    f.message = tr("%1: unknown error while loading").arg(path);
    fail(std::move(f));
  }
  if (cancel->load()) {  // the user cancelled: whatever came back is discarded
    out.scene.reset();
    out.session.reset();
    out.failure.reset();
    out.cancelled = true;
  }
  return out;
}

void AssemblyController::finished() {
  Outcome out = watcher_.result();
  const QString path = loadingPath_;
  loadingPath_.clear();
  if (out.scene) {
    scene_ = std::move(out.scene);
    session_ = std::move(out.session);
    currentPath_ = QFileInfo(out.scenePath).absoluteFilePath();
    sceneReference_ = out.sceneReference;
    emit assemblyLoaded();
  } else if (out.failure) {
    emit loadFailed(*out.failure);
  } else {
    emit loadCancelled(path);
  }
  emit loadFinished();
  if (pendingPath_) {
    const QString next = *pendingPath_;
    pendingPath_.reset();
    start(next);
  }
}

}  // namespace vaw::ui
