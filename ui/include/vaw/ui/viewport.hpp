#pragma once
// The 3D view: one Qt3D entity per part and per environment object, built synchronously from the
// core's meshes; orbit/pan/zoom camera with z up; picking. Selection is by PartId.
#include <Eigen/Geometry>
#include <QColor>
#include <QPoint>
#include <QPointF>
#include <QWidget>
#include <optional>
#include <vector>

#include "vaw/assembly.hpp"

namespace Qt3DCore {
class QEntity;
}
namespace Qt3DRender {
class QCamera;
class QRenderCapture;
class QScreenRayCaster;
}  // namespace Qt3DRender
namespace Qt3DExtras {
class Qt3DWindow;
class QPhongMaterial;
}  // namespace Qt3DExtras

namespace vaw::ui {

class OrbitController;

class Viewport : public QWidget {
  Q_OBJECT
 public:
  explicit Viewport(QWidget* parent = nullptr);
  ~Viewport() override;
  Viewport(const Viewport&) = delete;
  Viewport& operator=(const Viewport&) = delete;

  // Rebuilds the scene from `assembly` (null: empty scene) and frames it from the default direction.
  // Copies what it draws: no pointer into the assembly is kept.
  void setAssembly(const vaw::Assembly* assembly);

  [[nodiscard]] std::optional<vaw::PartId> selectedPart() const { return selected_; }
  [[nodiscard]] std::size_t partCount() const { return parts_.size(); }

  // The part under a point of the 3D window (window coordinates), by a synchronous ray cast.
  [[nodiscard]] std::optional<vaw::PartId> partAt(const QPoint& windowPos) const;
  // Where a world point (metres) appears in the 3D window (window coordinates).
  [[nodiscard]] QPointF projectToWindow(const Eigen::Vector3d& world) const;
  // World bounds of everything drawn that belongs to the assembly's parts (m).
  [[nodiscard]] Eigen::AlignedBox3d partsBounds() const { return partsBounds_; }

  [[nodiscard]] Qt3DExtras::Qt3DWindow* view3d() const { return view_; }
  [[nodiscard]] Qt3DRender::QCamera* camera() const;
  // The root of the frame graph: request captures from it (tests, screenshots).
  [[nodiscard]] Qt3DRender::QRenderCapture* renderCapture() const { return capture_; }
  [[nodiscard]] QColor clearColor() const;

  static QColor highlightColor() { return {255, 140, 26}; }

 public slots:
  // Selects and highlights `part` (nothing: clears). Emits partSelected when the selection changes.
  void selectPart(std::optional<vaw::PartId> part);
  // Frames the parts, keeping the current view direction.
  void fitToView();
  // Frames the parts from the default direction (front, right, above; z up).
  void resetView();

 signals:
  void partSelected(std::optional<vaw::PartId> part);

 protected:
  bool eventFilter(QObject* watched, QEvent* event) override;

 private:
  struct PartVisual {
    vaw::PartId id = 0;
    Qt3DCore::QEntity* entity = nullptr;
    Qt3DExtras::QPhongMaterial* material = nullptr;
    QColor color;
  };
  void createScene();
  void frame(const Eigen::Vector3d& direction);
  void applyHighlight(PartVisual& visual, bool selected);
  void onClick(const QPoint& windowPos);

  Qt3DExtras::Qt3DWindow* view_ = nullptr;
  QWidget* container_ = nullptr;
  Qt3DCore::QEntity* root_ = nullptr;
  Qt3DCore::QEntity* sceneRoot_ = nullptr;  // parts and environment; rebuilt per assembly
  Qt3DRender::QRenderCapture* capture_ = nullptr;
  Qt3DRender::QScreenRayCaster* rayCaster_ = nullptr;
  OrbitController* cameraController_ = nullptr;
  std::vector<PartVisual> parts_;
  std::vector<Qt3DCore::QEntity*> environment_;
  std::optional<vaw::PartId> selected_;
  Eigen::AlignedBox3d partsBounds_;
  Eigen::AlignedBox3d allBounds_;
  QPoint pressPos_;
  bool dragged_ = false;
  bool autoFit_ = true;  // refit on resize until the user moves the camera
};

}  // namespace vaw::ui
