// The headset renderer alone, with no OpenXR and no X server (docs/benchmarks.md, "The headset renderer
// through EGL"): ui/gl/gl_renderer.cpp draws both eyes of a bundled scene at a headset's resolution
// into textures, in an OpenGL 3.3 core context made through EGL on the device platform (a GPU's driver, or
// Mesa's software devices), falling back to Mesa's surfaceless platform. Per frame: the CPU's issue of both
// eyes, the GPU's time for them (GL_TIME_ELAPSED timer queries) and issue plus glFinish, medians over the
// frames after a warm-up.
//
//   build/bin/vaw_bench_gl_renderer [SCENE] [EYE_WIDTH EYE_HEIGHT] [FRAMES]
//   (defaults: large-gearbox.vaw.json 2064 2208 60)
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "vaw/gl/gl_renderer.hpp"
#include "vaw/gl/headless_gl.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/sim/scene.hpp"
#include "vaw/sim/world.hpp"
#include "vaw/view/frame.hpp"

namespace {

[[noreturn]] void die(const std::string& what) {
  std::fprintf(stderr, "vaw_bench_gl_renderer: %s\n", what.c_str());
  std::exit(1);
}

// An eye 0.45 m above the table top and 0.6 m back from its centre, looking at the centre; 6.4 cm apart.
vaw::xr::EyeView eye(const Eigen::Vector3d& target, double side) {
  const Eigen::Vector3d head(0.0, -0.6, 0.45);
  const Eigen::Vector3d back = (head - target).normalized();  // the eye looks along its -z
  const Eigen::Vector3d right = Eigen::Vector3d::UnitZ().cross(back).normalized();
  const Eigen::Vector3d up = back.cross(right);
  vaw::xr::EyeView v;
  v.pose.linear().col(0) = right;
  v.pose.linear().col(1) = up;
  v.pose.linear().col(2) = back;
  v.pose.translation() = head + side * 0.032 * right;
  const double deg = std::numbers::pi / 180.0;
  // A headset's asymmetric fields of view, wider towards the temple.
  v.angleLeft = (side < 0.0 ? -52.0 : -45.0) * deg;
  v.angleRight = (side < 0.0 ? 45.0 : 52.0) * deg;
  v.angleUp = 50.0 * deg;
  v.angleDown = -55.0 * deg;
  return v;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const std::string sceneName = argc > 1 ? argv[1] : "large-gearbox.vaw.json";
  const int width = argc > 3 ? std::atoi(argv[2]) : 2064, height = argc > 3 ? std::atoi(argv[3]) : 2208;
  const int frames = argc > 4 ? std::atoi(argv[4]) : 60;
  if (width <= 0 || height <= 0 || frames <= 0) die("usage: vaw_bench_gl_renderer [SCENE] [EYE_WIDTH EYE_HEIGHT] [FRAMES]");

  std::optional<vaw::gl::HeadlessGl> ctx;
  try {
    ctx.emplace();
  } catch (const std::exception& e) {
    die(e.what());
  }
  vaw::ImporterRegistry importers;
  (void)importers.loadPlugins(VAW_BUILD_PLUGIN_DIR);
  const auto scene = vaw::sim::Scene::build(
      vaw::loadScene(std::filesystem::path(VAW_BUILD_RESOURCE_DIR) / "scenes" / sceneName, importers));
  const vaw::view::SceneDescription description = vaw::view::describe(scene->assembly());
  const vaw::sim::World world(scene);
  vaw::view::Frame frame;
  vaw::view::makeFrame(world, description, {}, frame);

  std::uint32_t textures[2];
  glGenTextures(2, textures);
  for (const std::uint32_t t : textures) {
    glBindTexture(GL_TEXTURE_2D, t);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  }
  vaw::xr::GlRenderer renderer;
  renderer.setScene(description);
  const Eigen::Vector3d target = description.partsBounds.center();
  const vaw::xr::EyeView eyes[2] = {eye(target, -1.0), eye(target, 1.0)};
  const vaw::xr::HandsSample hands{};
  GLuint query = 0;
  glGenQueries(1, &query);

  std::vector<double> issue, gpu, finished;
  using Clock = std::chrono::steady_clock;
  for (int k = 0; k < frames + 5; ++k) {
    glBeginQuery(GL_TIME_ELAPSED, query);
    const auto t0 = Clock::now();
    for (int e = 0; e < 2; ++e) renderer.render(textures[e], width, height, eyes[e], &frame, hands);
    const auto t1 = Clock::now();
    glEndQuery(GL_TIME_ELAPSED);
    glFinish();
    const auto t2 = Clock::now();
    GLuint64 ns = 0;
    glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
    if (k < 5) continue;  // warm-up: uploads, shader compilation, first allocations
    issue.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    finished.push_back(std::chrono::duration<double, std::milli>(t2 - t0).count());
    gpu.push_back(static_cast<double>(ns) * 1e-6);
  }
  if (glGetError() != GL_NO_ERROR) die("an OpenGL error while drawing");
  // VAW_BENCH_LEFT_EYE=FILE.ppm: the left eye's last image, to look at.
  if (const char* file = std::getenv("VAW_BENCH_LEFT_EYE")) {
    GLuint read = 0;
    glGenFramebuffers(1, &read);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, read);
    glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, textures[0], 0);
    std::vector<unsigned char> rgba(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    glDeleteFramebuffers(1, &read);
    if (std::FILE* out = std::fopen(file, "wb")) {
      std::fprintf(out, "P6\n%d %d\n255\n", width, height);
      for (int y = height - 1; y >= 0; --y)  // OpenGL's rows run bottom up
        for (int x = 0; x < width; ++x) std::fwrite(&rgba[(static_cast<std::size_t>(y) * width + x) * 4], 1, 3, out);
      std::fclose(out);
    }
  }
  std::printf("renderer: %s; %s; EGL %s\n", reinterpret_cast<const char*>(glGetString(GL_RENDERER)),
              reinterpret_cast<const char*>(glGetString(GL_VERSION)), ctx->platform().c_str());
  std::printf("scene: %s, %zu drawables; both eyes at %d x %d; %d frames after 5 of warm-up\n", sceneName.c_str(),
              description.drawables.size(), width, height, frames);
  std::printf("median per frame (both eyes): CPU issue %.3f ms, GPU %.3f ms, issue + finish %.3f ms\n", median(issue), median(gpu),
              median(finished));
  glDeleteQueries(1, &query);
  glDeleteTextures(2, textures);
  return 0;
}
