#include "vaw/gl/gl_renderer.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace vaw::xr {

namespace {

// The desktop viewport's background, so that both views look alike.
constexpr float kClear[3] = {52.0f / 255.0f, 58.0f / 255.0f, 68.0f / 255.0f};
constexpr view::Rgb kSkin{0.91f, 0.75f, 0.62f};
constexpr view::Rgb kController{0.35f, 0.37f, 0.40f};
constexpr view::Rgb kLine{0.85f, 0.85f, 0.80f};
constexpr view::Rgb kCable{0.25f, 0.25f, 0.27f};
constexpr float kNear = 0.02f, kFar = 50.0f;  // m

const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 model;
uniform mat4 viewProj;
out vec3 worldNormal;
void main() {
  worldNormal = mat3(model) * normal;
  gl_Position = viewProj * model * vec4(position, 1.0);
}
)";

// Two lights fixed to the world (a key from above and in front, a fill from the other side) and ambient:
// faces keep their shading as the head moves. Both sides of a face are lit, as meshes from CAD are not
// always consistently wound. Colours are written as they come (sRGB values, like the desktop's).
const char* kFragmentShader = R"(#version 330 core
in vec3 worldNormal;
uniform vec3 color;
uniform bool lit;
uniform float alpha;
out vec4 fragColor;
void main() {
  if (!lit) { fragColor = vec4(color, alpha); return; }
  vec3 n = normalize(worldNormal);
  float key = abs(dot(n, normalize(vec3(0.35, -0.6, 0.75))));
  float fill = abs(dot(n, normalize(vec3(-0.5, 0.4, 0.3))));
  fragColor = vec4(color * (0.30 + 0.60 * key + 0.20 * fill), alpha);
}
)";

std::uint32_t compile(GLenum type, const char* source) {
  const GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (ok == 0) {
    char log[1024] = {};
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    glDeleteShader(s);
    throw std::runtime_error(std::string("headset renderer: shader does not compile: ") + log);
  }
  return s;
}

void pushVertex(std::vector<float>& v, const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
  v.insert(v.end(), {p.x(), p.y(), p.z(), n.x(), n.y(), n.z()});
}

// A unit sphere: an octahedron subdivided twice (128 triangles), normals along the radius.
std::vector<float> sphereVertices() {
  std::vector<std::array<Eigen::Vector3f, 3>> tris;
  const Eigen::Vector3f px(1, 0, 0), nx(-1, 0, 0), py(0, 1, 0), ny(0, -1, 0), pz(0, 0, 1), nz(0, 0, -1);
  tris = {{px, py, pz}, {py, nx, pz}, {nx, ny, pz}, {ny, px, pz}, {py, px, nz}, {nx, py, nz}, {ny, nx, nz}, {px, ny, nz}};
  for (int level = 0; level < 2; ++level) {
    std::vector<std::array<Eigen::Vector3f, 3>> next;
    for (const auto& t : tris) {
      const Eigen::Vector3f a = (t[0] + t[1]).normalized(), b = (t[1] + t[2]).normalized(), c = (t[2] + t[0]).normalized();
      next.push_back({t[0], a, c});
      next.push_back({a, t[1], b});
      next.push_back({c, b, t[2]});
      next.push_back({a, b, c});
    }
    tris = std::move(next);
  }
  std::vector<float> v;
  for (const auto& t : tris)
    for (const auto& p : t) pushVertex(v, p, p);
  return v;
}

// A cube from -0.5 to 0.5, flat normals.
std::vector<float> cubeVertices() {
  std::vector<float> v;
  for (int axis = 0; axis < 3; ++axis) {
    for (float side : {-1.0f, 1.0f}) {
      Eigen::Vector3f n = Eigen::Vector3f::Zero();
      n[axis] = side;
      const Eigen::Vector3f u = Eigen::Vector3f::Unit((axis + 1) % 3) * 0.5f, w = Eigen::Vector3f::Unit((axis + 2) % 3) * 0.5f;
      const Eigen::Vector3f c = n * 0.5f;
      const Eigen::Vector3f q[4] = {c - u - w, c + u - w, c + u + w, c - u + w};
      for (int i : {0, 1, 2, 0, 2, 3}) pushVertex(v, q[i], n);
    }
  }
  return v;
}

Eigen::Matrix4f toMatrix(const Eigen::Isometry3d& pose) { return pose.matrix().cast<float>(); }

// A frame whose z axis runs from `from` to `to`, x and y scaled to `width`: a cube becomes a thin beam.
Eigen::Matrix4f beam(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double width) {
  const Eigen::Vector3d d = to - from;
  const double length = d.norm();
  const Eigen::Vector3d z = length > 0.0 ? Eigen::Vector3d(d / length) : Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d x = z.unitOrthogonal(), y = z.cross(x);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<3, 1>(0, 0) = x * width;
  m.block<3, 1>(0, 1) = y * width;
  m.block<3, 1>(0, 2) = d;
  m.block<3, 1>(0, 3) = 0.5 * (from + to);
  return m.cast<float>();
}

Eigen::Matrix4f scaledAt(const Eigen::Isometry3d& pose, const Eigen::Vector3d& scale) {
  Eigen::Matrix4d m = pose.matrix();
  m.block<3, 3>(0, 0) = pose.linear() * scale.asDiagonal();
  return m.cast<float>();
}

}  // namespace

Eigen::Matrix4f projection(const EyeView& eye, float nearZ, float farZ) {
  const float l = static_cast<float>(std::tan(eye.angleLeft)), r = static_cast<float>(std::tan(eye.angleRight));
  const float u = static_cast<float>(std::tan(eye.angleUp)), d = static_cast<float>(std::tan(eye.angleDown));
  Eigen::Matrix4f p = Eigen::Matrix4f::Zero();
  p(0, 0) = 2.0f / (r - l);
  p(0, 2) = (r + l) / (r - l);
  p(1, 1) = 2.0f / (u - d);
  p(1, 2) = (u + d) / (u - d);
  p(2, 2) = -(farZ + nearZ) / (farZ - nearZ);
  p(2, 3) = -2.0f * farZ * nearZ / (farZ - nearZ);
  p(3, 2) = -1.0f;
  return p;
}

GlRenderer::GlRenderer() {
  const GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader);
  const GLuint fs = compile(GL_FRAGMENT_SHADER, kFragmentShader);
  program_ = glCreateProgram();
  glAttachShader(program_, vs);
  glAttachShader(program_, fs);
  glLinkProgram(program_);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (ok == 0) throw std::runtime_error("headset renderer: shaders do not link");
  uModel_ = glGetUniformLocation(program_, "model");
  uViewProj_ = glGetUniformLocation(program_, "viewProj");
  uColor_ = glGetUniformLocation(program_, "color");
  uLit_ = glGetUniformLocation(program_, "lit");
  uAlpha_ = glGetUniformLocation(program_, "alpha");
  const auto sphere = sphereVertices();
  sphere_ = upload(sphere, sphere.size() / view::kFloatsPerVertex);
  const auto cube = cubeVertices();
  cube_ = upload(cube, cube.size() / view::kFloatsPerVertex);
  glGenFramebuffers(1, &fbo_);
}

GlRenderer::~GlRenderer() {
  const auto release = [](GpuMesh& m) {
    glDeleteBuffers(1, &m.vbo);
    glDeleteVertexArrays(1, &m.vao);
  };
  for (auto& [key, mesh] : meshes_) release(mesh);
  if (overlay_) release(overlay_->gpu);
  release(sphere_);
  release(cube_);
  if (depth_ != 0) glDeleteRenderbuffers(1, &depth_);
  if (layer_.fbo != 0) {
    glDeleteRenderbuffers(1, &layer_.color);
    glDeleteRenderbuffers(1, &layer_.depth);
    glDeleteFramebuffers(1, &layer_.fbo);
  }
  glDeleteFramebuffers(1, &fbo_);
  glDeleteProgram(program_);
}

GlRenderer::GpuMesh GlRenderer::upload(const std::vector<float>& vertices, std::size_t count) {
  GpuMesh m;
  glGenVertexArrays(1, &m.vao);
  glGenBuffers(1, &m.vbo);
  glBindVertexArray(m.vao);
  glBindBuffer(GL_ARRAY_BUFFER, m.vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(float)), vertices.data(), GL_STATIC_DRAW);
  constexpr GLsizei stride = view::kFloatsPerVertex * sizeof(float);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(3 * sizeof(float)));
  glBindVertexArray(0);
  m.count = static_cast<std::int32_t>(count);
  return m;
}

void GlRenderer::setScene(const view::SceneDescription& scene) {
  items_.clear();
  layer_.valid = false;
  last_.clear();
  for (const auto& d : scene.drawables) {
    if (!d.mesh || d.mesh->vertexCount == 0) continue;
    auto it = meshes_.find(d.mesh.get());
    if (it == meshes_.end()) it = meshes_.emplace(d.mesh.get(), upload(d.mesh->vertices, d.mesh->vertexCount)).first;
    items_.push_back({d.kind, d.index, &it->second, toMatrix(d.pose), d.color});
  }
}

void GlRenderer::setOverlay(std::shared_ptr<const view::MeshBuffer> mesh, const view::Rgb& color, float alpha) {
  if (overlay_) {
    glDeleteBuffers(1, &overlay_->gpu.vbo);
    glDeleteVertexArrays(1, &overlay_->gpu.vao);
    overlay_.reset();
  }
  if (!mesh || mesh->vertexCount == 0) return;
  const GpuMesh gpu = upload(mesh->vertices, mesh->vertexCount);
  overlay_ = Overlay{std::move(mesh), gpu, color, alpha};
}

void GlRenderer::ensureTargets(int width, int height) {
  if (width == depthWidth_ && height == depthHeight_) return;
  if (depth_ == 0) glGenRenderbuffers(1, &depth_);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
  depthWidth_ = width;
  depthHeight_ = height;
}

void GlRenderer::draw(const GpuMesh& mesh, const Eigen::Matrix4f& model, const view::Rgb& color, bool lit, float alpha) {
  glUniformMatrix4fv(uModel_, 1, GL_FALSE, model.data());
  glUniform3f(uColor_, color.r, color.g, color.b);
  glUniform1i(uLit_, lit ? 1 : 0);
  glUniform1f(uAlpha_, alpha);
  glBindVertexArray(mesh.vao);
  glDrawArrays(GL_TRIANGLES, 0, mesh.count);
}

void GlRenderer::drawSegment(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double width, const view::Rgb& color) {
  draw(cube_, beam(from, to, width), color, false);
}

void GlRenderer::keepStillLayer(bool on) {
  layer_.on = on;
  layer_.valid = false;
}

GlRenderer::Look GlRenderer::lookOf(const Item& item, const view::Frame& frame) const {
  if (item.kind == view::DrawableKind::Environment || item.index >= frame.parts.size()) return {item.pose, item.color, true};
  const view::PartFrame& p = frame.parts[item.index];
  return {toMatrix(p.pose), p.color, p.shown};
}

namespace {

bool sameEye(const EyeView& a, const EyeView& b) {
  return a.pose.matrix() == b.pose.matrix() && a.angleLeft == b.angleLeft && a.angleRight == b.angleRight && a.angleUp == b.angleUp &&
         a.angleDown == b.angleDown;
}

// The state every pass starts from: depth tested, both sides drawn, and (unless a layer is copied over it)
// the picture cleared to the background.
void beginPass(int width, int height, bool clear = true) {
  glViewport(0, 0, width, height);
  // The values written are already sRGB-encoded (as on the desktop): no conversion into an sRGB image.
  glDisable(GL_FRAMEBUFFER_SRGB);
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  if (!clear) return;
  glClearColor(kClear[0], kClear[1], kClear[2], 1.0f);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

}  // namespace

bool GlRenderer::useStillLayer(const std::vector<Look>& looks, const EyeView& eye, int width, int height, const Eigen::Matrix4f& viewProj) {
  StillLayer& l = layer_;
  if (l.valid && l.width == width && l.height == height && sameEye(l.eye, eye) && l.in.size() == looks.size()) {
    bool intact = true;
    for (std::size_t i = 0; i < looks.size() && intact; ++i) intact = l.in[i] == 0 || looks[i] == l.drawn[i];
    if (intact) {
      ++use_.drawnOver;
      return true;
    }
  }
  l.valid = false;
  // Made only once the eye has held still for a frame: an eye that moves would have it made every frame.
  if (!lastEye_ || !sameEye(*lastEye_, eye) || last_.size() != looks.size()) return false;
  if (l.fbo == 0) {
    glGenFramebuffers(1, &l.fbo);
    glGenRenderbuffers(1, &l.color);
    glGenRenderbuffers(1, &l.depth);
  }
  if (l.width != width || l.height != height) {
    glBindRenderbuffer(GL_RENDERBUFFER, l.color);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glBindRenderbuffer(GL_RENDERBUFFER, l.depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
    l.width = width;
    l.height = height;
  }
  glBindFramebuffer(GL_FRAMEBUFFER, l.fbo);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, l.color);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, l.depth);
  beginPass(width, height);
  glUseProgram(program_);
  glUniformMatrix4fv(uViewProj_, 1, GL_FALSE, viewProj.data());
  l.in.assign(looks.size(), 0);
  l.drawn = looks;
  for (std::size_t i = 0; i < looks.size(); ++i) {
    if (!(looks[i] == last_[i])) continue;  // moving: drawn over the layer each frame
    l.in[i] = 1;
    if (looks[i].shown) draw(*items_[i].mesh, looks[i].pose, looks[i].color, true);
  }
  l.eye = eye;
  l.valid = true;
  ++use_.made;
  ++use_.drawnOver;
  return true;
}

void GlRenderer::render(std::uint32_t colorTexture, int width, int height, const EyeView& eye, const view::Frame* frame,
                        const HandsSample& hands) {
  ensureTargets(width, height);
  const Eigen::Matrix4f viewProj = projection(eye, kNear, kFar) * eye.pose.inverse().matrix().cast<float>();
  std::vector<Look>& looks = looks_;
  looks.clear();
  if (frame != nullptr)
    for (const Item& item : items_) looks.push_back(lookOf(item, *frame));
  const bool layered = layer_.on && frame != nullptr && useStillLayer(looks, eye, width, height, viewProj);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colorTexture, 0);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  beginPass(width, height, !layered);
  if (layered) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, layer_.fbo);
    glBlitFramebuffer(0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  }
  glUseProgram(program_);
  glUniformMatrix4fv(uViewProj_, 1, GL_FALSE, viewProj.data());

  if (frame != nullptr) {
    for (std::size_t i = 0; i < items_.size(); ++i)
      if ((!layered || layer_.in[i] == 0) && looks[i].shown) draw(*items_[i].mesh, looks[i].pose, looks[i].color, true);
    for (const view::DropLine& d : frame->drops) {
      drawSegment(d.from, d.to, 0.002, kLine);
      Eigen::Isometry3d mark = Eigen::Isometry3d::Identity();
      mark.translation() = d.to;
      draw(cube_, scaledAt(mark, Eigen::Vector3d(0.012, 0.012, 0.001)), kLine, false);
    }
    for (const view::HoistFrame& h : frame->hoists) {
      const Eigen::Vector3d hook = h.hook.translation();
      drawSegment(Eigen::Vector3d(hook.x(), hook.y(), h.top), hook, 0.004, kCable);
      draw(cube_, scaledAt(h.hook, Eigen::Vector3d::Constant(0.03)), h.engaged ? view::kHighlight : kCable, true);
    }
    last_.swap(looks);
  }
  for (const Line& l : lines_) drawSegment(l.from, l.to, l.width, l.color);
  lastEye_ = eye;
  for (int k = 0; k < 2; ++k) {
    const HandSample& hand = hands.hands[static_cast<std::size_t>(k)];
    const bool closed = frame != nullptr && (frame->hands[static_cast<std::size_t>(k)].grab ||
                                             frame->hands[static_cast<std::size_t>(k)].holding.has_value());
    if (hand.source == HandSample::Source::Joints) {
      for (int j = 0; j < kJointCount; ++j) {
        const double r = std::max(0.004, static_cast<double>(hand.radii[static_cast<std::size_t>(j)]));
        draw(sphere_, scaledAt(hand.joints[static_cast<std::size_t>(j)], Eigen::Vector3d::Constant(r)),
             closed ? view::kHighlight : kSkin, true);
      }
    } else if (hand.source == HandSample::Source::Controller) {
      draw(cube_, scaledAt(hand.joints[kPalm], Eigen::Vector3d(0.04, 0.04, 0.12)),
           closed || hand.select ? view::kHighlight : kController, true);
    }
  }
  // Last, over everything and hiding nothing: blended, depth tested but not written, front faces only so
  // that each pixel is covered once.
  if (overlay_) {
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glFrontFace(GL_CCW);
    draw(overlay_->gpu, Eigen::Matrix4f::Identity(), overlay_->color, true, overlay_->alpha);
    glDisable(GL_CULL_FACE);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
  }
  glBindVertexArray(0);
  glUseProgram(0);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace vaw::xr
