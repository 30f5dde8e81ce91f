#include "vaw/ui/viewport.hpp"

#include <Qt3DCore/QEntity>
#include <Qt3DCore/QTransform>
#include <Qt3DExtras/QForwardRenderer>
#include <Qt3DExtras/QPhongMaterial>
#include <Qt3DExtras/Qt3DWindow>
#include <Qt3DRender/QCamera>
#include <Qt3DRender/QDirectionalLight>
#include <Qt3DRender/QGeometryRenderer>
#include <Qt3DRender/QObjectPicker>
#include <Qt3DRender/QPickEvent>
#include <Qt3DRender/QPickingSettings>
#include <Qt3DRender/QPointLight>
#include <Qt3DRender/QRenderCapture>
#include <Qt3DRender/QRenderSettings>
#include <Qt3DRender/QScreenRayCaster>
#include <QApplication>
#include <QMatrix4x4>
#include <QKeyEvent>
#include <QMouseEvent>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <unordered_map>

#include "mesh_geometry.hpp"
#include "orbit_controller.hpp"

namespace vaw::ui {

namespace {

const QColor kClearColor(52, 58, 68);
// Default view direction (from the target towards the eye): front (-y), right (+x), above (+z).
const Eigen::Vector3d kDefaultViewDirection = Eigen::Vector3d(0.75, -1.5, 0.95).normalized();

QColor toQColor(const Eigen::Vector3f& c) {
  const auto channel = [](float v) { return std::clamp(static_cast<double>(v), 0.0, 1.0); };
  return QColor::fromRgbF(static_cast<float>(channel(c.x())), static_cast<float>(channel(c.y())),
                          static_cast<float>(channel(c.z())));
}

QVector3D toQ(const Eigen::Vector3d& v) {
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

QMatrix4x4 toQ(const Eigen::Isometry3d& pose) {
  QMatrix4x4 m;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) m(r, c) = static_cast<float>(pose.matrix()(r, c));
  }
  return m;
}

Eigen::AlignedBox3d worldBox(const vaw::TriMesh& mesh, const Eigen::Isometry3d& pose) {
  Eigen::AlignedBox3d box;
  const Eigen::AlignedBox3d local = mesh.bounds();
  if (local.isEmpty()) return box;
  for (int corner = 0; corner < 8; ++corner) {
    box.extend(pose * local.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner)));
  }
  return box;
}

QColor mix(const QColor& a, const QColor& b, double t) {
  const auto lerp = [t](float x, float y) { return static_cast<float>(x + (y - x) * t); };
  return QColor::fromRgbF(lerp(a.redF(), b.redF()), lerp(a.greenF(), b.greenF()), lerp(a.blueF(), b.blueF()));
}

QColor scaled(const QColor& c, double f) {
  const auto s = [f](float x) { return static_cast<float>(std::clamp(x * f, 0.0, 1.0)); };
  return QColor::fromRgbF(s(c.redF()), s(c.greenF()), s(c.blueF()));
}

}  // namespace

Viewport::Viewport(QWidget* parent) : QWidget(parent) {
  view_ = new Qt3DExtras::Qt3DWindow();
  view_->defaultFrameGraph()->setClearColor(kClearColor);
  // A capture node at the root of the frame graph, so that tests and --screenshot can wait for a
  // rendered frame.
  capture_ = new Qt3DRender::QRenderCapture();
  view_->activeFrameGraph()->setParent(capture_);
  view_->setActiveFrameGraph(capture_);
  view_->renderSettings()->setRenderPolicy(Qt3DRender::QRenderSettings::OnDemand);
  auto* picking = view_->renderSettings()->pickingSettings();
  picking->setPickMethod(Qt3DRender::QPickingSettings::TrianglePicking);
  picking->setPickResultMode(Qt3DRender::QPickingSettings::NearestPick);
  picking->setFaceOrientationPickingMode(Qt3DRender::QPickingSettings::FrontAndBackFace);

  container_ = QWidget::createWindowContainer(view_, this);
  container_->setMinimumSize(320, 240);
  container_->setFocusPolicy(Qt::StrongFocus);
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(container_);

  createScene();
  view_->installEventFilter(this);
}

Viewport::~Viewport() { view_->removeEventFilter(this); }

void Viewport::createScene() {
  root_ = new Qt3DCore::QEntity();

  Qt3DRender::QCamera* cam = view_->camera();
  cam->lens()->setPerspectiveProjection(35.0f, 16.0f / 9.0f, 0.01f, 100.0f);
  cam->setUpVector(QVector3D(0, 0, 1));
  cam->setViewCenter(QVector3D(0, 0, 0));
  cam->setPosition(toQ(kDefaultViewDirection));

  // A headlight that moves with the camera, and a key light from above, front left.
  auto* headlight = new Qt3DRender::QPointLight(cam);
  headlight->setColor(Qt::white);
  headlight->setIntensity(0.55f);
  headlight->setConstantAttenuation(1.0f);
  headlight->setLinearAttenuation(0.0f);
  headlight->setQuadraticAttenuation(0.0f);
  cam->addComponent(headlight);
  auto* keyEntity = new Qt3DCore::QEntity(root_);
  auto* key = new Qt3DRender::QDirectionalLight(keyEntity);
  key->setColor(Qt::white);
  key->setIntensity(0.6f);
  key->setWorldDirection(QVector3D(0.4f, 0.6f, -1.0f).normalized());
  keyEntity->addComponent(key);

  cameraController_ = new OrbitController(root_);
  cameraController_->setCamera(cam);
  cameraController_->setLookSpeed(90.0f);  // degrees per second, arrow keys

  rayCaster_ = new Qt3DRender::QScreenRayCaster(root_);
  rayCaster_->setRunMode(Qt3DRender::QAbstractRayCaster::SingleShot);
  root_->addComponent(rayCaster_);

  view_->setRootEntity(root_);
}

Qt3DRender::QCamera* Viewport::camera() const { return view_->camera(); }

QColor Viewport::clearColor() const { return view_->defaultFrameGraph()->clearColor(); }

void Viewport::setAssembly(const vaw::Assembly* assembly) {
  const bool hadSelection = selected_.has_value();
  selected_.reset();
  parts_.clear();
  environment_.clear();
  delete sceneRoot_;
  sceneRoot_ = new Qt3DCore::QEntity(root_);
  partsBounds_.setEmpty();
  allBounds_.setEmpty();

  // Parts that share a mesh (a box of identical bolts) share its GPU geometry too.
  std::unordered_map<const vaw::TriMesh*, Qt3DRender::QGeometryRenderer*> geometries;
  const auto geometryOf = [&](const vaw::TriMesh& mesh) {
    auto [it, added] = geometries.try_emplace(&mesh, nullptr);
    if (added) it->second = makeFlatShadedRenderer(mesh, sceneRoot_);
    return it->second;
  };
  if (assembly != nullptr) {
    for (const vaw::Part& part : assembly->parts) {
      if (!part.mesh) continue;
      auto* entity = new Qt3DCore::QEntity(sceneRoot_);
      entity->setObjectName(QString::fromStdString(part.name));
      entity->addComponent(geometryOf(*part.mesh));
      auto* transform = new Qt3DCore::QTransform(entity);
      transform->setMatrix(toQ(part.pose));
      entity->addComponent(transform);
      auto* material = new Qt3DExtras::QPhongMaterial(entity);
      entity->addComponent(material);
      QColor color(178, 178, 184);
      if (auto it = assembly->materials.find(part.material); it != assembly->materials.end()) {
        color = toQColor(it->second.color);
      }
      auto* picker = new Qt3DRender::QObjectPicker(entity);
      entity->addComponent(picker);
      const vaw::PartId id = part.id;
      connect(picker, &Qt3DRender::QObjectPicker::clicked, this, [this, id](Qt3DRender::QPickEvent* pick) {
        if (pick->button() == Qt3DRender::QPickEvent::LeftButton && !dragged_) selectPart(id);
      });
      parts_.push_back(PartVisual{id, entity, material, color});
      applyHighlight(parts_.back(), false);
      const Eigen::AlignedBox3d box = worldBox(*part.mesh, part.pose);
      partsBounds_.extend(box);
      allBounds_.extend(box);
    }
    for (const vaw::EnvironmentObject& object : assembly->environment) {
      if (!object.mesh) continue;
      auto* entity = new Qt3DCore::QEntity(sceneRoot_);
      entity->setObjectName(QString::fromStdString(object.name));
      entity->addComponent(geometryOf(*object.mesh));
      auto* transform = new Qt3DCore::QTransform(entity);
      transform->setMatrix(toQ(object.pose));
      entity->addComponent(transform);
      auto* material = new Qt3DExtras::QPhongMaterial(entity);
      const QColor color = toQColor(object.color);
      material->setDiffuse(color);
      material->setAmbient(scaled(color, 0.35));
      material->setSpecular(QColor(20, 20, 20));
      material->setShininess(10.0f);
      entity->addComponent(material);
      // Environment objects are pickable so that a click on them (or on a part hidden behind them)
      // clears the selection instead of selecting what is behind.
      auto* picker = new Qt3DRender::QObjectPicker(entity);
      entity->addComponent(picker);
      connect(picker, &Qt3DRender::QObjectPicker::clicked, this, [this](Qt3DRender::QPickEvent* pick) {
        if (pick->button() == Qt3DRender::QPickEvent::LeftButton && !dragged_) selectPart(std::nullopt);
      });
      environment_.push_back(entity);
      allBounds_.extend(worldBox(*object.mesh, object.pose));
    }
  }
  resetView();
  if (hadSelection) emit partSelected(std::nullopt);
}

void Viewport::applyHighlight(PartVisual& visual, bool selected) {
  const QColor base = visual.color;
  if (selected) {
    visual.material->setDiffuse(mix(base, highlightColor(), 0.45));
    visual.material->setAmbient(scaled(highlightColor(), 0.45));
    visual.material->setSpecular(QColor(60, 60, 60));
  } else {
    visual.material->setDiffuse(base);
    visual.material->setAmbient(scaled(base, 0.3));
    visual.material->setSpecular(QColor(45, 45, 45));
  }
  visual.material->setShininess(40.0f);
}

void Viewport::selectPart(std::optional<vaw::PartId> part) {
  if (part && std::none_of(parts_.begin(), parts_.end(), [&](const PartVisual& v) { return v.id == *part; })) {
    part.reset();  // not drawn: nothing to select
  }
  if (part == selected_) return;
  selected_ = part;
  for (auto& visual : parts_) applyHighlight(visual, selected_ && visual.id == *selected_);
  emit partSelected(selected_);
}

void Viewport::fitToView() {
  const QVector3D eye = view_->camera()->position() - view_->camera()->viewCenter();
  Eigen::Vector3d direction(eye.x(), eye.y(), eye.z());
  frame(direction.norm() > 0.0 ? Eigen::Vector3d(direction.normalized()) : kDefaultViewDirection);
}

void Viewport::resetView() {
  frame(kDefaultViewDirection);
  autoFit_ = true;
}

void Viewport::frame(const Eigen::Vector3d& direction) {
  Eigen::AlignedBox3d box = partsBounds_.isEmpty() ? allBounds_ : partsBounds_;
  if (box.isEmpty()) box = Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-0.5), Eigen::Vector3d::Constant(0.5));
  const Eigen::Vector3d centre = box.center();
  const double radius = std::max(0.5 * box.diagonal().norm(), 1e-3);

  Qt3DRender::QCamera* cam = view_->camera();
  const double width = std::max(1, view_->width());
  const double height = std::max(1, view_->height());
  const double aspect = width / height;
  const double halfV = 0.5 * static_cast<double>(cam->fieldOfView()) * std::numbers::pi / 180.0;
  const double halfH = std::atan(std::tan(halfV) * aspect);
  const double distance = radius / std::sin(std::min(halfV, halfH)) * 1.02;

  Eigen::Vector3d dir = direction.normalized();
  if (std::abs(dir.z()) > 0.999) dir = Eigen::Vector3d(0.0, -0.05, dir.z() > 0 ? 1.0 : -1.0).normalized();
  const double sceneRadius =
      allBounds_.isEmpty() ? radius : std::max(radius, 0.5 * allBounds_.diagonal().norm());
  cam->setAspectRatio(static_cast<float>(aspect));
  cam->setNearPlane(static_cast<float>(std::max(distance * 0.01, 1e-4)));
  const double farthest = 10.0 * std::max(distance, sceneRadius);  // zoom-out limit
  cam->setFarPlane(static_cast<float>(farthest + 2.0 * sceneRadius));
  cam->setUpVector(QVector3D(0, 0, 1));
  cam->setViewCenter(toQ(centre));
  cam->setPosition(toQ(centre + distance * dir));
  cameraController_->setDistanceLimits(static_cast<float>(0.05 * radius),
                                       static_cast<float>(farthest));
}

std::optional<vaw::PartId> Viewport::partAt(const QPoint& windowPos) const {
  const auto hits = rayCaster_->pick(windowPos);
  const Qt3DCore::QEntity* nearest = nullptr;
  float best = std::numeric_limits<float>::infinity();
  for (const auto& hit : hits) {
    if (hit.entity() != nullptr && hit.distance() < best) {
      best = hit.distance();
      nearest = hit.entity();
    }
  }
  for (const auto& visual : parts_) {
    if (visual.entity == nearest) return visual.id;
  }
  return std::nullopt;
}

QPointF Viewport::projectToWindow(const Eigen::Vector3d& world) const {
  const Qt3DRender::QCamera* cam = view_->camera();
  const QVector4D clip = cam->projectionMatrix() * cam->viewMatrix() * QVector4D(toQ(world), 1.0f);
  if (clip.w() == 0.0f) return {};
  const double x = static_cast<double>(clip.x() / clip.w());
  const double y = static_cast<double>(clip.y() / clip.w());
  return {(x + 1.0) * 0.5 * view_->width(), (1.0 - y) * 0.5 * view_->height()};
}

void Viewport::onClick(const QPoint& windowPos) {
  // Parts select themselves through their QObjectPicker; a click that hits no part clears the
  // selection (nothing is picked on the background, so ask the ray caster).
  if (!partAt(windowPos)) selectPart(std::nullopt);
}

bool Viewport::eventFilter(QObject* watched, QEvent* event) {
  if (watched == view_) {
    switch (event->type()) {
      case QEvent::MouseButtonPress: {
        const auto* mouse = static_cast<QMouseEvent*>(event);
        pressPos_ = mouse->position().toPoint();
        dragged_ = false;
        break;
      }
      case QEvent::MouseMove: {
        const auto* mouse = static_cast<QMouseEvent*>(event);
        if (mouse->buttons() != Qt::NoButton &&
            (mouse->position().toPoint() - pressPos_).manhattanLength() > QApplication::startDragDistance()) {
          dragged_ = true;
          autoFit_ = false;
        }
        break;
      }
      case QEvent::MouseButtonRelease: {
        const auto* mouse = static_cast<QMouseEvent*>(event);
        if (mouse->button() == Qt::LeftButton && !dragged_) onClick(mouse->position().toPoint());
        break;
      }
      case QEvent::KeyPress: {
        // The 3D view is a native window of its own: the main window's shortcuts do not reach it.
        const auto* key = static_cast<QKeyEvent*>(event);
        if (key->modifiers() == Qt::NoModifier && key->key() == Qt::Key_F) {
          fitToView();
          return true;
        }
        if (key->modifiers() == Qt::NoModifier && key->key() == Qt::Key_Home) {
          resetView();
          return true;
        }
        if (key->key() == Qt::Key_Escape) {
          selectPart(std::nullopt);
          return true;
        }
        autoFit_ = false;
        break;
      }
      case QEvent::Wheel: autoFit_ = false; break;
      case QEvent::Resize:
        if (autoFit_) frame(kDefaultViewDirection);
        break;
      default: break;
    }
  }
  return QWidget::eventFilter(watched, event);
}

}  // namespace vaw::ui
