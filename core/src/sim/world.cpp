// The step, the base, transitions, live edits, snapshots and the public API of vaw::sim::World.
#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "world_impl.hpp"
#include "vaw/units.hpp"

namespace vaw::sim {

using detail::angleOf;
using detail::fmt;
using vaw::kDeg;
using interact::Event;
using interact::PartState;

Settings settingsFor(const Assembly& assembly) {
  Settings s;
  const SceneSettings& in = assembly.settings;
  if (in.rate) s.rate = *in.rate;
  if (in.freeFlightScale) s.gravity.freeFlight = *in.freeFlightScale;
  if (in.slideScale) s.gravity.slide = *in.slideScale;
  if (in.rotationScale) s.gravity.rotation = *in.rotationScale;
  if (in.rotationMethod)
    if (const auto m = dyn::parseMethod(*in.rotationMethod, dyn::Hinge::kMethods)) s.rotationMethod = *m;
  if (in.placeAtRest) s.placeAtRest = *in.placeAtRest;
  return s;
}

World::Impl::Impl(std::shared_ptr<const Scene> s, Settings st)
    : scene(std::move(s)), assembly(scene->assembly()), collision(scene->collision().instance()) {
  settings = st;
  if (settings.hoist) {
    Hoist h;
    h.position = settings.hoist->position;
    h.reach = settings.hoist->reach;
    h.lowest = -std::numeric_limits<double>::infinity();
    h.highest = std::numeric_limits<double>::infinity();
    hoistTool = h;
  } else if (!assembly.hoists.empty()) {
    hoistTool = assembly.hoists.front();
  }
  base = assembly.base;
  if (base) baseLoad = basePose = assembly.parts[*base].pose;
  for (const auto& [name, m] : assembly.materials)
    materials[name] = FrictionValues{m.staticFriction, m.kineticFriction, m.rotationalFriction};
  overrides.resize(assembly.parts.size());
  for (const auto& [id, f] : assembly.settings.partFriction) overrides[id] = f;
  parts.resize(assembly.parts.size());
  models.resize(assembly.parts.size());
  dirty.assign(assembly.parts.size(), 0);
  slots.resize(assembly.parts.size());
  touched.assign(assembly.parts.size(), 1);
  ownMoves.assign(assembly.parts.size(), 0);
  for (std::size_t i = 0; i < parts.size(); ++i) {
    parts[i].id = i;
    parts[i].pose = assembly.parts[i].pose;
  }
  // A partner part is PLACED exactly at its final pose relative to the base, so its constraint geometry in
  // the base's frame is fixed: the on-base models then treat it as the base's own.
  inBaseFrame = assembly.constraints;
  for (Constraint& c : inBaseFrame) {
    if (!c.partner || !base) continue;
    const Part& partner = assembly.parts[*c.partner];
    const Eigen::Isometry3d T = baseLoad.inverse() * partner.finalPose.value_or(partner.pose);
    c.baseAxis = {T * c.baseAxis.point, T.linear() * c.baseAxis.direction};
    c.basePlane = {T * c.basePlane.point, T.linear() * c.basePlane.normal};
    c.homeDirection = T.linear() * c.homeDirection;
  }
  if (hoistTool) {
    lastInput.hoist.height = hoistTool->height;
    hook = hoistFrame(lastInput.hoist);
  }
}

FrictionValues World::Impl::friction(PartId id) const {
  if (overrides[id]) return *overrides[id];
  const auto it = materials.find(def(id).material);
  if (it != materials.end()) return it->second;
  const Material fallback;
  return {fallback.staticFriction, fallback.kineticFriction, fallback.rotationalFriction};
}

std::string World::Impl::unplacedPartner(PartId id) const {
  for (const Constraint& c : assembly.constraints)
    if (c.part == id && c.partner && parts[*c.partner].state != PartState::Placed) return assembly.parts[*c.partner].name;
  return {};
}

std::string World::Impl::objectName(const std::optional<collision::ObjectId>& o) const {
  if (!o) return "?";
  if (o->kind == collision::ObjectId::Kind::Part) return assembly.parts[o->index].name;
  return assembly.environment[o->index].name;
}

bool World::Impl::fireEvent(PartId id, Event e, interact::Hands hands, const std::string& cause) {
  interact::GuardContext ctx;
  ctx.category = def(id).category.category;
  ctx.hands = hands;
  if (e == Event::ConstraintRecognized || e == Event::ReachedFinalLocation) ctx.unplacedPartner = unplacedPartner(id);
  PartRuntime& p = parts[id];
  touched[id] = 1;
  const interact::Outcome o = interact::fire(p.state, e, ctx);
  if (!o.accepted) {
    refusals.push_back({stepIndex, endOfStep(), id, p.state, e, o.reason});
    return false;
  }
  transitions.push_back({stepIndex, endOfStep(), id, p.state, o.to, e, cause});
  p.state = o.to;
  return true;
}

void World::Impl::setPose(PartId id, const Eigen::Isometry3d& pose) {
  touched[id] = 1;
  if (!(pose.matrix() == parts[id].pose.matrix())) {
    ++moves;
    ++ownMoves[id];
  }
  parts[id].pose = pose;
  if (!dirty[id]) {
    dirty[id] = 1;
    dirtyList.push_back(id);
  }
}

void World::Impl::flush(std::optional<PartId> except) {
  if (dirtyList.empty()) return;
  std::size_t kept = 0;
  for (const PartId d : dirtyList) {
    if (except && d == *except) {
      dirtyList[kept++] = d;
      continue;
    }
    collision.setPose(collision::ObjectId::part(d), parts[d].pose);
    dirty[d] = 0;
  }
  dirtyList.resize(kept);
}

void World::Impl::moveBase(const std::optional<Eigen::Isometry3d>& pose) {
  // A base held still costs nothing: the broad phase's update is O(all objects) in FCL 0.7.
  if (pose && base && !(pose->matrix() == basePose.matrix())) {
    ++moves;
    basePose = *pose;
    parts[*base].pose = basePose;
    touched[*base] = 1;
    collision.setPose(collision::ObjectId::part(*base), basePose);
  }
  // Acceleration of the base's origin from its last three positions (second difference).
  baseTrail[0] = baseTrail[1];
  baseTrail[1] = baseTrail[2];
  baseTrail[2] = basePose.translation();
  baseTrailCount = std::min(baseTrailCount + 1, 3);
  baseAcceleration = baseTrailCount == 3 ? Eigen::Vector3d((baseTrail[2] - 2.0 * baseTrail[1] + baseTrail[0]) / (h() * h()))
                                         : Eigen::Vector3d::Zero();
}

std::string World::Impl::tiltCause(const Eigen::Vector3d& surfaceNormalWorld) const {
  const double tilt = angleOf(basePose.linear() * baseLoad.linear().transpose());
  const double slope = std::acos(std::clamp(surfaceNormalWorld.normalized().z(), -1.0, 1.0));
  return fmt("base tilt=%.4f deg, surface slope=%.4f deg", tilt / kDeg, slope / kDeg);
}

Eigen::Isometry3d World::Impl::inBaseOf(PartId id, double angle, double slide, const Eigen::Vector2d& p) const {
  const PartRuntime& r = parts[id];
  const PartModel& m = models[id];
  if (r.model == Model::Cylindrical && m.hinge) {
    Eigen::Isometry3d pose = m.hinge->partInBase(angle, slide);
    pose.pretranslate(m.play);
    return pose;
  }
  if (r.model == Model::Plane) {
    Eigen::Isometry3d shift = Eigen::Isometry3d::Identity();
    shift.translation() = m.e1b * p.x() + m.e2b * p.y();
    return shift * m.inBase;
  }
  return m.inBase;
}

void World::Impl::step(const Input& in) {
  const double t1 = endOfStep();
  const bool baseMoved = in.base.has_value() && !in.base->isApprox(basePose, 0.0);
  moveBase(in.base);
  hands(in);
  hoist(in.hoist);
  active = 0;
  // Only parts that can move are visited: STATIC parts cost nothing per step. The list is rebuilt
  // (in id order, so the order of work never depends on history) after any transition.
  if (awakeStamp != transitions.size()) {
    awake.clear();
    for (PartId id = 0; id < parts.size(); ++id)
      if (!(base && id == *base) && parts[id].state != PartState::Static) awake.push_back(id);
    awakeStamp = transitions.size();
  }
  for (const PartId id : awake) {
    PartRuntime& r = parts[id];
    PartModel& m = models[id];
    // A part whose model steps may change it; one that only rides the base changes by its pose (setPose).
    if (r.state != PartState::Placed && (r.state != PartState::OnBaseStatic || def(id).category.category == Category::OneHand))
      touched[id] = 1;
    switch (r.state) {
      case PartState::InHand: {
        ++active;
        const HandInput& hand = r.holder == Holder::Right ? in.right : in.left;
        setPose(id, hand.pose * m.offset);
        m.history.push_back({t1, comWorld(id), Eigen::Quaterniond(r.pose.linear())});
        if (m.history.size() > detail::kMaxHistory) m.history.erase(m.history.begin());
        break;
      }
      case PartState::OnTool:
        ++active;
        setPose(id, *hook * m.offset);
        break;
      case PartState::InSpace:
        ++active;
        // Released this step: stepFlight already ran from the release.
        if (!transitions.empty() && transitions.back().part == id && transitions.back().step == stepIndex &&
            transitions.back().to == PartState::InSpace && transitions.back().event == Event::Release)
          break;
        stepFlight(id, t, t1);
        break;
      case PartState::OnBaseSlide:
        ++active;
        stepOnBase(id);
        break;
      case PartState::OnBaseStatic:
        // Only one-hand parts get dynamics (the table's guard): the others just ride on the base.
        if (def(id).category.category != Category::OneHand) {
          if (baseMoved) setPose(id, basePose * currentInBase(id));
          break;
        }
        ++active;
        checkStart(id);
        break;
      case PartState::Placed:
        if (baseMoved) setPose(id, basePose * m.inBase);
        break;
      case PartState::Static:
        break;
    }
  }
  if (base) parts[*base].pose = basePose;
  lastInput = in;
  t = t1;
  ++stepIndex;
}

// ---- live edits ----

std::string World::Impl::apply(const Edit& e) {
  if (std::string problem = validate(e, assembly); !problem.empty()) return problem;
  if (const auto* g = std::get_if<GravityEdit>(&e)) {
    const bool flightChanges = g->scales.freeFlight != settings.gravity.freeFlight;
    settings.gravity = g->scales;
    if (flightChanges)
      for (PartId id = 0; id < parts.size(); ++id)
        if (parts[id].model == Model::Free) rebaseFlight(id);
  } else if (const auto* mf = std::get_if<MaterialFrictionEdit>(&e)) {
    materials[mf->material] = mf->friction;
  } else if (const auto* pf = std::get_if<PartFrictionEdit>(&e)) {
    overrides[pf->part] = pf->friction;
  } else if (const auto* me = std::get_if<MethodEdit>(&e)) {
    settings.rotationMethod = me->rotation;
  } else if (const auto* re = std::get_if<RateEdit>(&e)) {
    rateTime = t;
    rateStep = stepIndex;
    settings.rate = re->rate;
    baseTrailCount = 0;  // the second difference needs three samples one step apart
  }
  // A hinge holds its viscous friction: give it the (possibly new) value of its part.
  for (PartId id = 0; id < parts.size(); ++id)
    if (models[id].hinge) models[id].hinge->setFriction(friction(id).rotationalFriction);
  std::fill(touched.begin(), touched.end(), 1);
  edits.push_back({stepIndex, t, e});
  return {};
}

// A flight's path is a closed form from its release: under a new gravity it restarts now from where the
// part is, as it moves (the rotation keeps its model).
void World::Impl::rebaseFlight(PartId id) {
  PartRuntime& r = parts[id];
  PartModel& m = models[id];
  const Eigen::Quaterniond q(r.pose.linear());
  m.release = dyn::Release{t, comWorld(id), dyn::ballisticVelocity(m.release, m.gFree, t), q,
                           m.torqueFree ? m.torqueFree->omegaWorld() : m.release.omega};
  m.gFree = dyn::worldGravity() * settings.gravity.freeFlight;
  r.velocity = m.release.velocity;
}

// ---- snapshots ----

Snapshot World::Impl::snapshot() {
  if (transitions.size() != sealedTransitions || refusals.size() != sealedRefusals || edits.size() != sealedEdits) {
    auto chunk = std::make_shared<LogChunk>();
    chunk->transitions.assign(transitions.begin() + static_cast<std::ptrdiff_t>(sealedTransitions), transitions.end());
    chunk->refusals.assign(refusals.begin() + static_cast<std::ptrdiff_t>(sealedRefusals), refusals.end());
    chunk->edits.assign(edits.begin() + static_cast<std::ptrdiff_t>(sealedEdits), edits.end());
    chunk->previous = sealed;
    sealed = std::move(chunk);
    sealedTransitions = transitions.size();
    sealedRefusals = refusals.size();
    sealedEdits = edits.size();
  }
  for (PartId id = 0; id < parts.size(); ++id) {
    if (!touched[id] && slots[id]) continue;
    slots[id] = std::make_shared<const PartSlot>(PartSlot{parts[id], models[id]});
    touched[id] = 0;
  }
  auto stored = std::make_shared<Snapshot::Stored>();
  // The state without the parts and models, which the slots hold.
  std::vector<PartRuntime> liveParts = std::move(parts);
  std::vector<PartModel> liveModels = std::move(models);
  parts.clear();
  models.clear();
  stored->state = static_cast<const Snapshot::State&>(*this);
  parts = std::move(liveParts);
  models = std::move(liveModels);
  stored->slots = slots;
  Snapshot s;
  s.stored_ = std::move(stored);
  return s;
}

void World::Impl::restore(const Snapshot& s) {
  if (!s.stored_) throw std::invalid_argument("World::restore: an empty snapshot");
  if (s.stored_->slots.size() != parts.size()) throw std::invalid_argument("World::restore: a snapshot of another scene");
  const std::size_t n = parts.size();
  static_cast<Snapshot::State&>(*this) = s.stored_->state;
  parts.resize(n);
  models.resize(n);
  for (PartId id = 0; id < n; ++id) {
    parts[id] = s.stored_->slots[id]->runtime;
    models[id] = s.stored_->slots[id]->model;
  }
  slots = s.stored_->slots;
  std::fill(touched.begin(), touched.end(), 0);
  std::vector<const LogChunk*> chain;
  for (const LogChunk* c = sealed.get(); c != nullptr; c = c->previous.get()) chain.push_back(c);
  transitions.clear();
  refusals.clear();
  edits.clear();
  for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
    transitions.insert(transitions.end(), (*it)->transitions.begin(), (*it)->transitions.end());
    refusals.insert(refusals.end(), (*it)->refusals.begin(), (*it)->refusals.end());
    edits.insert(edits.end(), (*it)->edits.begin(), (*it)->edits.end());
  }
  // The derived parts: every pose to the collision world, the awake list rebuilt at the next step.
  for (PartId id = 0; id < parts.size(); ++id) collision.setPose(collision::ObjectId::part(id), parts[id].pose);
  std::fill(dirty.begin(), dirty.end(), 0);
  dirtyList.clear();
  awakeStamp = static_cast<std::size_t>(-1);
}

std::uint64_t World::Impl::hash() const {
  std::uint64_t hv = fnv1a(&t, sizeof t);
  for (const PartRuntime& r : parts) {
    const auto st = static_cast<std::uint8_t>(r.state);
    hv = fnv1a(&st, 1, hv);
    hv = fnv1a(r.pose.matrix().data(), sizeof(double) * 16, hv);
    const double c[] = {r.angle, r.omega, r.slide, r.slideRate, r.planeP.x(), r.planeP.y(), r.planeV.x(),
                        r.planeV.y(), r.velocity.x(), r.velocity.y(), r.velocity.z(), r.angularVelocity.x(),
                        r.angularVelocity.y(), r.angularVelocity.z()};
    hv = fnv1a(c, sizeof c, hv);
  }
  return hv;
}

// ---- the public API ----

std::uint64_t Snapshot::step() const { return stored_ ? stored_->state.stepIndex : 0; }
double Snapshot::time() const { return stored_ ? stored_->state.t : 0.0; }

std::size_t Snapshot::bytes(std::unordered_set<const void*>& counted) const {
  if (!stored_) return 0;
  const State& s = stored_->state;
  std::size_t bytes = sizeof(Stored) + stored_->slots.capacity() * sizeof(stored_->slots.front()) +
                      s.overrides.capacity() * sizeof(s.overrides.front()) + s.ownMoves.capacity() * sizeof(std::uint64_t) +
                      s.materials.size() * (sizeof(std::string) + sizeof(FrictionValues) + 64);
  for (const auto& slot : stored_->slots)
    if (counted.insert(slot.get()).second)
      bytes += sizeof(PartSlot) + 16 + slot->model.history.capacity() * sizeof(interact::PoseSample);  // 16: the shared count
  return bytes;
}

World::World(std::shared_ptr<const Scene> scene, Settings settings)
    : impl_(std::make_unique<Impl>(std::move(scene), settings)) {}
World::World(const Assembly& assembly, Settings settings) : World(Scene::build(assembly), settings) {}
World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

void World::step(const Input& input) { impl_->step(input); }
std::string World::apply(const Edit& edit) { return impl_->apply(edit); }
Snapshot World::snapshot() const { return impl_->snapshot(); }
void World::restore(const Snapshot& s) { impl_->restore(s); }
double World::time() const { return impl_->t; }
std::uint64_t World::stepCount() const { return impl_->stepIndex; }
const Settings& World::settings() const { return impl_->settings; }
const Assembly& World::assembly() const { return impl_->assembly; }
const std::shared_ptr<const Scene>& World::scene() const { return impl_->scene; }
FrictionValues World::friction(PartId id) const { return impl_->friction(id); }
std::optional<FrictionValues> World::frictionOverride(PartId id) const { return impl_->overrides.at(id); }
FrictionValues World::materialFriction(const std::string& material) const {
  const auto it = impl_->materials.find(material);
  if (it == impl_->materials.end()) throw std::out_of_range("no material \"" + material + "\"");
  return it->second;
}
const std::vector<PartRuntime>& World::parts() const { return impl_->parts; }
const PartRuntime& World::part(PartId id) const { return impl_->parts.at(id); }
Eigen::Isometry3d World::basePose() const { return impl_->basePose; }
const std::vector<TransitionRecord>& World::transitions() const { return impl_->transitions; }
const std::vector<Refusal>& World::refusals() const { return impl_->refusals; }
const std::vector<EditRecord>& World::edits() const { return impl_->edits; }
const Input& World::lastInput() const { return impl_->lastInput; }
std::optional<Hoist> World::hoist() const { return impl_->hoistTool; }
std::optional<Eigen::Isometry3d> World::hookPose() const { return impl_->hook; }
std::optional<PartId> World::held(int hand) const { return impl_->held[hand == 0 ? 0 : 1]; }
std::optional<PartId> World::onHoist() const { return impl_->onHoist; }
std::optional<interact::Twist> World::releaseVelocity(PartId id) const {
  if (impl_->parts.at(id).state != PartState::InHand) return std::nullopt;
  return interact::releaseVelocity(impl_->models[id].history, impl_->settings.release);
}
std::optional<CaptureHint> World::captureHint(PartId id) const { return impl_->captureHint(id); }
std::optional<dyn::RotationModel> World::flightRotation(PartId id) const {
  if (impl_->parts.at(id).model != Model::Free) return std::nullopt;
  return impl_->models[id].rotation;
}
std::optional<Eigen::Vector3d> World::surfaceBelow(const Eigen::Vector3d& point, double depth,
                                                   std::optional<PartId> except) const {
  impl_->flush();  // the collision world learns the poses it has not needed yet; results do not change
  const auto hit = impl_->collision.castRay(point, -Eigen::Vector3d::UnitZ(), depth,
                                            except ? std::optional(collision::ObjectId::part(*except)) : std::nullopt);
  if (!hit) return std::nullopt;
  return hit->point;
}
std::size_t World::activeParts() const { return impl_->active; }
std::uint64_t World::stateHash() const { return impl_->hash(); }

}  // namespace vaw::sim
