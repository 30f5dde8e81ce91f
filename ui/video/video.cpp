#include "vaw/video/video.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>

#include <QtGui/QFont>
#include <QtGui/QFontMetrics>
#include <QtGui/QGuiApplication>
#include <QtGui/QImage>
#include <QtGui/QPainter>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <deque>
#include <numbers>
#include <utility>
#include <vector>

#include "vaw/error.hpp"
#include "vaw/evaluation/way_clearance.hpp"
#include "vaw/gl/gl_renderer.hpp"
#include "vaw/gl/headless_gl.hpp"
#include "vaw/report/gltf.hpp"
#include "vaw/sim/carried_path.hpp"
#include "vaw/sim/world.hpp"
#include "vaw/video/mp4_writer.hpp"
#include "vaw/view/frame.hpp"

namespace vaw::video {

namespace {

// The window's Home view (ui/src/viewport.cpp) and its lens: the video looks as the viewport does.
const Eigen::Vector3d kHomeDirection = Eigen::Vector3d(0.75, -1.5, 0.95).normalized();
constexpr double kHalfFov = 0.5 * 35.0 * std::numbers::pi / 180.0;  // vertical
constexpr double kSettle = 0.3;  // s of recording: the camera's time constant when it moves to a new aim
constexpr double kEventShown = 2.5;  // s of recording a state change stays in the caption
constexpr std::size_t kEventLines = 3;

// Numbers in the caption as in every file vaw writes: with a point, whatever the locale Qt applied.
std::string fixed(double v, int digits) {
  char b[48];
  const auto r = std::to_chars(b, b + sizeof b, v, std::chars_format::fixed, digits);
  return std::string(b, r.ptr);
}

// QPainter needs a QGuiApplication for its fonts; vaw-sim has none, so one is made for the call on the
// offscreen platform, as vaw-sim's charts do.
class PaintingApp {
 public:
  PaintingApp() {
    if (QCoreApplication::instance() != nullptr) return;
    if (qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "offscreen");
    app_ = std::make_unique<QGuiApplication>(argc_, argv_);
  }

 private:
  int argc_ = 1;
  char name_[8] = "vaw-sim";
  char* argv_[2] = {name_, nullptr};
  std::unique_ptr<QGuiApplication> app_;
};

Eigen::AlignedBox3d worldBox(const Eigen::AlignedBox3d& local, const Eigen::Isometry3d& pose) {
  Eigen::AlignedBox3d box;
  for (int k = 0; k < 8; ++k) box.extend(pose * local.corner(static_cast<Eigen::AlignedBox3d::CornerType>(k)));
  return box;
}

// How far back a camera stands to hold a ball of `radius` in the picture (the viewport's rule).
double framing(double radius, double aspect) {
  const double halfH = std::atan(std::tan(kHalfFov) * aspect);
  return std::max(radius, 1e-3) / std::sin(std::min(kHalfFov, halfH)) * 1.02;
}

xr::EyeView eyeAt(const Eigen::Vector3d& centre, const Eigen::Vector3d& direction, double distance, double aspect) {
  Eigen::Vector3d back = direction.normalized();
  if (std::abs(back.z()) > 0.999) back = Eigen::Vector3d(0.0, -0.05, back.z() > 0 ? 1.0 : -1.0).normalized();
  const Eigen::Vector3d right = Eigen::Vector3d::UnitZ().cross(back).normalized();
  xr::EyeView eye;
  eye.pose.linear().col(0) = right;
  eye.pose.linear().col(1) = back.cross(right);
  eye.pose.linear().col(2) = back;  // the eye looks along its -z
  eye.pose.translation() = centre + distance * back;
  const double halfH = std::atan(std::tan(kHalfFov) * aspect);
  eye.angleLeft = -halfH;
  eye.angleRight = halfH;
  eye.angleUp = kHalfFov;
  eye.angleDown = -kHalfFov;
  return eye;
}

// Where the camera looks, frame by frame (Camera's kinds), moving smoothly to each new aim.
class CameraMan {
 public:
  CameraMan(const Camera& camera, const Assembly& a, const view::SceneDescription& scene, const Eigen::AlignedBox3d& box,
            double aspect, const std::string& file)
      : kind_(camera.kind), scene_(scene), aspect_(aspect), direction_(kHomeDirection), home_(box.center()),
        distance_(framing(0.5 * box.diagonal().norm(), aspect)) {
    if (kind_ == Camera::Kind::Follow) {
      part_ = a.findPart(camera.part);
      if (!part_ || !scene.partDrawable[*part_]) fail(file, "camera", "follow and the name of a part of the scene", "\"" + camera.part + "\"");
      const view::Drawable& d = scene.drawables[*scene.partDrawable[*part_]];
      local_ = d.mesh->bounds.center();
      distance_ = framing(std::max(2.5 * d.mesh->bounds.diagonal().norm(), 0.08), aspect);
    } else if (kind_ == Camera::Kind::View) {
      const std::string& v = camera.view;
      direction_ = v == "iso" ? kHomeDirection
                   : v == "front" ? Eigen::Vector3d(0, -1, 0.25)
                   : v == "back" ? Eigen::Vector3d(0, 1, 0.25)
                   : v == "left" ? Eigen::Vector3d(-1, 0, 0.25)
                   : v == "right" ? Eigen::Vector3d(1, 0, 0.25)
                   : v == "top" ? Eigen::Vector3d(0, 0, 1)
                                : Eigen::Vector3d::Zero();
      if (direction_.isZero()) fail(file, "camera", kCameraChoices, "\"" + v + "\"");
    } else if (kind_ == Camera::Kind::Eye) {
      const Eigen::Vector3d back = camera.position - camera.target;
      const bool finite = camera.position.allFinite() && camera.target.allFinite() && camera.up.allFinite() && std::isfinite(camera.verticalFovDeg);
      if (!finite || back.norm() < 1e-9 || camera.up.cross(back).norm() < 1e-9 * back.norm() * camera.up.norm() ||
          camera.verticalFovDeg <= 0.0 || camera.verticalFovDeg >= 180.0)
        fail(file, "camera", "an eye apart from what it looks at, an up across its view and a field of view between 0 and 180 degrees",
             "an eye at (" + fixed(camera.position.x(), 3) + ", " + fixed(camera.position.y(), 3) + ", " + fixed(camera.position.z(), 3) + ") m, field of view " +
                 fixed(camera.verticalFovDeg, 1) + " degrees");
      const Eigen::Vector3d z = back.normalized(), x = camera.up.cross(z).normalized();
      eye_.pose.linear().col(0) = x;
      eye_.pose.linear().col(1) = z.cross(x);
      eye_.pose.linear().col(2) = z;  // the eye looks along its -z
      eye_.pose.translation() = camera.position;
      const double halfV = 0.5 * camera.verticalFovDeg * std::numbers::pi / 180.0, halfH = std::atan(std::tan(halfV) * aspect);
      eye_.angleLeft = -halfH;
      eye_.angleRight = halfH;
      eye_.angleUp = halfV;
      eye_.angleDown = -halfV;
    }
  }

  // The eye for `frame`, `dt` seconds of recording after the last one (0: the first, no easing in). Auto
  // and a view frame every part drawn where it is now, as the window's F does, and hold still while that
  // stays in the picture and fills most of it, as a camera operator would: a still picture is easier to
  // watch and is drawn for the cost of what moves (GlRenderer's still layer). When the work leaves the
  // picture or shrinks in it, the camera moves smoothly to frame it again with a tenth to spare. Follow
  // keeps its part in the middle all the time.
  xr::EyeView aim(const view::Frame& frame, double dt) {
    if (kind_ == Camera::Kind::Eye) return eye_;
    if (kind_ == Camera::Kind::Follow) {
      ease(frame.parts[*part_].pose * local_, distance_, dt);
      return eyeAt(*centre_, direction_, distanceNow_, aspect_);
    }
    Eigen::AlignedBox3d box;
    for (PartId p = 0; p < frame.parts.size() && p < scene_.partDrawable.size(); ++p)
      if (frame.parts[p].shown && scene_.partDrawable[p]) box.extend(worldBox(scene_.drawables[*scene_.partDrawable[p]].mesh->bounds, frame.parts[p].pose));
    const Eigen::Vector3d wanted = box.isEmpty() ? home_ : Eigen::Vector3d(box.center());
    const double radius = box.isEmpty() ? radiusOf(distance_) : std::max(0.5 * box.diagonal().norm(), 1e-3);
    if (!centre_) {
      centre_ = wanted;
      distanceNow_ = framing(kSpare * radius, aspect_);
      return eyeAt(*centre_, direction_, distanceNow_, aspect_);
    }
    const double held = radiusOf(distanceNow_), reach = (wanted - *centre_).norm() + radius;
    if (!moving_ && (reach > held || reach < kShrunk * held)) moving_ = true;
    if (moving_) {
      const double distance = framing(kSpare * radius, aspect_);
      ease(wanted, distance, dt);
      // Close enough that the rest would not show: there, and still.
      if ((wanted - *centre_).norm() < 1e-4 * distanceNow_ && std::abs(distance - distanceNow_) < 1e-4 * distanceNow_) {
        centre_ = wanted;
        distanceNow_ = distance;
        moving_ = false;
      }
    }
    return eyeAt(*centre_, direction_, distanceNow_, aspect_);
  }

 private:
  Camera::Kind kind_;
  const view::SceneDescription& scene_;
  double aspect_;
  Eigen::Vector3d direction_, home_, local_ = Eigen::Vector3d::Zero();
  double distance_;
  std::optional<PartId> part_;
  std::optional<Eigen::Vector3d> centre_;
  double distanceNow_ = 0.0;
  bool moving_ = false;
  xr::EyeView eye_;  // Eye's, fixed
  static constexpr double kSpare = 1.1;    // the work framed with a tenth of its size to spare
  static constexpr double kShrunk = 0.6;   // held until the work fills less than this of the picture

  // The ball a camera `distance` back holds (framing's inverse).
  [[nodiscard]] double radiusOf(double distance) const { return distance / framing(1.0, aspect_); }
  void ease(const Eigen::Vector3d& wanted, double distance, double dt) {
    const double k = dt > 0.0 && centre_ ? 1.0 - std::exp(-dt / kSettle) : 1.0;
    centre_ = centre_ ? *centre_ + (wanted - *centre_) * k : wanted;
    distanceNow_ += (distance - distanceNow_) * k;
  }
};

// Draws frames in a context of its own and reads them back as pictures, top row first.
class Shooter {
 public:
  Shooter(const view::SceneDescription& scene, int width, int height) : width_(width), height_(height) {
    renderer_ = std::make_unique<xr::GlRenderer>();
    renderer_->setScene(scene);
    renderer_->keepStillLayer(true);
    glGenTextures(1, &texture_);
    glBindTexture(GL_TEXTURE_2D, texture_);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glGenFramebuffers(1, &read_);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, read_);
    glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture_, 0);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    name_ = std::string(reinterpret_cast<const char*>(glGetString(GL_RENDERER))) + ", EGL " + gl_.platform();
  }
  ~Shooter() {
    glDeleteFramebuffers(1, &read_);
    glDeleteTextures(1, &texture_);
    renderer_.reset();  // its buffers go while the context is there
  }
  Shooter(const Shooter&) = delete;
  Shooter& operator=(const Shooter&) = delete;

  QImage shoot(const view::Frame& frame, const xr::EyeView& eye) {
    renderer_->render(texture_, width_, height_, eye, &frame, xr::HandsSample{});
    glBindFramebuffer(GL_READ_FRAMEBUFFER, read_);
    QImage image(width_, height_, QImage::Format_RGBA8888);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, image.bits());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    if (glGetError() != GL_NO_ERROR) throw std::runtime_error("OpenGL failed while drawing a frame of the video");
    return image.mirrored(false, true);  // OpenGL's rows run bottom up
  }
  [[nodiscard]] const std::string& name() const { return name_; }
  void show(std::shared_ptr<const view::MeshBuffer> volume, std::vector<xr::GlRenderer::Line> lines) {
    renderer_->setOverlay(std::move(volume), view::kSweptColor, view::kSweptAlpha);
    renderer_->setLines(std::move(lines));
  }

 private:
  gl::HeadlessGl gl_;  // first: the renderer needs the context current
  int width_, height_;
  std::unique_ptr<xr::GlRenderer> renderer_;
  GLuint texture_ = 0, read_ = 0;
  std::string name_;
};

// The caption band along the bottom: the state changes of the last seconds above the line of time, what is
// in hand and the scene's name.
void caption(QImage& image, const std::string& left, const std::string& right, const std::deque<std::pair<double, std::string>>& events) {
  QPainter p(&image);
  p.setRenderHint(QPainter::TextAntialiasing);
  QFont font;
  font.setPixelSize(std::max(9, image.height() / 34));
  p.setFont(font);
  const int line = QFontMetrics(font).height(), pad = std::max(3, line / 3);
  const int rows = 1 + static_cast<int>(events.size());
  const QRect band(0, image.height() - rows * line - 2 * pad, image.width(), rows * line + 2 * pad);
  p.fillRect(band, QColor(0, 0, 0, 160));
  int y = band.top() + pad;
  p.setPen(QColor(255, 196, 110));
  for (const auto& e : events) {
    p.drawText(QRect(pad, y, image.width() - 2 * pad, line), Qt::AlignLeft | Qt::AlignVCenter, QString::fromStdString(e.second));
    y += line;
  }
  p.setPen(Qt::white);
  const QRect last(pad, y, image.width() - 2 * pad, line);
  p.drawText(last, Qt::AlignRight | Qt::AlignVCenter, QString::fromStdString(right));
  p.drawText(last, Qt::AlignLeft | Qt::AlignVCenter, QString::fromStdString(left));
}

std::string inHand(const Assembly& a, const view::Frame& f) {
  const auto& l = f.hands[0].holding;
  const auto& r = f.hands[1].holding;
  if (l && r && *l == *r) return "both hands: " + a.parts[*l].name;
  std::string s;
  if (l) s = "left hand: " + a.parts[*l].name;
  if (r) s += (s.empty() ? "" : ", ") + std::string("right hand: ") + a.parts[*r].name;
  for (const view::HoistFrame& h : f.hoists)
    if (h.load) s += (s.empty() ? "" : ", ") + std::string("hoist: ") + a.parts[*h.load].name;
  return s.empty() ? "nothing in hand" : s;
}

void checkSize(const VideoOptions& o, const std::string& file) {
  if (o.width < 16 || o.height < 16 || o.width % 2 != 0 || o.height % 2 != 0 || o.width > 7680 || o.height > 4320)
    fail(file, "size", "an even width and height from 16 x 16 to 7680 x 4320 pixels", std::to_string(o.width) + " x " + std::to_string(o.height));
  if (o.fps < 1 || o.fps > 240) fail(file, "fps", "1 to 240 frames a second", std::to_string(o.fps));
  if (!(o.speed > 0.0) || !std::isfinite(o.speed) || o.speed > 1000.0) fail(file, "speed", "a positive factor up to 1000", fixed(o.speed, 3));
}

// The span [from, to] of a recording or order that lasts `end` seconds.
std::pair<double, double> span(const VideoOptions& o, double end, const std::string& file) {
  const double from = o.from.value_or(0.0), to = std::min(o.to.value_or(end), end);
  if (!(from >= 0.0) || !(from < end) || !(to > from))
    fail(file, "from/to", "a span within 0 to " + fixed(end, 2) + " s", fixed(from, 2) + " to " + fixed(o.to.value_or(end), 2) + " s");
  return {from, to};
}

struct Enough {};  // thrown out of a replay once the last frame wanted is made

// Every frame of the session's video, in order, to `take(index, picture)` (false: no more wanted).
template <class Take>
std::string playSession(const std::shared_ptr<const sim::Scene>& scene, const sim::Session& session, const VideoOptions& o, Take take,
                        const ProgressFn& progress) {
  const std::string file = sim::sessionName(session);
  checkSize(o, file);
  const Assembly& a = scene->assembly();
  const double end = static_cast<double>(session.inputs.size()) * session.settings.step();
  const auto [from, to] = span(o, end, file);
  const double dt = o.speed / o.fps;  // s of recording a frame
  const view::SceneDescription described = view::describe(a);
  PaintingApp app;
  Shooter shooter(described, o.width, o.height);
  CameraMan camera(o.camera, a, described, described.partsBounds, static_cast<double>(o.width) / o.height, file);
  view::Frame frame;
  std::deque<std::pair<double, std::string>> events;
  std::size_t seen = 0;
  std::int64_t k = 0;
  const auto frames = static_cast<std::int64_t>(std::floor((to - from) / dt + 1e-9)) + 1;
  try {
    (void)sim::replay(scene, session, [&](const sim::World& w) {
      const auto& log = w.transitions();
      for (; seen < log.size(); ++seen) {
        const sim::TransitionRecord& r = log[seen];
        events.emplace_back(r.t, a.parts[r.part].name + " " + std::string(interact::name(r.to)) + (r.cause.empty() ? "" : " (" + r.cause + ")"));
      }
      // A frame shows the world at the first step that reaches its time.
      for (double t = from + static_cast<double>(k) * dt; k < frames && t <= w.time() + 1e-9; t = from + static_cast<double>(++k) * dt) {
        view::makeFrame(w, described, {}, frame);
        while (!events.empty() && (events.front().first < t - kEventShown || events.size() > kEventLines)) events.pop_front();
        std::deque<std::pair<double, std::string>> shown;
        for (const auto& e : events)
          if (e.first >= from - 1e-9) shown.push_back(e);
        QImage picture = shooter.shoot(frame, camera.aim(frame, k == 0 ? 0.0 : dt));
        caption(picture, fixed(t, 1) + " s   " + inHand(a, frame), a.name, shown);
        if (!take(k, picture)) throw Enough{};
        if (progress && !progress(static_cast<double>(k + 1) / static_cast<double>(frames), "frame " + std::to_string(k + 1) + " of " + std::to_string(frames)))
          throw LoadCancelled();
      }
      if (k >= frames) throw Enough{};
    });
  } catch (const Enough&) {
  }
  return shooter.name();
}

// A track's pose at `t`: between its keys, the position straight and the turn the shortest way.
Eigen::Isometry3d poseAt(const report::Track& track, double t) {
  if (track.times.empty()) return Eigen::Isometry3d::Identity();
  if (t <= track.times.front()) return track.poses.front();
  if (t >= track.times.back()) return track.poses.back();
  const std::size_t i = static_cast<std::size_t>(std::upper_bound(track.times.begin(), track.times.end(), t) - track.times.begin()) - 1;
  const double s = (t - track.times[i]) / (track.times[i + 1] - track.times[i]);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::Quaterniond(track.poses[i].linear()).slerp(s, Eigen::Quaterniond(track.poses[i + 1].linear())).toRotationMatrix();
  pose.translation() = (1.0 - s) * track.poses[i].translation() + s * track.poses[i + 1].translation();
  return pose;
}

}  // namespace

std::optional<Camera> parseCamera(const std::string& text) {
  Camera c;
  if (text == "auto") return c;
  if (text.rfind("follow ", 0) == 0 && text.size() > 7) {
    c.kind = Camera::Kind::Follow;
    c.part = text.substr(7);
    return c;
  }
  for (const char* v : {"iso", "front", "back", "left", "right", "top"})
    if (text == v) {
      c.kind = Camera::Kind::View;
      c.view = text;
      return c;
    }
  return std::nullopt;
}

VideoResult writeSessionVideo(const std::shared_ptr<const sim::Scene>& scene, const sim::Session& session, const std::filesystem::path& file,
                              const VideoOptions& options, const ProgressFn& progress) {
  checkSize(options, file.string());
  Mp4Writer writer(file, options.width, options.height, options.fps);
  VideoResult result;
  result.gl = playSession(scene, session, options, [&](std::int64_t, const QImage& picture) {
    writer.add(picture.constBits(), static_cast<int>(picture.bytesPerLine()));
    return true;
  }, progress);
  writer.finish();
  result.frames = writer.frames();
  result.seconds = static_cast<double>(result.frames) / options.fps;
  result.encoder = writer.encoder();
  return result;
}

QImage sessionPicture(const std::shared_ptr<const sim::Scene>& scene, const sim::Session& session, const VideoOptions& options,
                      std::int64_t index) {
  QImage found;
  (void)playSession(scene, session, options, [&](std::int64_t k, const QImage& picture) {
    if (k < index) return true;
    found = picture;
    return false;
  }, {});
  return found;
}

VideoResult writeOrderVideo(const std::shared_ptr<const sim::Scene>& scene, const eval::SequencePlan& plan, const std::filesystem::path& file,
                            const VideoOptions& options, const ProgressFn& progress) {
  const std::string name = file.string();
  checkSize(options, name);
  if (!(options.stepSeconds > 0.0) || !std::isfinite(options.stepSeconds) || options.stepSeconds > 600.0)
    fail(name, "step-seconds", "a positive time up to 600 s", fixed(options.stepSeconds, 3));
  if (!(options.sweepVoxel >= 0.0) || !std::isfinite(options.sweepVoxel) || (options.sweepVoxel > 0.0 && options.sweepVoxel < 1e-4))
    fail(name, "sweeps", "a voxel edge of 0.1 mm or more (or none)", fixed(options.sweepVoxel * 1e3, 3) + " mm");
  const Assembly& a = scene->assembly();
  const report::Motion motion = report::orderMotion(a, plan, options.stepSeconds, options.fps / options.speed);
  // Each way's swept volume and nearest pass, by part, before the first frame.
  std::vector<std::optional<eval::WayClearance>> ways(a.parts.size());
  if (options.sweepVoxel > 0.0) {
    eval::WayClearanceOptions wo;
    wo.voxel = options.sweepVoxel;
    const ProgressFn told = progress ? ProgressFn([&](double f, const std::string& what) { return progress(0.0, "swept volumes: " + what + " (" + fixed(100.0 * f, 0) + " %)"); })
                                     : ProgressFn{};
    for (eval::WayClearance& w : eval::wayClearances(a, plan, wo, told)) ways[w.part] = std::move(w);
  }
  const auto [from, to] = span(options, motion.duration + 1e-9, name);
  const double dt = options.speed / options.fps;
  const view::SceneDescription described = view::describe(a);
  // Framed on the assembly as built, which is where everything ends.
  Eigen::AlignedBox3d built;
  for (PartId p = 0; p < a.parts.size(); ++p)
    if (described.partDrawable[p]) built.extend(worldBox(described.drawables[*described.partDrawable[p]].mesh->bounds, motion.parts[p].poses.back()));
  if (built.isEmpty()) built = described.partsBounds;
  Mp4Writer writer(file, options.width, options.height, options.fps);
  PaintingApp app;
  Shooter shooter(described, options.width, options.height);
  CameraMan camera(options.camera, a, described, built, static_cast<double>(options.width) / options.height, name);
  const auto frames = static_cast<std::int64_t>(std::floor((to - from) / dt + 1e-9)) + 1;
  view::Frame frame;
  frame.parts.resize(a.parts.size());
  std::optional<PartId> sweptShown;
  std::int64_t sweeps = 0;
  for (std::int64_t k = 0; k < frames; ++k) {
    const double t = from + static_cast<double>(k) * dt;
    // The step at hand: the part in the order that came in last (none before the first).
    std::size_t at = plan.order.size();
    for (std::size_t i = 0; i < plan.order.size(); ++i) {
      const auto& shown = motion.parts[plan.order[i]].shown;
      if (!shown || *shown <= t + 1e-9) at = i;
    }
    const bool any = at < plan.order.size();
    const PartId current = any ? plan.order[at] : 0;
    const bool isBase = any && plan.base && current == *plan.base;
    for (PartId p = 0; p < a.parts.size(); ++p) {
      view::PartFrame& f = frame.parts[p];
      const report::Track& track = motion.parts[p];
      f.pose = poseAt(track, t);
      f.shown = !track.shown || *track.shown <= t + 1e-9;
      f.selected = any && !isBase && current == p;
      const view::Rgb own = described.partDrawable[p] ? described.drawables[*described.partDrawable[p]].color : view::Rgb{};
      f.color = view::displayColor(own, interact::PartState::Static, f.selected);
    }
    std::string left = fixed(t, 1) + " s";
    if (any) {
      const auto* way = plan.wayOf(current);
      left += "   step " + std::to_string(plan.step[at]) + " of " + std::to_string(plan.step.back()) + ": " + a.parts[current].name +
              (isBase ? std::string(" (the base)") : way ? ", " + eval::travelText(way->out) : std::string());
      const std::optional<eval::WayClearance>& swept = ways[current];
      if (swept && !isBase) {
        if (const eval::WayObject* near = swept->nearest())
          left += ", nearest " + a.parts[near->part].name + " " + fixed(near->least * 1e3, 1) + " mm";
      }
    }
    // The step's way: its volume and its nearest pass, from the step's first frame to the next step's.
    const std::optional<PartId> wanted = any && !isBase && ways[current] ? std::optional<PartId>(current) : std::nullopt;
    if (wanted != sweptShown) {
      std::shared_ptr<const view::MeshBuffer> volume;
      std::vector<xr::GlRenderer::Line> lines;
      if (wanted) {
        const eval::WayClearance& w = *ways[*wanted];
        if (w.swept) volume = view::flatShaded(w.swept->surface());
        if (const eval::WayObject* near = w.nearest()) lines.push_back({near->onPart, near->onOther, 0.0015, view::kHighlight});
        ++sweeps;
      }
      shooter.show(std::move(volume), std::move(lines));
      sweptShown = wanted;
    }
    QImage picture = shooter.shoot(frame, camera.aim(frame, k == 0 ? 0.0 : dt));
    caption(picture, left, a.name, {});
    writer.add(picture.constBits(), static_cast<int>(picture.bytesPerLine()));
    if (progress && !progress(static_cast<double>(k + 1) / static_cast<double>(frames), "frame " + std::to_string(k + 1) + " of " + std::to_string(frames)))
      throw LoadCancelled();
  }
  writer.finish();
  return {writer.frames(), static_cast<double>(writer.frames()) / options.fps, writer.encoder(), shooter.name(), sweeps};
}

}  // namespace vaw::video
