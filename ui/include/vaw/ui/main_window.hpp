#pragma once
// The workbench window: composes the viewport and the docks, the menus and the status bar, and wires
// them to the controller. It holds no assembly state of its own.
#include <QMainWindow>
#include <optional>
#include <string>

#include "vaw/assembly.hpp"

class QAction;

namespace vaw::ui {

class AssemblyController;
class Viewport;
class SceneDock;
class PartDock;
class MessagesDock;
class LoadFeedback;

class MainWindow : public QMainWindow {
  Q_OBJECT
 public:
  explicit MainWindow(AssemblyController& controller, QWidget* parent = nullptr);

  [[nodiscard]] Viewport* viewport() const { return viewport_; }
  [[nodiscard]] SceneDock* sceneDock() const { return sceneDock_; }
  [[nodiscard]] PartDock* partDock() const { return partDock_; }
  [[nodiscard]] MessagesDock* messagesDock() const { return messagesDock_; }
  [[nodiscard]] LoadFeedback* loadFeedback() const { return loadFeedback_; }

 public slots:
  void openFileDialog();

 private:
  void createMenus();
  void assemblyLoaded();
  void showSelection(std::optional<vaw::PartId> part);

  AssemblyController& controller_;
  Viewport* viewport_ = nullptr;
  SceneDock* sceneDock_ = nullptr;
  PartDock* partDock_ = nullptr;
  MessagesDock* messagesDock_ = nullptr;
  LoadFeedback* loadFeedback_ = nullptr;
  QAction* reloadAction_ = nullptr;
  // Kept across File > Reload: the selected part's name and the file it came from.
  std::string selectedName_;
  QString selectedFrom_;
};

}  // namespace vaw::ui
