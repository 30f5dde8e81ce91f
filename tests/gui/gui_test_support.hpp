#pragma once
// Shared by the GUI tests (Qt Test under Xvfb): the workbench started and files opened as every test
// does it (Workbench), any Qt warning fails the test, captures of the 3D view, where a part shows on screen.
#include <QAbstractSpinBox>
#include <QImage>
#include <QWindow>
#include <QPoint>
#include <QRgb>
#include <QString>
#include <QSize>
#include <QStringList>
#include <functional>
#include <memory>
#include <optional>

#include "vaw/assembly.hpp"

class QMainWindow;
class QTimer;
class QMenu;
class QWidget;

namespace vaw::ui {
class AssemblyController;
class MainWindow;
class Viewport;
}

namespace vaw::guitest {

// The window as a GUI test starts it: Qt warnings fail the test, the settings of earlier runs gone, the
// workbench shown at a fixed size, exposed (its 3D view too) and active so that shortcuts reach it. A test
// class holds one and refers to its controller and window.
struct WorkbenchOptions {
  bool clearSettings = true;
  std::optional<bool> autoPlay;  // whether an opened scene starts running; empty: the window's default
  QSize size{1280, 800};
  bool activate = true;
};
class Workbench {
 public:
  Workbench();
  ~Workbench();
  Workbench(const Workbench&) = delete;
  Workbench& operator=(const Workbench&) = delete;
  // From initTestCase: false, with the test failed, when the window does not come up. `beforeShow` sees
  // the new window first (to attach model testers, say).
  [[nodiscard]] bool start(const WorkbenchOptions& options = {}, const std::function<void(ui::MainWindow&)>& beforeShow = {});
  // Another window for the same controller's successor (a restart within one test).
  [[nodiscard]] bool restart();
  // From cleanupTestCase.
  void stop();
  // File > Open as a person does it, unsaved tuning dropped without a question: false, with the test
  // failed, when the assembly does not load within a minute or the viewport shows nothing.
  [[nodiscard]] bool open(const QString& path);

  std::unique_ptr<ui::AssemblyController> controller;
  std::unique_ptr<ui::MainWindow> window;

 private:
  WorkbenchOptions options_;
  // A modal dialog left open (no test answered it) blocks its exec() until ctest's time limit: after 30 s
  // the watch fails the test, naming the dialog, and closes it.
  std::unique_ptr<QTimer> modalWatch_;
};

// Installs a message handler that collects every Qt warning and critical message, except the harmless
// ones it lists (each with its reason). takeWarnings() returns and clears them.
void failOnWarnings();
void restoreMessageHandler();
QStringList takeWarnings();
// Fails the running test with the Qt warnings collected since the last call, if there were any.
void verifyNoWarnings();

// A rendered frame of the viewport (waits for it); null on timeout.
QImage capture(ui::Viewport* viewport);
bool differs(QRgb a, QRgb b, int tolerance);
double nonBackgroundFraction(const ui::Viewport* viewport, const QImage& image);
// A window point where the viewport shows `part` at `pose`: the projection of the centre of its bounds,
// or, when something else is in front of that, the nearest point of a grid over them; (-1, -1) if none.
QPoint pointOnPart(ui::Viewport* viewport, const Assembly& assembly, PartId part, const Eigen::Isometry3d& pose);

// As a person does it: a press at `from` and a move in `steps` to `to`, each after `msPerStep`; no release.
void pressAndDrag(QWindow* window, const QPoint& from, const QPoint& to, int steps, int msPerStep,
                  Qt::KeyboardModifiers modifiers = {});
// The centre of the largest of the part's highest upward-facing triangles at `pose`, in the world: a point
// on its top, where a person takes a nut (the middle of its bounds is the hole).
// A point of the 3D window where a click meets CAD face `face` of `part` (whose Part is `p`), the view
// turned round it until the face shows (the camera is left there); (-1, -1) when no view shows it.
QPoint aimAtFace(ui::Viewport& viewport, const Part& p, PartId part, std::size_t face);
Eigen::Vector3d topFaceCentre(const TriMesh& mesh, const Eigen::Isometry3d& pose);
// As a person carries a part: a steep view from above that holds the part and its target, a press on the
// part's top face and a drag past the drag distance, the wheel for depth and the pointer for the rest,
// held still and let go (unless `letGo` is false), so that the part is let go at `target` (it keeps its
// orientation). `name` is for the failure messages.
void carryWithMouse(ui::MainWindow& window, PartId part, const Eigen::Isometry3d& target, const char* name, bool letGo = true);
// The part in the mouse's hand moved on to `target` (wheel and pointer, from where the hand is now), held still.
void moveCarriedWithMouse(ui::MainWindow& window, PartId part, const Eigen::Isometry3d& target, const char* name);
// The button let go where the hand is.
void releaseWithMouse(ui::MainWindow& window);

// A number as a person types it in the window's locale ("0.01" is "0,01" under a decimal comma).
QString inLocale(QString number);
// Types `text` (a number written with a point) into a spin box as inLocale has it: focus, select all, the
// keys, Return.
void typeInto(QAbstractSpinBox* box, const QString& text);

// A key press where the keyboard focus is, the window's menu shortcuts included. After work in the 3D view
// the keyboard is in its window: as a person does, it clicks back into the main window (on its status
// bar) first.
void pressKey(QMainWindow* window, int key, Qt::KeyboardModifiers modifiers = {});

// As a person opens it: a right-click on the part's row in the scene tree. The context menu once it is
// shown, or null when it does not show within 5 s.
QMenu* openSceneTreeMenu(ui::MainWindow& window, PartId part);
// Where screenshots go (the build tree's tests/gui).
// Answers an open Save or Open file dialog as a person does: `path` typed into its file name field, then its
// Save (Open) button clicked. The field's completer is taken off first: its popup, when a loaded machine
// shows it late, takes the key or the click meant for the dialog and leaves the dialog open for ever.
// `fileType`, when given, is the start of the file type to pick first from the dialog's list, by keyboard.
void answerFileDialog(QWidget* modal, const QString& path, const QString& fileType = {});
// Runs `act` on the next modal dialog once it shows (a message box, a file dialog).
void whenModal(std::function<void(QWidget*)> act);

QString shotPath(const QString& name);
// Saves a screenshot of `widget` (the whole window as the screen shows it, when it is `window`).
void shot(QMainWindow* window, QWidget* widget, const QString& name);

}  // namespace vaw::guitest
