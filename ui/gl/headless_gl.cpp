#include "vaw/gl/headless_gl.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <stdexcept>

namespace vaw::gl {

namespace {

EGLDisplay initialize(EGLDisplay d) {
  if (d == EGL_NO_DISPLAY) return d;
  EGLint major = 0, minor = 0;
  return eglInitialize(d, &major, &minor) ? d : EGL_NO_DISPLAY;
}

}  // namespace

HeadlessGl::HeadlessGl() {
  const auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  const auto queryDeviceString = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
  const auto platformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (platformDisplay == nullptr) throw std::runtime_error("EGL without eglGetPlatformDisplayEXT");
  EGLDisplay display = EGL_NO_DISPLAY;
  if (queryDevices != nullptr) {
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (queryDevices(16, devices, &count)) {
      for (EGLint i = 0; i < count && display == EGL_NO_DISPLAY; ++i) {
        display = initialize(platformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr));
        if (display == EGL_NO_DISPLAY) continue;
        const char* ext = queryDeviceString != nullptr ? queryDeviceString(devices[i], EGL_EXTENSIONS) : nullptr;
        platform_ = "device " + std::to_string(i) + " of " + std::to_string(count) +
                    (ext != nullptr && std::string(ext).find("EGL_MESA_device_software") != std::string::npos ? " (software)" : "");
      }
    }
  }
  if (display == EGL_NO_DISPLAY) {
    display = initialize(platformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr));
    platform_ = "surfaceless";
  }
  if (display == EGL_NO_DISPLAY) throw std::runtime_error("no EGL display: neither the device nor the surfaceless platform initialises");
  const auto fail = [&](const char* why) {
    eglTerminate(display);
    throw std::runtime_error(why);
  };
  if (!eglBindAPI(EGL_OPENGL_API)) fail("EGL without desktop OpenGL");
  // No window: any surface type (the device platform offers pbuffer configs only, and eglChooseConfig
  // asks for a window one unless told).
  const EGLint configAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_DONT_CARE, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint configs = 0;
  if (!eglChooseConfig(display, configAttribs, &config, 1, &configs) || configs < 1) fail("no EGL config for OpenGL");
  const EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                   EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttribs);
  if (context == EGL_NO_CONTEXT) fail("no OpenGL 3.3 core context through EGL");
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    eglDestroyContext(display, context);
    fail("cannot make the EGL context current without a surface");
  }
  display_ = display;
  context_ = context;
}

HeadlessGl::~HeadlessGl() {
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
  eglTerminate(display_);
}

}  // namespace vaw::gl
