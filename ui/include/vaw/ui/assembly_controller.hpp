#pragma once
// The one place that holds the loaded vaw::Assembly. Widgets observe it through Qt signals and read
// the assembly through assembly(); they never keep pointers into it past the next assemblyLoaded().
// Loading runs on a worker thread; a failed or cancelled load leaves the current assembly untouched.
#include <QFutureWatcher>
#include <QObject>
#include <QString>
#include <QStringList>
#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/collision/collision_world.hpp"
#include "vaw/importer.hpp"
#include "vaw/scene_loader.hpp"

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
  [[nodiscard]] const vaw::Assembly* assembly() const { return assembly_.get(); }
  // How each part and environment object collides (its proxy), measured when the assembly loaded.
  [[nodiscard]] const std::vector<vaw::collision::ObjectInfo>& collisionInfo() const { return collisionInfo_; }
  // The file of the current assembly (what File > Reload reads).
  [[nodiscard]] QString currentPath() const { return currentPath_; }
  [[nodiscard]] bool isLoading() const { return watcher_.isRunning(); }

  // What a load calls on the worker thread; vaw::loadAny unless replaced (tests use a slow one).
  using Loader = std::function<vaw::Assembly(const std::filesystem::path&, const vaw::ImporterRegistry&,
                                             const vaw::LoadOptions&, const vaw::ProgressFn&)>;
  // An empty loader restores vaw::loadAny. Takes effect with the next load.
  void setLoader(Loader loader);

  void setLoadOptions(const vaw::LoadOptions& options) { options_ = options; }
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
    std::shared_ptr<vaw::Assembly> assembly;
    std::vector<vaw::collision::ObjectInfo> collision;
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
  std::unique_ptr<vaw::Assembly> assembly_;
  std::vector<vaw::collision::ObjectInfo> collisionInfo_;
  QString currentPath_;
  QString loadingPath_;
  std::optional<QString> pendingPath_;
  std::shared_ptr<std::atomic<bool>> cancel_;
  QFutureWatcher<Outcome> watcher_;
};

}  // namespace vaw::ui

Q_DECLARE_METATYPE(vaw::ui::LoadFailure)
