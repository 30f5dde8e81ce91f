#include "vaw/ui/simulation_controller.hpp"

#include <QFile>

#include <algorithm>
#include <cmath>
#include <limits>

#include "vaw/sim/edit.hpp"

namespace vaw::ui {

namespace {

double approach(double value, double target, double maxStep) {
  return value + std::clamp(target - value, -maxStep, maxStep);
}

QString describeRefusal(const vaw::Assembly& a, const vaw::sim::Refusal& r) {
  return QObject::tr("%1: %2 refused (%3): %4")
      .arg(QString::fromStdString(a.parts[r.part].name), QString::fromStdString(std::string(interact::name(r.event))),
           QString::fromStdString(std::string(interact::name(r.state))), QString::fromStdString(r.reason));
}

}  // namespace

SimulationController::SimulationController(QObject* parent) : QObject(parent) {
  timer_.setTimerType(Qt::PreciseTimer);
  timer_.setInterval(4);
  connect(&timer_, &QTimer::timeout, this, &SimulationController::tick);
  clock_.start();
}

SimulationController::~SimulationController() = default;

void SimulationController::start(std::shared_ptr<const vaw::sim::Scene> scene, const QString& sceneReference,
                                 const vaw::sim::Settings& settings) {
  pause();
  commands_.clear();
  playbackSession_.reset();
  playback_ = false;
  recorder_ = std::make_unique<vaw::sim::Recorder>(std::move(scene), settings, sceneReference.toStdString());
  description_ = vaw::view::describe(recorder_->scene().assembly());
  selected_.reset();  // ids of another scene mean nothing here
  resetInputs();
  vaw::view::makeFrame(recorder_->world(), description_, {}, frame_);
  emit started();
  publish();
  emit logChanged();
}

void SimulationController::startPlayback(std::shared_ptr<const vaw::sim::Scene> scene, vaw::sim::Session session) {
  pause();
  commands_.clear();
  auto recorder = std::make_unique<vaw::sim::Recorder>(std::move(scene), session);  // may throw: nothing changed yet
  recorder_ = std::move(recorder);
  playbackSession_ = std::move(session);
  playback_ = true;
  description_ = vaw::view::describe(recorder_->scene().assembly());
  selected_.reset();
  resetInputs();
  vaw::view::makeFrame(recorder_->world(), description_, {}, frame_);
  emit started();
  publish();
  emit logChanged();
}

void SimulationController::resetInputs() {
  hand_ = Eigen::Isometry3d::Identity();
  grabEdges_.clear();
  handClosed_ = bothHands_ = false;
  target_.reset();
  handTurn_.setZero();
  base_ = baseTarget_ = baseRates_ = BaseAngles{};
  accumulator_ = 0.0;
  const vaw::Assembly& a = recorder_->scene().assembly();
  if (a.base) {
    baseLoad_ = a.parts[*a.base].pose;
    const auto drawable = description_.partDrawable[*a.base];
    baseBox_ = drawable ? description_.drawables[*drawable].mesh->bounds : Eigen::AlignedBox3d();
    basePivot_ = drawable ? Eigen::Vector3d(baseLoad_ * baseBox_.center()) : baseLoad_.translation();
    baseLowest_ = std::numeric_limits<double>::infinity();
    for (int c = 0; c < 8 && !baseBox_.isEmpty(); ++c)
      baseLowest_ = std::min(baseLowest_, (baseLoad_ * baseBox_.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c))).z());
  }
  hoistInput_ = vaw::sim::HoistInput{};
  if (const auto h = recorder_->world().hoist()) hoistInput_.height = recorder_->world().hookPose()->translation().z();
  hoistRate_ = hoistYawRate_ = 0.0;
}

// ---- commands from the views ----

void SimulationController::grab(vaw::PartId part, const Eigen::Vector3d& at, bool bothHands) {
  hand_ = Eigen::Isometry3d::Identity();
  hand_.translation() = at;
  target_ = part;
  bothHands_ = bothHands;
  grabEdges_.push_back(true);
}

void SimulationController::moveHand(const Eigen::Vector3d& at) { hand_.translation() = at; }

void SimulationController::release() {
  grabEdges_.push_back(false);
  handTurn_.setZero();
}

void SimulationController::setHandTurn(const Eigen::Vector3d& angularVelocity) { handTurn_ = angularVelocity; }

void SimulationController::setBaseTarget(const BaseAngles& target) { baseTarget_ = target; }
void SimulationController::setBaseRates(const BaseAngles& rates) { baseRates_ = rates; }

void SimulationController::setHoistEngaged(bool engaged) { hoistInput_.engaged = engaged; }
void SimulationController::setHoistHeight(double metres) {
  if (const auto h = hasWorld() ? world().hoist() : std::nullopt) metres = std::clamp(metres, h->lowest, h->highest);
  hoistInput_.height = metres;
}
void SimulationController::setHoistYaw(double radians) { hoistInput_.yaw = radians; }
void SimulationController::setHoistRates(double metresPerSecond, double radiansPerSecond) {
  hoistRate_ = metresPerSecond;
  hoistYawRate_ = radiansPerSecond;
}

void SimulationController::setInputSource(InputSource source) {
  inputSource_ = std::move(source);
  if (!inputSource_ && recorder_) syncInputs();  // the desktop continues from what the source did last
}

void SimulationController::setScript(Script script) {
  const bool ended = script_ && !script;
  script_ = std::move(script);
  if (ended && recorder_) syncInputs();
}

void SimulationController::setExternalPacing(bool on) {
  externalPacing_ = on;
  lastTickNs_ = clock_.nsecsElapsed();
  accumulator_ = 0.0;
  restartRate();
}

void SimulationController::advance(int steps) {
  if (!recorder_ || !isPlaying()) return;
  runSteps(steps);
  if (steps > 0) publish();
  meterRate();
}

void SimulationController::requestEdit(const vaw::sim::Edit& edit) {
  commands_.push_back([this, edit] {
    if (!recorder_) return;
    const std::string problem = vaw::sim::validate(edit, recorder_->scene().assembly());
    if (!problem.empty()) {
      emit editRefused(QString::fromStdString(problem));
      return;
    }
    if (inPast() || playback_) takeOver();
    const std::string refused = recorder_->apply(edit);
    if (refused.empty()) emit editApplied(QString::fromStdString(vaw::sim::describe(edit, recorder_->scene().assembly())));
    else emit editRefused(QString::fromStdString(refused));
    emit logChanged();
  });
  if (!isPlaying()) {
    drainCommands();
    publish();
  }
}

void SimulationController::setSelected(std::optional<vaw::PartId> part) {
  if (part && (!recorder_ || *part >= recorder_->scene().assembly().parts.size())) part.reset();
  if (part == selected_) return;
  selected_ = part;
  if (hasWorld()) publish();
}

// ---- time ----

void SimulationController::play() {
  if (!recorder_ || isPlaying()) return;
  if (playback_ && recorder_->atEnd()) {
    playback_ = false;
    syncInputs();
  }
  lastTickNs_ = clock_.nsecsElapsed();
  accumulator_ = 0.0;
  timer_.start();
  restartRate();
  emit playingChanged(true);
}

void SimulationController::pause() {
  if (!isPlaying()) return;
  timer_.stop();
  restartRate();
  emit playingChanged(false);
}

void SimulationController::restartRate() {
  rateMeter_.reset();
  steppingNs_ = 0;
  ticks_ = cappedOnTime_ = 0;
  if (behind_) {
    behind_ = false;
    emit behindChanged(false);
  }
}

std::optional<std::size_t> SimulationController::availableMemory() {
  QFile info(QStringLiteral("/proc/meminfo"));
  if (!info.open(QIODevice::ReadOnly | QIODevice::Text)) return std::nullopt;
  while (!info.atEnd()) {
    const QByteArray line = info.readLine();
    if (!line.startsWith("MemAvailable:")) continue;
    bool ok = false;
    const qulonglong kb = line.mid(13).trimmed().split(' ').value(0).toULongLong(&ok);
    if (ok) return static_cast<std::size_t>(kb) * 1024;
  }
  return std::nullopt;
}

void SimulationController::setMemoryProbe(MemoryProbe probe, int intervalMs) {
  memoryProbe_ = std::move(probe);
  memoryCheckNs_ = static_cast<qint64>(intervalMs) * 1'000'000;
  lastMemoryCheckNs_ = clock_.nsecsElapsed();
}

void SimulationController::checkMemory() {
  const qint64 now = clock_.nsecsElapsed();
  if (!recorder_ || !memoryProbe_ || now - lastMemoryCheckNs_ < memoryCheckNs_) return;
  lastMemoryCheckNs_ = now;
  const auto available = memoryProbe_();
  if (!available || *available >= kLowMemory) return;
  const std::uint64_t step = recorder_->giveUpOldest(recorder_->memoryBytes() / 2);
  if (step > 0) emit pastGivenUp(recorder_->timeAt(step));
}

void SimulationController::meterRate() {
  if (!recorder_ || !isPlaying()) return;
  checkMemory();
  rateMeter_.sample(static_cast<double>(clock_.nsecsElapsed()) * 1e-9, recorder_->world().time(), static_cast<double>(steppingNs_) * 1e-9);
  steppingNs_ = 0;
  const auto reading = rateMeter_.reading();
  if (!reading) return;
  const bool behind = vaw::sim::fallingBehind(*reading, speed_, behind_);
  if (behind == behind_) return;
  behind_ = behind;
  emit behindChanged(behind_);
}

void SimulationController::togglePlay() { isPlaying() ? pause() : play(); }

void SimulationController::stepOnce() {
  if (!recorder_) return;
  pause();
  stepOnceNow();
  publish();
}

void SimulationController::setSpeed(double speed) {
  speed = std::clamp(speed, kMinSpeed, kMaxSpeed);
  if (speed == speed_) return;
  speed_ = speed;
  restartRate();
  emit speedChanged(speed_);
}

// The menu's steps: 0.1, 0.25, 0.5, 1, 1.5, 2.
void SimulationController::faster() {
  for (double s : {0.25, 0.5, 1.0, 1.5, 2.0})
    if (s > speed_ + 1e-9) return setSpeed(s);
}
void SimulationController::slower() {
  for (double s : {1.5, 1.0, 0.5, 0.25, 0.1})
    if (s < speed_ - 1e-9) return setSpeed(s);
}

void SimulationController::reset() {
  if (!recorder_) return;
  if (playbackSession_) {
    vaw::sim::Session s = *playbackSession_;
    startPlayback(recorder_->scenePtr(), std::move(s));
    return;
  }
  // The scene as loaded, with the tuning as it is now: the settings (gravity, method, rate) carry over and
  // the friction that differs from the scene's own (its materials and its settings block's part overrides,
  // what a new world starts with) is applied again at step 0.
  const vaw::sim::World& w = recorder_->world();
  const auto scene = recorder_->scenePtr();
  const vaw::Assembly& a = scene->assembly();
  std::vector<vaw::sim::Edit> tuning;
  for (const auto& [name, m] : a.materials)
    if (!(w.materialFriction(name) == vaw::FrictionValues{m.staticFriction, m.kineticFriction, m.rotationalFriction}))
      tuning.emplace_back(vaw::sim::MaterialFrictionEdit{name, w.materialFriction(name)});
  for (vaw::PartId id = 0; id < a.parts.size(); ++id) {
    const auto now = w.frictionOverride(id);
    const auto own = a.settings.partFriction.find(id);
    const bool same = own == a.settings.partFriction.end() ? !now : (now && *now == own->second);
    if (!same) tuning.emplace_back(vaw::sim::PartFrictionEdit{id, now});
  }
  const bool wasPlaying = isPlaying();
  start(scene, QString::fromStdString(recorder_->session().scene), w.settings());
  for (const auto& e : tuning) (void)recorder_->apply(e);
  publish();
  emit logChanged();
  if (wasPlaying) play();
}

void SimulationController::seek(std::uint64_t step) {
  if (!recorder_) return;
  pause();
  drainCommands();
  recorder_->seek(step);
  grabEdges_.clear();
  publish();
}

void SimulationController::seekToEnd() {
  if (recorder_) seek(recorder_->length());
}

void SimulationController::tick() {
  const qint64 now = clock_.nsecsElapsed();
  const double wall = static_cast<double>(now - lastTickNs_) * 1e-9;
  lastTickNs_ = now;
  if (externalPacing_) return;
  accumulator_ += wall * speed_;
  const double h = world().settings().step();
  auto n = static_cast<int>(std::floor(accumulator_ / h));
  // A tick on time that still owes more steps than it may run: the rate is more than the timer can step.
  ++ticks_;
  if (n > kMaxCatchUp && wall < 2e-3 * timer_.interval()) ++cappedOnTime_;
  if (ticks_ >= 1000) {  // keep the last few seconds' share
    ticks_ /= 2;
    cappedOnTime_ /= 2;
  }
  if (n > kMaxCatchUp) {
    n = kMaxCatchUp;
    accumulator_ = 0.0;  // a stall: drop the time owed rather than run it all at once
  } else {
    accumulator_ -= n * h;
  }
  runSteps(n);
  if (n > 0) publish();
  meterRate();
}

void SimulationController::runSteps(int n) {
  for (int i = 0; i < n && isPlaying(); ++i) {
    stepOnceNow();
    if (playback_ && recorder_->atEnd()) {
      pause();
      playback_ = false;  // from here on the desktop's hands drive it
      syncInputs();
    }
  }
}

void SimulationController::drainCommands() {
  while (!commands_.empty()) {
    auto command = std::move(commands_.front());
    commands_.pop_front();
    command();
  }
}

void SimulationController::takeOver() {
  bool discarded = false;
  if (!recorder_->atEnd()) {
    const double from = recorder_->world().time();
    recorder_->discardFuture();
    discarded = true;
    emit futureDiscarded(from);
    emit logChanged();
  }
  if (playback_ || discarded) syncInputs();
  playback_ = false;
}

// The desktop's hands, base and hoist continue from what the world last did, so nothing jumps when live
// input takes over from a recording or from a step in the past. A grab the user has just started stays.
void SimulationController::syncInputs() {
  const vaw::sim::Input& last = recorder_->world().lastInput();
  if (grabEdges_.empty()) {
    hand_ = last.right.pose;
    handClosed_ = last.right.grab;
    target_ = last.right.target;
    bothHands_ = last.left.grab && last.right.grab;
  }
  hoistInput_ = last.hoist;
  base_ = baseTarget_ = worldBaseAngles();
}

BaseAngles SimulationController::worldBaseAngles() const {
  // R = Rx(a) Ry(b) Rz(c): b = asin(R02), a = atan2(-R12, R22), c = atan2(-R01, R00).
  const Eigen::Matrix3d r = recorder_->world().basePose().linear() * baseLoad_.linear().transpose();
  return {std::atan2(-r(1, 2), r(2, 2)), std::asin(std::clamp(r(0, 2), -1.0, 1.0)), std::atan2(-r(0, 1), r(0, 0))};
}

Eigen::Isometry3d SimulationController::basePose(const BaseAngles& a) const {
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(a.tiltX, Eigen::Vector3d::UnitX()) *
                             Eigen::AngleAxisd(a.tiltY, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(a.turn, Eigen::Vector3d::UnitZ()))
                                .toRotationMatrix();
  Eigen::Isometry3d about = Eigen::Isometry3d::Identity();
  about.linear() = r;
  about.translation() = basePivot_ - r * basePivot_;
  Eigen::Isometry3d pose = about * baseLoad_;
  // The left hand lifts the base as it tilts it, so that no corner goes lower than the base's lowest point
  // at load: a hand-held base is not pushed into the table.
  if (!baseBox_.isEmpty()) {
    double lowest = std::numeric_limits<double>::infinity();
    for (int c = 0; c < 8; ++c)
      lowest = std::min(lowest, (pose * baseBox_.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c))).z());
    pose.pretranslate(Eigen::Vector3d(0.0, 0.0, std::max(0.0, baseLowest_ - lowest)));
  }
  return pose;
}

vaw::sim::Input SimulationController::nextInput() {
  const double h = world().settings().step();
  vaw::sim::Input in;
  if (!grabEdges_.empty()) {
    handClosed_ = grabEdges_.front();
    grabEdges_.pop_front();
  }
  if (const double rate = handTurn_.norm(); rate > 0.0)
    hand_.linear() = Eigen::AngleAxisd(rate * h, handTurn_ / rate).toRotationMatrix() * hand_.linear();
  in.right = {hand_, handClosed_, target_};
  in.left = bothHands_ ? in.right : vaw::sim::HandInput{hand_, false, std::nullopt};
  // The base: the keys move its target, the base follows at a bounded rate.
  baseTarget_.tiltX += baseRates_.tiltX * h;
  baseTarget_.tiltY += baseRates_.tiltY * h;
  baseTarget_.turn += baseRates_.turn * h;
  const BaseAngles before = base_;
  const double maxStep = std::max({kBaseRate, std::abs(baseRates_.tiltX), std::abs(baseRates_.tiltY),
                                   std::abs(baseRates_.turn)}) * h;
  base_.tiltX = approach(base_.tiltX, baseTarget_.tiltX, maxStep);
  base_.tiltY = approach(base_.tiltY, baseTarget_.tiltY, maxStep);
  base_.turn = approach(base_.turn, baseTarget_.turn, maxStep);
  if (!(base_ == before)) in.base = basePose(base_);
  if (hoistRate_ != 0.0) setHoistHeight(hoistInput_.height + hoistRate_ * h);
  hoistInput_.yaw += hoistYawRate_ * h;
  in.hoist = hoistInput_;
  return in;
}

void SimulationController::stepOnceNow() {
  drainCommands();
  const std::size_t transitions = recorder_->transitions().size(), refusals = recorder_->refusals().size();
  QElapsedTimer cost;
  if (playback_ && !recorder_->atEnd()) {
    cost.start();
    recorder_->playNext();
  } else {
    if (inPast() || playback_) takeOver();
    const double end = recorder_->timeAt(recorder_->step() + 1);
    vaw::sim::Input in = inputSource_ ? inputSource_(end) : nextInput();
    if (script_) script_(end, in);
    cost.start();
    recorder_->record(in);
  }
  lastStepNs_ = cost.nsecsElapsed();
  steppingNs_ += lastStepNs_;
  reportNews(transitions, refusals);
}

void SimulationController::reportNews(std::size_t transitionsBefore, std::size_t refusalsBefore) {
  const auto& refusals = recorder_->refusals();
  if (refusals.size() > refusalsBefore && !playback_)
    for (std::size_t i = refusalsBefore; i < refusals.size(); ++i)
      emit refused(describeRefusal(recorder_->scene().assembly(), refusals[i]));
  if (recorder_->transitions().size() != transitionsBefore || refusals.size() != refusalsBefore) emit logChanged();
}

void SimulationController::publish() {
  vaw::view::FrameOptions options;
  options.selected = selected_;
  vaw::view::makeFrame(recorder_->world(), description_, options, frame_);
  emit frameReady();
}

}  // namespace vaw::ui
