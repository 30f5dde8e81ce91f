#pragma once
// The one owner of the loaded scene (vaw::sim::Scene: the assembly with its collision geometry, built once
// on a worker thread and then shared, read-only, by the panels, the viewport and the simulation). Widgets
// observe it through Qt signals; they never keep pointers into it past the next assemblyLoaded(). A failed
// or cancelled load leaves the current scene untouched. A session file (*.vaw-session.json) opens its
// scene and hands the session on (takeSession()) for the simulation to play back.
#include <QFutureWatcher>
#include <QObject>
#include <QString>
#include <QStringList>
#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/collision/collision_world.hpp"
#include "vaw/importer.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/sim/scene.hpp"
#include "vaw/sim/session.hpp"
#include "vaw/sim/world.hpp"

namespace vaw::ui {

// Why a load failed, in the words the user needs to fix the file.
struct LoadFailure {
  QString path;             // what was being opened
  QString message;          // one line: vaw::Diagnostic::message() or the exception's what()
  bool inputError = false;  // true when the fields below come from a vaw::Diagnostic
  QString file;
  QString field;
  QString expected;
  QString found;
};

class AssemblyController : public QObject {
  Q_OBJECT
 public:
  // Creates the importer registry and loads the plugins in vaw::ImporterRegistry::defaultPluginDirs().
  explicit AssemblyController(QObject* parent = nullptr);
  // The same with explicit plugin directories (tests).
  AssemblyController(const std::vector<std::filesystem::path>& pluginDirs, QObject* parent);
  ~AssemblyController() override;
  AssemblyController(const AssemblyController&) = delete;
  AssemblyController& operator=(const AssemblyController&) = delete;

  [[nodiscard]] const vaw::ImporterRegistry& importers() const { return registry_; }
  // Plugins that failed to load, and a note when no importer was found at all.
  [[nodiscard]] const QStringList& pluginMessages() const { return pluginMessages_; }
  // File dialog filters: scenes, meshes the importers read, all files.
  [[nodiscard]] QStringList fileDialogFilters() const;

  // The current assembly, or null before the first successful load. Valid until the next
  // assemblyLoaded() signal.
  [[nodiscard]] const vaw::Assembly* assembly() const { return scene_ ? &scene_->assembly() : nullptr; }
  // The loaded scene, shared: holders keep it alive past a reload.
  [[nodiscard]] const std::shared_ptr<const vaw::sim::Scene>& scene() const { return scene_; }
  // How each part and environment object collides (its proxy), measured when the assembly loaded.
  [[nodiscard]] const std::vector<vaw::collision::ObjectInfo>& collisionInfo() const;
  // The file of the current assembly (what File > Reload reads): the scene, also when a session was opened.
  [[nodiscard]] QString currentPath() const { return currentPath_; }
  // The scene as a session should name it: the path given, or a bundled scene's file name.
  [[nodiscard]] QString sceneReference() const { return sceneReference_; }
  // The session that came with the last load (a session file was opened), once; empty otherwise.
  [[nodiscard]] std::optional<vaw::sim::Session> takeSession();
  [[nodiscard]] bool isLoading() const { return watcher_.isRunning(); }

  // What a load calls on the worker thread; vaw::loadAny unless replaced (tests use a slow one).
  using Loader = std::function<vaw::Assembly(const std::filesystem::path&, const vaw::ImporterRegistry&,
                                             const vaw::LoadOptions&, const vaw::ProgressFn&)>;
  // An empty loader restores vaw::loadAny. Takes effect with the next load.
  void setLoader(Loader loader);

  void setLoadOptions(const vaw::LoadOptions& options) { options_ = options; }

  // The current assembly with `constraints` instead of its own, as a new scene built here (synchronously:
  // the collision geometry is rebuilt, which takes milliseconds for a CAD assembly); emits assemblyLoaded
  // with isEditReload() true. The file stays the current one. `keepTuningOf`, when given, is the running
  // world whose tuning (rate, gravity, method, friction) the new scene starts with, so an edit of the
  // constraints does not undo the user's tuning. Returns false, with the reason in `why`, when the scene
  // cannot be built (the current one then stays).
  bool setConstraints(std::vector<vaw::Constraint> constraints, const vaw::sim::World* keepTuningOf = nullptr,
                      QString* why = nullptr);
  // True while assemblyLoaded is emitted for setConstraints: the same file, only its constraints changed.
  [[nodiscard]] bool isEditReload() const { return editReload_; }
  // Opens `path` with `base` as the base of its CAD assembly (vaw::LoadOptions::cadBase), and keeps that
  // base for File > Reload of the same file.
  void openWithBase(const QString& path, const std::string& base);
  // Opens `path` standing the way `up` says (vaw::LoadOptions::cadUp: "auto" or a file axis such as "+y"),
  // and keeps that choice for File > Reload of the same file; File > Save writes it into the scene.
  void openWithUp(const QString& path, const std::string& up);
  // Opens `path` again with the sub-assembly `name` taken apart (`asOne` false: a unit's parts each its own) or
  // joined as one unit; the choices add up while the same file is reopened.
  void openWithUnit(const QString& path, const std::string& name, bool asOne);
  [[nodiscard]] const vaw::LoadOptions& loadOptions() const { return options_; }

 public slots:
  // Starts loading `path` in the background. A load already running is cancelled and this one
  // starts when it has stopped.
  void open(const QString& path);
  void reload();
  void cancelLoad();

 signals:
  void loadStarted(const QString& path);
  void progress(double fraction, const QString& stage);
  void assemblyLoaded();  // assembly() is the new one
  void loadFailed(const vaw::ui::LoadFailure& failure);
  void loadCancelled(const QString& path);
  void loadFinished();  // after each of assemblyLoaded, loadFailed, loadCancelled

 private:
  struct Outcome {
    std::shared_ptr<const vaw::sim::Scene> scene;
    QString scenePath;       // the scene file read (the session's scene when a session was opened)
    QString sceneReference;  // how a session names it
    std::optional<vaw::sim::Session> session;
    std::optional<LoadFailure> failure;
    bool cancelled = false;
  };
  void start(const QString& path);
  void finished();
  [[nodiscard]] Outcome runLoad(const QString& path, const Loader& loader, const vaw::LoadOptions& options,
                               const std::shared_ptr<std::atomic<bool>>& cancel);

  vaw::ImporterRegistry registry_;
  QStringList pluginMessages_;
  vaw::LoadOptions options_;
  Loader loader_;
  std::shared_ptr<const vaw::sim::Scene> scene_;
  std::optional<vaw::sim::Session> session_;
  QString currentPath_;
  QString sceneReference_;
  QString loadingPath_;
  std::optional<QString> pendingPath_;
  std::shared_ptr<std::atomic<bool>> cancel_;
  QFutureWatcher<Outcome> watcher_;
  bool editReload_ = false;
  struct ChosenBase {
    QString path;  // absolute
    std::string base;
  };
  std::optional<ChosenBase> chosenBase_;
  std::optional<ChosenBase> chosenUp_;  // `base` holds the up choice
  struct ChosenUnits {
    QString path;  // absolute
    std::set<std::string> split, join;
  };
  std::optional<ChosenUnits> chosenUnits_;
};

}  // namespace vaw::ui

Q_DECLARE_METATYPE(vaw::ui::LoadFailure)
