#include "vaw/ui/viewport.hpp"
#include "qt_convert.hpp"

#include <Qt3DCore/QEntity>
#include <Qt3DCore/QTransform>
#include <Qt3DExtras/QCylinderMesh>
#include <Qt3DExtras/QForwardRenderer>
#include <Qt3DExtras/QPhongAlphaMaterial>
#include <Qt3DExtras/QPhongMaterial>
#include <Qt3DExtras/QSphereMesh>
#include <Qt3DExtras/QTorusMesh>
#include <Qt3DExtras/Qt3DWindow>
#include <Qt3DRender/QCamera>
#include <Qt3DRender/QDirectionalLight>
#include <Qt3DRender/QGeometryRenderer>
#include <Qt3DRender/QPickingSettings>
#include <Qt3DRender/QPointLight>
#include <Qt3DRender/QRenderCapture>
#include <Qt3DRender/QRenderSettings>
#include <Qt3DRender/QScreenRayCaster>
#include <QApplication>
#include <QKeyEvent>
#include <QMatrix4x4>
#include <QMouseEvent>
#include <QVBoxLayout>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <unordered_map>

#include "mesh_geometry.hpp"
#include "orbit_controller.hpp"
#include "vaw/units.hpp"

namespace vaw::ui {

namespace {

const QColor kClearColor(52, 58, 68);
// Default view direction (from the target towards the eye): front (-y), right (+x), above (+z).
const Eigen::Vector3d kDefaultViewDirection = Eigen::Vector3d(0.75, -1.5, 0.95).normalized();
using vaw::kDeg;
constexpr double kHandTurnRate = 90.0 * kDeg;  // rad/s while Q/E, Z/X or C/V is held
constexpr double kBaseKeyRate = 10.0 * kDeg;   // rad/s while I/K, J/L or U/O is held
constexpr double kHoistRate = 0.15;            // m/s while Shift+Up/Down is held
constexpr double kHoistYawRate = 30.0 * kDeg;  // rad/s while Shift+Left/Right is held
constexpr std::size_t kMaxDropLines = 16;      // lifted parts drawn with a drop line at once


QMatrix4x4 toQ(const Eigen::Isometry3d& pose) {
  QMatrix4x4 m;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) m(r, c) = static_cast<float>(pose.matrix()(r, c));
  }
  return m;
}

QColor scaled(const QColor& c, double f) {
  const auto s = [f](float x) { return static_cast<float>(std::clamp(x * f, 0.0, 1.0)); };
  return QColor::fromRgbF(s(c.redF()), s(c.greenF()), s(c.blueF()));
}

void setColor(Qt3DExtras::QPhongMaterial* material, const QColor& color, double ambient = 0.3) {
  material->setDiffuse(color);
  material->setAmbient(scaled(color, ambient));
}

Eigen::AlignedBox3d worldBox(const Eigen::AlignedBox3d& local, const Eigen::Isometry3d& pose) {
  Eigen::AlignedBox3d box;
  if (local.isEmpty()) return box;
  for (int corner = 0; corner < 8; ++corner) box.extend(pose * local.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner)));
  return box;
}



}  // namespace

QColor Viewport::highlightColor() { return toQColor(vaw::view::kHighlight); }

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

Viewport::Overlay Viewport::makeOverlay(Qt3DRender::QGeometryRenderer* mesh, const QColor& color) {
  Overlay o;
  o.entity = new Qt3DCore::QEntity(sceneRoot_);
  o.entity->addComponent(mesh);
  o.transform = new Qt3DCore::QTransform(o.entity);
  o.entity->addComponent(o.transform);
  o.material = new Qt3DExtras::QPhongMaterial(o.entity);
  setColor(o.material, color, 0.6);
  o.material->setSpecular(QColor(20, 20, 20));
  o.entity->addComponent(o.material);
  hide(o);
  return o;
}

void Viewport::setScene(const vaw::view::SceneDescription* scene) {
  const bool hadSelection = selected_.has_value();
  selected_.reset();
  candidate_.reset();
  grabbing_ = false;
  parts_.clear();
  visualOfPart_.clear();
  environment_.clear();
  cables_.clear();
  hooks_.clear();
  drops_.clear();
  marks_.clear();
  axesShown_.reset();
  constraintShown_.reset();
  constraintSegments_.clear();
  delete sceneRoot_;
  for (auto& line : constraintLines_) line = Overlay{};
  captureRing_ = captureLine_ = Overlay{};
  captureShown_.reset();
  swept_ = nullptr;
  if (sweptMesh_) {
    sweptMesh_.reset();
    emit sweptVolumeChanged();
  }
  sceneRoot_ = new Qt3DCore::QEntity(root_);
  partsBounds_.setEmpty();
  allBounds_.setEmpty();

  if (scene != nullptr) {
    // Drawables that share a mesh buffer (a box of identical bolts) share its GPU geometry too.
    std::unordered_map<const vaw::view::MeshBuffer*, Qt3DRender::QGeometryRenderer*> geometries;
    const auto geometryOf = [&](const vaw::view::MeshBuffer& mesh) {
      auto [it, added] = geometries.try_emplace(&mesh, nullptr);
      if (added) it->second = makeRenderer(mesh, sceneRoot_);
      return it->second;
    };
    visualOfPart_.resize(scene->partDrawable.size());
    for (const vaw::view::Drawable& d : scene->drawables) {
      auto* entity = new Qt3DCore::QEntity(sceneRoot_);
      entity->setObjectName(QString::fromStdString(d.name));
      entity->addComponent(geometryOf(*d.mesh));
      auto* transform = new Qt3DCore::QTransform(entity);
      transform->setMatrix(toQ(d.pose));
      entity->addComponent(transform);
      auto* material = new Qt3DExtras::QPhongMaterial(entity);
      setColor(material, toQColor(d.color));
      entity->addComponent(material);
      const Eigen::AlignedBox3d box = worldBox(d.mesh->bounds, d.pose);
      allBounds_.extend(vaw::view::boundsOf(d));
      if (d.kind == vaw::view::DrawableKind::Environment) {
        material->setSpecular(QColor(20, 20, 20));
        material->setShininess(10.0f);
        environment_.push_back(entity);
        continue;
      }
      material->setSpecular(QColor(45, 45, 45));
      material->setShininess(40.0f);
      visualOfPart_[d.index] = parts_.size();
      parts_.push_back(PartVisual{d.index, d.kind == vaw::view::DrawableKind::Base, entity, transform, material, d.pose,
                                  d.color, d.mesh->bounds});
      partsBounds_.extend(box);
    }
    // Overlays share three unit meshes.
    auto* cylinder = new Qt3DExtras::QCylinderMesh(sceneRoot_);
    cylinder->setRadius(1.0f);
    cylinder->setLength(1.0f);
    cylinder->setSlices(12);
    cylinder->setRings(2);
    cylinder_ = cylinder;
    auto* sphere = new Qt3DExtras::QSphereMesh(sceneRoot_);
    sphere->setRadius(1.0f);
    sphere_ = sphere;
    auto* torus = new Qt3DExtras::QTorusMesh(sceneRoot_);
    torus->setRadius(1.0f);
    torus->setMinorRadius(0.25f);
    torus_ = torus;
    hands_[0] = makeOverlay(sphere_, toQColor(vaw::view::stateColor(interact::PartState::InHand)));
    hands_[1] = makeOverlay(sphere_, toQColor(vaw::view::stateColor(interact::PartState::InHand)));
    for (std::size_t i = 0; i < scene->hoists.size(); ++i) {
      cables_.push_back(makeOverlay(cylinder_, QColor(40, 40, 40)));
      hooks_.push_back(makeOverlay(torus_, QColor(60, 60, 60)));
    }
    // Drop lines for the parts that can be lifted at once (held, hoisted, flying), made up front: entities
    // added after the first frame that share a mesh are not drawn (Qt 6.4).
    const std::size_t pool = std::min<std::size_t>(kMaxDropLines, scene->partDrawable.size());
    for (std::size_t i = 0; i < pool; ++i) {
      drops_.push_back(makeOverlay(cylinder_, QColor(250, 250, 250)));
      marks_.push_back(makeOverlay(cylinder_, QColor(25, 25, 25)));  // a contact spot, read like a shadow
    }
    const QColor axisColors[3] = {QColor(220, 50, 50), QColor(50, 190, 60), QColor(60, 90, 230)};
    for (int k = 0; k < 3; ++k) axes_[k] = makeOverlay(cylinder_, axisColors[k]);
    // Magenta: no state tint, selection or axis colour uses it.
    for (auto& line : constraintLines_) line = makeOverlay(cylinder_, QColor(225, 0, 200));
    captureRing_ = makeOverlay(torus_, QColor(215, 50, 50));
    captureLine_ = makeOverlay(cylinder_, QColor(215, 50, 50));
  }
  resetView();
  if (hadSelection) emit partSelected(std::nullopt);
}

double Viewport::lineRadius() const {
  // About two pixels wide at the parts' distance when they fill the view.
  const double size = partsBounds_.isEmpty() ? 0.5 : partsBounds_.diagonal().norm();
  return std::clamp(0.004 * size, 0.001, 0.01);
}

void Viewport::hide(Overlay& o) {
  if (o.transform->scale3D() != QVector3D(0, 0, 0)) o.transform->setScale3D(QVector3D(0, 0, 0));
}

void Viewport::placeAt(Overlay& o, const Eigen::Isometry3d& pose, const Eigen::Vector3d& scale) {
  Eigen::Affine3d m = pose * Eigen::Scaling(scale);
  Eigen::Isometry3d asIso;
  asIso.matrix() = m.matrix();
  o.transform->setMatrix(toQ(asIso));
}

void Viewport::placeLine(Overlay& o, const Eigen::Vector3d& from, const Eigen::Vector3d& to, double radius) {
  const Eigen::Vector3d d = to - from;
  const double length = d.norm();
  if (!(length > 1e-9)) {
    hide(o);
    return;
  }
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitY(), d / length).toRotationMatrix();
  pose.translation() = 0.5 * (from + to);
  placeAt(o, pose, Eigen::Vector3d(radius, length, radius));
}

void Viewport::applyFrame(const vaw::view::Frame& f) {
  std::size_t updates = 0;
  for (PartVisual& v : parts_) {
    if (v.id >= f.parts.size()) continue;
    const vaw::view::PartFrame& p = f.parts[v.id];
    if (p.pose.matrix() != v.pose.matrix()) {
      v.pose = p.pose;
      v.transform->setMatrix(toQ(p.pose));
      ++updates;
    }
    if (!(p.color == v.color)) {
      v.color = p.color;
      setColor(v.material, toQColor(p.color), p.selected ? 0.45 : 0.3);
      ++updates;
    }
  }
  if (parts_.empty()) {
    lastUpdates_ = 0;
    return;
  }
  const double r = lineRadius();
  // The hands: a small sphere where each closed hand holds something.
  for (int k = 0; k < 2; ++k) {
    const auto& hand = f.hands[static_cast<std::size_t>(k)];
    if (hand.grab && hand.holding) {
      placeAt(hands_[k], hand.pose, Eigen::Vector3d::Constant(4.0 * r));
      ++updates;
    } else {
      hide(hands_[k]);
    }
  }
  for (std::size_t i = 0; i < cables_.size(); ++i) {
    if (i >= f.hoists.size()) {
      hide(cables_[i]);
      hide(hooks_[i]);
      continue;
    }
    const vaw::view::HoistFrame& h = f.hoists[i];
    const Eigen::Vector3d hook = h.hook.translation();
    const double ring = 8.0 * r;
    placeLine(cables_[i], Eigen::Vector3d(hook.x(), hook.y(), h.top), hook + Eigen::Vector3d(0, 0, ring), 0.5 * r);
    Eigen::Isometry3d hookPose = h.hook;
    hookPose.translation() += Eigen::Vector3d(0, 0, ring);
    hookPose.linear() = h.hook.linear() * Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
    placeAt(hooks_[i], hookPose, Eigen::Vector3d::Constant(ring));
    setColor(hooks_[i].material,
             h.engaged ? toQColor(vaw::view::stateColor(interact::PartState::OnTool)) : QColor(60, 60, 60), 0.6);
    updates += 2;
  }
  // Drop lines under lifted parts, and a flat marker where they meet the surface.
  for (std::size_t i = 0; i < drops_.size(); ++i) {
    if (i >= f.drops.size()) {
      hide(drops_[i]);
      hide(marks_[i]);
      continue;
    }
    const vaw::view::DropLine& d = f.drops[i];
    placeLine(drops_[i], d.from, d.to, 0.5 * r);
    Eigen::Isometry3d mark = Eigen::Isometry3d::Identity();
    mark.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    mark.translation() = d.to + Eigen::Vector3d(0, 0, 0.25 * r);
    placeAt(marks_[i], mark, Eigen::Vector3d(7.0 * r, 0.5 * r, 7.0 * r));
    updates += 2;
  }
  if (axesShown_ && axesShown_->part < f.parts.size()) {
    const Eigen::Isometry3d& pose = f.parts[axesShown_->part].pose;
    const Eigen::Vector3d c = pose * axesShown_->centre;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = pose.linear() * axesShown_->axes.col(k) * axesShown_->halfLengths[k];
      placeLine(axes_[k], c - a, c + a, 1.0 * r);
    }
    updates += 3;
  } else {
    for (auto& a : axes_) hide(a);
  }
  if (constraintShown_) {
    placeConstraint();
    updates += constraintSegments_.size();
  }
  lastUpdates_ = updates;
}

void Viewport::showConstraintGeometry(const ConstraintGeometry& geometry) {
  constraintShown_ = geometry;
  placeConstraint();
}

void Viewport::hideConstraintGeometry() {
  constraintShown_.reset();
  placeConstraint();
}

void Viewport::placeConstraint() {
  constraintSegments_.clear();
  const ConstraintGeometry* g = constraintShown_ ? &*constraintShown_ : nullptr;
  if (g != nullptr && g->partner < visualOfPart_.size() && visualOfPart_[g->partner]) {
    const Eigen::Isometry3d& pose = parts_[*visualOfPart_[g->partner]].pose;
    const Eigen::Vector3d c = pose * g->point;
    const Eigen::Vector3d d = (pose.linear() * g->direction).normalized();
    const double half = 0.5 * g->size;
    if (g->kind == ConstraintGeometry::Kind::Axis) {
      constraintSegments_.emplace_back(c - half * d, c + half * d);
    } else {
      // Two directions in the plane; which two does not matter, the square is symmetric.
      const Eigen::Vector3d u = d.unitOrthogonal(), v = d.cross(u);
      const Eigen::Vector3d corners[4] = {c + half * (u + v), c + half * (-u + v), c + half * (-u - v), c + half * (u - v)};
      for (int k = 0; k < 4; ++k) constraintSegments_.emplace_back(corners[k], corners[(k + 1) % 4]);
      constraintSegments_.emplace_back(c, c + half * d);
    }
  }
  if (constraintLines_[0].entity == nullptr) return;  // no scene
  const double r = lineRadius();
  for (std::size_t k = 0; k < kConstraintLines; ++k) {
    if (k < constraintSegments_.size()) placeLine(constraintLines_[k], constraintSegments_[k].first, constraintSegments_[k].second, 0.8 * r);
    else hide(constraintLines_[k]);
  }
}

void Viewport::showSweptVolume(std::shared_ptr<const vaw::view::MeshBuffer> mesh) {
  delete swept_;
  swept_ = nullptr;
  sweptMesh_ = std::move(mesh);
  if (sweptMesh_ && sceneRoot_ != nullptr) {
    swept_ = new Qt3DCore::QEntity(sceneRoot_);
    swept_->setObjectName(QStringLiteral("sweptVolume"));
    swept_->addComponent(makeRenderer(*sweptMesh_, swept_));
    auto* material = new Qt3DExtras::QPhongAlphaMaterial(swept_);
    material->setDiffuse(QColor::fromRgbF(vaw::view::kSweptColor.r, vaw::view::kSweptColor.g, vaw::view::kSweptColor.b));
    material->setAmbient(QColor(40, 80, 140));
    material->setSpecular(QColor(20, 20, 20));
    material->setAlpha(vaw::view::kSweptAlpha);
    swept_->addComponent(material);
  }
  emit sweptVolumeChanged();
}

void Viewport::showCaptureZone(const std::optional<CaptureZone>& zone) {
  captureShown_ = zone;
  if (captureRing_.entity == nullptr) return;  // no scene
  if (!zone) {
    hide(captureRing_);
    hide(captureLine_);
    return;
  }
  const QColor color = zone->captures ? QColor(50, 190, 60) : QColor(215, 50, 50);
  setColor(captureRing_.material, color, 0.6);
  setColor(captureLine_.material, color, 0.6);
  const Eigen::Vector3d d = zone->direction.normalized();
  Eigen::Isometry3d ring = Eigen::Isometry3d::Identity();
  ring.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), d).toRotationMatrix();
  ring.translation() = zone->point;
  // The torus's tube is a quarter of its radius: the ring's inside edge is the capture distance.
  placeAt(captureRing_, ring, Eigen::Vector3d::Constant(zone->reach / 0.75));
  // The axis (or normal) on from the ring, away from the part.
  placeLine(captureLine_, zone->point, zone->point + (zone->axis ? 4.0 : 2.0) * zone->reach * d, 0.6 * lineRadius());
}

void Viewport::showAxes(const std::optional<Axes>& axes) {
  axesShown_ = axes;
  if (!axes)
    for (auto& a : axes_)
      if (a.entity) hide(a);
}

void Viewport::selectPart(std::optional<vaw::PartId> part) {
  if (part && (*part >= visualOfPart_.size() || !visualOfPart_[*part])) part.reset();  // not drawn
  if (part == selected_) return;
  selected_ = part;
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

void Viewport::lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& centre) {
  Qt3DRender::QCamera* cam = view_->camera();
  cam->setUpVector(QVector3D(0.0f, 0.0f, 1.0f));
  cam->setPosition(toQ(eye));
  cam->setViewCenter(toQ(centre));
  autoFit_ = false;
}

Eigen::AlignedBox3d Viewport::partsBounds() const {
  Eigen::AlignedBox3d box;
  for (const PartVisual& v : parts_) box.extend(worldBox(v.local, v.pose));
  return box;
}

void Viewport::frame(const Eigen::Vector3d& direction) {
  Eigen::AlignedBox3d box = parts_.empty() ? allBounds_ : partsBounds();
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

std::optional<Viewport::Pick> Viewport::pick(const QPoint& windowPos) const {
  const auto hits = rayCaster_->pick(windowPos);
  // The nearest hit on a part or an environment object decides; overlays (lines, hands) do not block.
  const Qt3DCore::QEntity* nearest = nullptr;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  float best = std::numeric_limits<float>::infinity();
  for (const auto& hit : hits) {
    const Qt3DCore::QEntity* e = hit.entity();
    if (e == nullptr || hit.distance() >= best) continue;
    const bool solid = std::any_of(parts_.begin(), parts_.end(), [e](const PartVisual& v) { return v.entity == e; }) ||
                       std::find(environment_.begin(), environment_.end(), e) != environment_.end();
    if (!solid) continue;
    best = hit.distance();
    nearest = e;
    point = toEigen(hit.worldIntersection());
  }
  for (const auto& visual : parts_) {
    if (visual.entity == nearest) return Pick{visual.id, point};
  }
  return std::nullopt;
}

QPoint Viewport::windowToGlobal(const QPoint& windowPos) const { return view_->mapToGlobal(windowPos); }

std::optional<vaw::PartId> Viewport::partAt(const QPoint& windowPos) const {
  const auto p = pick(windowPos);
  return p ? std::optional(p->part) : std::nullopt;
}

QPointF Viewport::projectToWindow(const Eigen::Vector3d& world) const {
  const Qt3DRender::QCamera* cam = view_->camera();
  const QVector4D clip = cam->projectionMatrix() * cam->viewMatrix() * QVector4D(toQ(world), 1.0f);
  if (clip.w() == 0.0f) return {};
  const double x = static_cast<double>(clip.x() / clip.w());
  const double y = static_cast<double>(clip.y() / clip.w());
  return {(x + 1.0) * 0.5 * view_->width(), (1.0 - y) * 0.5 * view_->height()};
}

std::pair<Eigen::Vector3d, Eigen::Vector3d> Viewport::rayThrough(const QPointF& windowPos) const {
  // From the eye through the point on the near plane (the far plane is far enough for float round-off to
  // bend the ray).
  const Qt3DRender::QCamera* cam = view_->camera();
  const QRect area(0, 0, view_->width(), view_->height());
  const auto x = static_cast<float>(windowPos.x()), y = static_cast<float>(view_->height() - windowPos.y());
  const QVector3D nearPoint = QVector3D(x, y, 0.0f).unproject(cam->viewMatrix(), cam->projectionMatrix(), area);
  const Eigen::Vector3d eye = toEigen(cam->position());
  return {eye, (toEigen(nearPoint) - eye).normalized()};
}

// Where the pointer puts the hand: on the plane through the grab point facing the camera (moved in depth
// by the wheel).
Eigen::Vector3d Viewport::handOnPlane(const QPointF& windowPos) const {
  const auto [o, d] = rayThrough(windowPos);
  const double denominator = planeNormal_.dot(d);
  if (std::abs(denominator) < 1e-9) return planePoint_;
  return o + d * (planeNormal_.dot(planePoint_ - o) / denominator);
}

std::optional<Eigen::Isometry3d> Viewport::partPose(vaw::PartId part) const {
  if (part >= visualOfPart_.size() || !visualOfPart_[part]) return std::nullopt;
  return parts_[*visualOfPart_[part]].pose;
}

void Viewport::setPickingFaces(bool on) { pickingFaces_ = on; }

void Viewport::onClick(const QPoint& windowPos) {
  if (!pickingFaces_) {
    selectPart(partAt(windowPos));
    return;
  }
  // A miss (the table, the background) keeps the selection: the user is aiming, not clearing.
  if (const auto p = pick(windowPos)) {
    selectPart(p->part);
    emit facePicked(p->part, p->point);
  }
}

void Viewport::keyRates() {
  const auto held = [this](int key) { return keysDown_.contains(key) ? 1.0 : 0.0; };
  if (grabbing_) {
    const QVector3D view = (camera()->viewCenter() - camera()->position()).normalized();
    const Eigen::Vector3d right = toEigen(QVector3D::crossProduct(view, QVector3D(0, 0, 1)).normalized());
    emit handTurn(kHandTurnRate * ((held(Qt::Key_Q) - held(Qt::Key_E)) * Eigen::Vector3d::UnitZ() +
                                   (held(Qt::Key_Z) - held(Qt::Key_X)) * right +
                                   (held(Qt::Key_C) - held(Qt::Key_V)) * toEigen(view)));
  }
  emit baseRates((held(Qt::Key_I) - held(Qt::Key_K)) * kBaseKeyRate, (held(Qt::Key_L) - held(Qt::Key_J)) * kBaseKeyRate,
                 (held(Qt::Key_U) - held(Qt::Key_O)) * kBaseKeyRate);
  const bool shift = keysDown_.contains(Qt::Key_Shift);
  emit hoistRates(shift ? (held(Qt::Key_Up) - held(Qt::Key_Down)) * kHoistRate : 0.0,
                  shift ? (held(Qt::Key_Left) - held(Qt::Key_Right)) * kHoistYawRate : 0.0);
}

bool Viewport::eventFilter(QObject* watched, QEvent* event) {
  if (watched != view_) return QWidget::eventFilter(watched, event);
  switch (event->type()) {
    case QEvent::MouseButtonPress: {
      const auto* mouse = static_cast<QMouseEvent*>(event);
      pressPos_ = mouse->position().toPoint();
      dragged_ = false;
      candidate_.reset();
      if (mouse->button() != Qt::LeftButton || (mouse->modifiers() & (Qt::AltModifier | Qt::ShiftModifier))) break;
      // Picking faces, a drag turns the view to reach the next face: nothing is grabbed.
      if (pickingFaces_) break;
      // A press on a part that a hand can take starts a possible grab: the camera does not see it.
      if (auto p = pick(pressPos_); p && !parts_[*visualOfPart_[p->part]].base) {
        candidate_ = p;
        bothHands_ = (mouse->modifiers() & Qt::ControlModifier) != 0;
        cameraController_->setSuspended(true);
        return true;
      }
      break;
    }
    case QEvent::MouseMove: {
      const auto* mouse = static_cast<QMouseEvent*>(event);
      if (mouse->buttons() != Qt::NoButton &&
          (mouse->position().toPoint() - pressPos_).manhattanLength() > QApplication::startDragDistance()) {
        dragged_ = true;
        if (!candidate_) autoFit_ = false;
      }
      if (!candidate_) break;
      if (dragged_ && !grabbing_) {
        grabbing_ = true;
        planePoint_ = candidate_->point;
        planeNormal_ = toEigen((camera()->viewCenter() - camera()->position()).normalized());
        selectPart(candidate_->part);
        emit grabStarted(candidate_->part, candidate_->point, bothHands_);
        keyRates();
      }
      if (grabbing_) {
        lastPointer_ = mouse->position();
        emit handMoved(handOnPlane(lastPointer_));
      }
      return true;
    }
    case QEvent::MouseButtonRelease: {
      const auto* mouse = static_cast<QMouseEvent*>(event);
      // A right drag turns the view; a right click asks for the menu of what is under it.
      if (mouse->button() == Qt::RightButton && !grabbing_ &&
          (mouse->position().toPoint() - pressPos_).manhattanLength() < QApplication::startDragDistance())
        emit contextMenuRequested(mouse->position().toPoint());
      if (mouse->button() != Qt::LeftButton) break;
      cameraController_->setSuspended(false);
      if (grabbing_) {
        grabbing_ = false;
        candidate_.reset();
        emit handTurn(Eigen::Vector3d::Zero());
        emit grabEnded();
        return true;
      }
      const bool ours = candidate_.has_value();
      candidate_.reset();
      if (!dragged_) onClick(mouse->position().toPoint());
      if (ours) return true;
      break;
    }
    case QEvent::Wheel:
      if (grabbing_) {
        // The wheel pushes the held part away from the camera (forward) or pulls it closer: 5 % of its
        // distance along the view a notch.
        const auto* wheel = static_cast<QWheelEvent*>(event);
        const double notches = wheel->angleDelta().y() / 120.0;
        const double distance = planeNormal_.dot(planePoint_ - toEigen(camera()->position()));
        planePoint_ += planeNormal_ * (0.05 * distance * notches);
        emit handMoved(handOnPlane(lastPointer_));
        return true;
      }
      autoFit_ = false;
      break;
    case QEvent::KeyPress:
    case QEvent::KeyRelease: {
      // The 3D view is a native window of its own: the main window's shortcuts do not reach it.
      const auto* key = static_cast<QKeyEvent*>(event);
      const bool press = event->type() == QEvent::KeyPress;
      if (press && key->modifiers() == Qt::NoModifier && key->key() == Qt::Key_F) {
        fitToView();
        return true;
      }
      if (press && key->modifiers() == Qt::NoModifier && key->key() == Qt::Key_Home) {
        resetView();
        return true;
      }
      if (press && key->key() == Qt::Key_Escape) {
        if (pickingFaces_) {
          emit facePickCancelled();
          return true;
        }
        selectPart(std::nullopt);
        return true;
      }
      if (press && key->key() == Qt::Key_H && !key->isAutoRepeat()) {
        emit hoistToggled();
        return true;
      }
      static const QSet<int> held{Qt::Key_Q, Qt::Key_E, Qt::Key_Z, Qt::Key_X, Qt::Key_C, Qt::Key_V, Qt::Key_I, Qt::Key_K,
                                  Qt::Key_J, Qt::Key_L, Qt::Key_U, Qt::Key_O, Qt::Key_Shift};
      const bool arrowWithShift = (key->modifiers() & Qt::ShiftModifier) &&
                                  (key->key() == Qt::Key_Up || key->key() == Qt::Key_Down ||
                                   key->key() == Qt::Key_Left || key->key() == Qt::Key_Right);
      if (held.contains(key->key()) || arrowWithShift) {
        if (!key->isAutoRepeat()) {
          if (press) keysDown_.insert(key->key());
          else keysDown_.remove(key->key());
          if (key->key() == Qt::Key_Shift && !press)
            for (int k : {Qt::Key_Up, Qt::Key_Down, Qt::Key_Left, Qt::Key_Right}) keysDown_.remove(k);
          keyRates();
        }
        // Shift and arrows also reach the camera (orbit with arrows, pan with Shift+drag) unless combined.
        if (!arrowWithShift && key->key() != Qt::Key_Shift) return true;
        if (arrowWithShift) return true;
        break;
      }
      if (press && !key->isAutoRepeat() && key->key() != Qt::Key_Control && key->key() != Qt::Key_Alt &&
          key->key() != Qt::Key_Meta) {
        emit shortcutKey(QKeySequence(key->keyCombination()));
        return true;
      }
      break;
    }
    case QEvent::FocusOut:
      if (!keysDown_.isEmpty()) {
        keysDown_.clear();
        keyRates();
      }
      break;
    case QEvent::Resize:
      if (autoFit_) frame(kDefaultViewDirection);
      break;
    default: break;
  }
  return QWidget::eventFilter(watched, event);
}

}  // namespace vaw::ui
