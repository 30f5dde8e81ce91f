// The headset through OpenXR (docs/vr.md): instance and session with XR_KHR_opengl_enable on X11/GLX, the
// PRIMARY_STEREO view configuration, a STAGE space (else LOCAL), a swapchain per eye, the frame loop paced by
// xrWaitFrame, tracked hands (XR_EXT_hand_tracking) with the KHR simple controller as the fallback, and the
// validation layer's messages (XR_EXT_debug_utils) handed to the workbench.
#include <time.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

// Eigen first: Xlib defines macros (Success, None, Status) that Eigen's headers refuse to see.
#include "vaw/gl/gl_renderer.hpp"
#include "vaw/ui/xr.hpp"

#include <GL/glx.h>
#include <X11/Xlib.h>

#define XR_USE_PLATFORM_XLIB
#define XR_USE_GRAPHICS_API_OPENGL
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

namespace vaw::xr {

namespace {

constexpr XrViewConfigurationType kViewConfig = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
constexpr std::int64_t kGlSrgb8Alpha8 = 0x8C43, kGlRgba8 = 0x8058;  // GL_SRGB8_ALPHA8, GL_RGBA8

double threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

Eigen::Isometry3d toEigen(const XrPosef& p) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = Eigen::Quaterniond(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z).normalized().toRotationMatrix();
  out.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return out;
}

Eigen::Vector3d toEigen(const XrVector3f& v) { return {v.x, v.y, v.z}; }

constexpr XrPosef kIdentityPose{{0.0f, 0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 0.0f}};

bool located(XrSpaceLocationFlags f) {
  return (f & XR_SPACE_LOCATION_POSITION_VALID_BIT) != 0 && (f & XR_SPACE_LOCATION_ORIENTATION_VALID_BIT) != 0;
}

SessionState toState(XrSessionState s) {
  switch (s) {
    case XR_SESSION_STATE_IDLE: return SessionState::Idle;
    case XR_SESSION_STATE_READY: return SessionState::Ready;
    case XR_SESSION_STATE_SYNCHRONIZED: return SessionState::Synchronized;
    case XR_SESSION_STATE_VISIBLE: return SessionState::Visible;
    case XR_SESSION_STATE_FOCUSED: return SessionState::Focused;
    case XR_SESSION_STATE_STOPPING: return SessionState::Stopping;
    case XR_SESSION_STATE_LOSS_PENDING: return SessionState::LossPending;
    case XR_SESSION_STATE_EXITING: return SessionState::Exiting;
    default: return SessionState::Unknown;
  }
}

std::string resultName(XrResult r) {
  // xrResultToString needs an instance; these are the ones a user may meet before there is one.
  switch (r) {
    case XR_ERROR_RUNTIME_UNAVAILABLE: return "XR_ERROR_RUNTIME_UNAVAILABLE";
    case XR_ERROR_RUNTIME_FAILURE: return "XR_ERROR_RUNTIME_FAILURE";
    case XR_ERROR_INSTANCE_LOST: return "XR_ERROR_INSTANCE_LOST";
    case XR_ERROR_SESSION_LOST: return "XR_ERROR_SESSION_LOST";
    case XR_ERROR_FORM_FACTOR_UNAVAILABLE: return "XR_ERROR_FORM_FACTOR_UNAVAILABLE";
    case XR_ERROR_FORM_FACTOR_UNSUPPORTED: return "XR_ERROR_FORM_FACTOR_UNSUPPORTED";
    case XR_ERROR_EXTENSION_NOT_PRESENT: return "XR_ERROR_EXTENSION_NOT_PRESENT";
    case XR_ERROR_API_VERSION_UNSUPPORTED: return "XR_ERROR_API_VERSION_UNSUPPORTED";
    case XR_ERROR_INITIALIZATION_FAILED: return "XR_ERROR_INITIALIZATION_FAILED";
    case XR_ERROR_GRAPHICS_DEVICE_INVALID: return "XR_ERROR_GRAPHICS_DEVICE_INVALID";
    default: return "XrResult " + std::to_string(static_cast<int>(r));
  }
}

std::string versionText(XrVersion v) {
  return std::to_string(XR_VERSION_MAJOR(v)) + "." + std::to_string(XR_VERSION_MINOR(v)) + "." +
         std::to_string(XR_VERSION_PATCH(v));
}

// Thrown inside start() and caught there: what failed, in the user's words.
struct StartError {
  Failure failure;
  std::string text;
};

class OpenXrBackend final : public Backend {
 public:
  ~OpenXrBackend() override { destroy(); }

  Event start(const StartOptions& options) override {
    options_ = options;
    try {
      createInstance();
      createSession();
      createSpaces();
      createSwapchains();
      createInputs();
      renderer_ = std::make_unique<GlRenderer>();
    } catch (const StartError& e) {
      destroy();
      return failureEvent(e.failure, e.text);
    } catch (const std::exception& e) {
      destroy();
      return failureEvent(Failure::RuntimeError, e.what());
    }
    return {};
  }

  const RuntimeInfo& runtime() const override { return info_; }

  void setScene(const view::SceneDescription& scene) override {
    if (renderer_) renderer_->setScene(scene);
  }

  void setOverlay(std::shared_ptr<const view::MeshBuffer> mesh, const view::Rgb& color, float alpha) override {
    if (renderer_) renderer_->setOverlay(std::move(mesh), color, alpha);
  }

  std::vector<Event> poll() override {
    std::vector<Event> out;
    while (instance_ != XR_NULL_HANDLE && !finished_) {
      XrEventDataBuffer event{XR_TYPE_EVENT_DATA_BUFFER};
      const XrResult r = xrPollEvent(instance_, &event);
      if (r == XR_EVENT_UNAVAILABLE) break;
      if (!ok(r, "xrPollEvent")) break;
      switch (event.type) {
        case XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED: {
          const auto& e = *reinterpret_cast<const XrEventDataSessionStateChanged*>(&event);
          state_ = e.state;
          Event s;
          s.kind = Event::Kind::State;
          s.state = toState(e.state);
          out.push_back(s);
          sessionStateChanged(e.state);
          break;
        }
        case XR_TYPE_EVENT_DATA_INSTANCE_LOSS_PENDING:
          fail(Failure::RuntimeLost, "the OpenXR runtime " + info_.name + " is going away (instance loss pending)");
          break;
        case XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED:
          interactionProfileChanged();
          break;
        case XR_TYPE_EVENT_DATA_EVENTS_LOST:
          note("the runtime dropped " +
                   std::to_string(reinterpret_cast<const XrEventDataEventsLost*>(&event)->lostEventCount) + " events",
               true);
          break;
        default:
          break;
      }
    }
    flushMessages(out);
    return out;
  }

  bool running() const override { return running_ && !finished_; }
  bool finished() const override { return finished_; }

  void requestExit() override {
    if (running_ && !finished_) ok(xrRequestExitSession(session_), "xrRequestExitSession");
    else if (!running_) finished_ = true;  // not begun yet: nothing for the runtime to wind down
  }

  FrameResult frame(const Simulate& simulate) override {
    FrameResult result;
    XrFrameWaitInfo waitInfo{XR_TYPE_FRAME_WAIT_INFO};
    XrFrameState frameState{XR_TYPE_FRAME_STATE};
    if (!ok(xrWaitFrame(session_, &waitInfo, &frameState), "xrWaitFrame")) return result;
    XrFrameBeginInfo beginInfo{XR_TYPE_FRAME_BEGIN_INFO};
    if (!ok(xrBeginFrame(session_, &beginInfo), "xrBeginFrame")) return result;
    syncActions();

    FrameTiming timing{frameState.predictedDisplayTime, frameState.shouldRender == XR_TRUE};
    double t0 = threadCpuMs();
    const view::Frame* drawn = simulate(timing);
    result.simulateMs = threadCpuMs() - t0;
    if (finished_) return result;

    XrViewLocateInfo locateInfo{XR_TYPE_VIEW_LOCATE_INFO};
    locateInfo.viewConfigurationType = kViewConfig;
    locateInfo.displayTime = frameState.predictedDisplayTime;
    locateInfo.space = space_;
    XrViewState viewState{XR_TYPE_VIEW_STATE};
    std::array<XrView, 2> views{};
    for (auto& v : views) v.type = XR_TYPE_VIEW;
    std::uint32_t viewCount = 0;
    if (!ok(xrLocateViews(session_, &locateInfo, &viewState, 2, &viewCount, views.data()), "xrLocateViews")) return result;

    std::array<XrCompositionLayerProjectionView, 2> layerViews{};
    XrCompositionLayerProjection layer{XR_TYPE_COMPOSITION_LAYER_PROJECTION};
    const bool render = frameState.shouldRender == XR_TRUE && viewCount == 2 && located(viewState.viewStateFlags);
    if (render) {
      const HandsSample hands = sampleHands(frameState.predictedDisplayTime);
      t0 = threadCpuMs();
      for (std::size_t eye = 0; eye < 2; ++eye) {
        Swapchain& sc = swapchains_[eye];
        XrSwapchainImageAcquireInfo acquireInfo{XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO};
        std::uint32_t index = 0;
        if (!ok(xrAcquireSwapchainImage(sc.handle, &acquireInfo, &index), "xrAcquireSwapchainImage")) return result;
        XrSwapchainImageWaitInfo swapWait{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO};
        swapWait.timeout = XR_INFINITE_DURATION;
        if (!ok(xrWaitSwapchainImage(sc.handle, &swapWait), "xrWaitSwapchainImage")) return result;
        EyeView eyeView;
        eyeView.pose = worldFromSpace_ * toEigen(views[eye].pose);
        eyeView.angleLeft = views[eye].fov.angleLeft;
        eyeView.angleRight = views[eye].fov.angleRight;
        eyeView.angleUp = views[eye].fov.angleUp;
        eyeView.angleDown = views[eye].fov.angleDown;
        renderer_->render(sc.images[index].image, sc.width, sc.height, eyeView, drawn, hands);
        XrSwapchainImageReleaseInfo releaseInfo{XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO};
        if (!ok(xrReleaseSwapchainImage(sc.handle, &releaseInfo), "xrReleaseSwapchainImage")) return result;
        layerViews[eye] = {XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW};
        layerViews[eye].pose = views[eye].pose;
        layerViews[eye].fov = views[eye].fov;
        layerViews[eye].subImage.swapchain = sc.handle;
        layerViews[eye].subImage.imageRect = {{0, 0}, {sc.width, sc.height}};
        layerViews[eye].subImage.imageArrayIndex = 0;
      }
      result.renderMs = threadCpuMs() - t0;
      layer.space = space_;
      layer.viewCount = 2;
      layer.views = layerViews.data();
      result.rendered = true;
    }
    const XrCompositionLayerBaseHeader* layers[] = {reinterpret_cast<const XrCompositionLayerBaseHeader*>(&layer)};
    XrFrameEndInfo endInfo{XR_TYPE_FRAME_END_INFO};
    endInfo.displayTime = frameState.predictedDisplayTime;
    endInfo.environmentBlendMode = blendMode_;
    endInfo.layerCount = render ? 1 : 0;
    endInfo.layers = render ? layers : nullptr;
    if (!ok(xrEndFrame(session_, &endInfo), "xrEndFrame")) return result;
    result.submitted = true;
    if (viewCount == 2 && located(viewState.viewStateFlags)) {
      const Eigen::Isometry3d a = toEigen(views[0].pose), b = toEigen(views[1].pose);
      Eigen::Isometry3d head = a;
      head.translation() = 0.5 * (a.translation() + b.translation());
      head.linear() = Eigen::Quaterniond(a.linear()).slerp(0.5, Eigen::Quaterniond(b.linear())).toRotationMatrix();
      headInSpace_ = head;
      result.head = worldFromSpace_ * head;
      result.fovUp = 0.5 * (views[0].fov.angleUp + views[1].fov.angleUp);
      result.fovDown = 0.5 * (views[0].fov.angleDown + views[1].fov.angleDown);
    }
    return result;
  }

  HandsSample sampleHands(std::int64_t time) override {
    HandsSample out;
    if (state_ != XR_SESSION_STATE_FOCUSED || finished_) return out;
    for (std::size_t h = 0; h < 2; ++h) {
      HandSample& hand = out.hands[h];
      if (handTrackers_[h] != XR_NULL_HANDLE && locateJoints(h, time, hand)) continue;
      locateController(h, time, hand);
    }
    return out;
  }

 private:
  struct Swapchain {
    XrSwapchain handle = XR_NULL_HANDLE;
    int width = 0, height = 0;
    std::vector<XrSwapchainImageOpenGLKHR> images;
  };

  // ---- failures and messages ----

  Event failureEvent(Failure f, const std::string& text) {
    Event e;
    e.kind = Event::Kind::Failure;
    e.failure = f;
    e.text = text;
    return e;
  }

  void fail(Failure f, const std::string& text) {
    if (finished_) return;
    finished_ = true;
    running_ = false;
    pendingFailure_ = failureEvent(f, text);
  }

  void note(const std::string& text, bool warning) {
    std::lock_guard<std::mutex> lock(messagesMutex_);
    messages_.push_back({text, warning});
  }

  void flushMessages(std::vector<Event>& out) {
    {
      std::lock_guard<std::mutex> lock(messagesMutex_);
      for (auto& [text, warning] : messages_) {
        Event e;
        e.kind = Event::Kind::Message;
        e.warning = warning;
        e.text = std::move(text);
        out.push_back(std::move(e));
      }
      messages_.clear();
    }
    if (pendingFailure_) {
      out.push_back(std::move(*pendingFailure_));
      pendingFailure_.reset();
    }
  }

  // An error from a call in the running session ends it, saying which: the session or the whole runtime lost,
  // or another error with the call's name.
  bool ok(XrResult r, const char* call) {
    if (XR_SUCCEEDED(r)) return true;
    const std::string who = info_.name.empty() ? std::string("the OpenXR runtime") : "the OpenXR runtime " + info_.name;
    if (r == XR_ERROR_SESSION_LOST) fail(Failure::SessionLost, who + " lost the session (" + call + ": XR_ERROR_SESSION_LOST)");
    else if (r == XR_ERROR_INSTANCE_LOST)
      fail(Failure::RuntimeLost, who + " stopped answering: it crashed or quit (" + call + ": XR_ERROR_INSTANCE_LOST)");
    else if (r == XR_ERROR_RUNTIME_FAILURE)
      fail(Failure::RuntimeLost, who + " failed (" + call + ": XR_ERROR_RUNTIME_FAILURE)");
    else fail(Failure::RuntimeError, who + ": " + call + " failed with " + name(r));
    return false;
  }

  std::string name(XrResult r) const {
    char text[XR_MAX_RESULT_STRING_SIZE] = {};
    if (instance_ != XR_NULL_HANDLE && XR_SUCCEEDED(xrResultToString(instance_, r, text))) return text;
    return resultName(r);
  }

  // Start-up: a failing call throws with what the user should know.
  void must(XrResult r, const char* call, Failure f = Failure::RuntimeError) {
    if (XR_SUCCEEDED(r)) return;
    if (r == XR_ERROR_RUNTIME_UNAVAILABLE)
      throw StartError{Failure::NoRuntime, "no OpenXR runtime is installed or active (" + std::string(call) +
                                               ": XR_ERROR_RUNTIME_UNAVAILABLE); install SteamVR or Monado and make "
                                               "it the active runtime, or point XR_RUNTIME_JSON at its manifest"};
    const std::string who = info_.name.empty() ? std::string("the OpenXR runtime") : "the OpenXR runtime " + info_.name;
    throw StartError{f, who + ": " + call + " failed with " + name(r)};
  }

  static XRAPI_ATTR XrBool32 XRAPI_CALL debugMessage(XrDebugUtilsMessageSeverityFlagsEXT severity,
                                                     XrDebugUtilsMessageTypeFlagsEXT,
                                                     const XrDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    auto* self = static_cast<OpenXrBackend*>(user);
    std::string text = "OpenXR";
    if (data->functionName != nullptr) text += std::string(" ") + data->functionName;
    if (data->messageId != nullptr) text += std::string(" [") + data->messageId + "]";
    text += std::string(": ") + (data->message != nullptr ? data->message : "");
    self->note(text, (severity & XR_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) != 0 ||
                         (severity & XR_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) != 0);
    return XR_FALSE;
  }

  template <class Fn>
  Fn proc(const char* fnName) {
    PFN_xrVoidFunction fn = nullptr;
    must(xrGetInstanceProcAddr(instance_, fnName, &fn), fnName);
    return reinterpret_cast<Fn>(fn);
  }

  // ---- start-up ----

  void createInstance() {
    std::uint32_t count = 0;
    must(xrEnumerateInstanceExtensionProperties(nullptr, 0, &count, nullptr), "xrEnumerateInstanceExtensionProperties");
    std::vector<XrExtensionProperties> available(count, {XR_TYPE_EXTENSION_PROPERTIES});
    must(xrEnumerateInstanceExtensionProperties(nullptr, count, &count, available.data()), "xrEnumerateInstanceExtensionProperties");
    const auto has = [&](const char* ext) {
      return std::any_of(available.begin(), available.end(), [&](const auto& p) { return std::strcmp(p.extensionName, ext) == 0; });
    };
    if (!has(XR_KHR_OPENGL_ENABLE_EXTENSION_NAME))
      throw StartError{Failure::NoOpenGL, "the OpenXR runtime does not offer " XR_KHR_OPENGL_ENABLE_EXTENSION_NAME
                                          ", which vaw draws with (it renders with OpenGL on X11)"};
    std::vector<const char*> enabled{XR_KHR_OPENGL_ENABLE_EXTENSION_NAME};
    handTrackingExt_ = has(XR_EXT_HAND_TRACKING_EXTENSION_NAME);
    if (handTrackingExt_) enabled.push_back(XR_EXT_HAND_TRACKING_EXTENSION_NAME);
    const bool debugUtils = has(XR_EXT_DEBUG_UTILS_EXTENSION_NAME);
    if (debugUtils) enabled.push_back(XR_EXT_DEBUG_UTILS_EXTENSION_NAME);

    XrDebugUtilsMessengerCreateInfoEXT messengerInfo{XR_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    messengerInfo.messageSeverities = XR_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | XR_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    messengerInfo.messageTypes = XR_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | XR_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                 XR_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT | XR_DEBUG_UTILS_MESSAGE_TYPE_CONFORMANCE_BIT_EXT;
    messengerInfo.userCallback = &OpenXrBackend::debugMessage;
    messengerInfo.userData = this;

    XrInstanceCreateInfo create{XR_TYPE_INSTANCE_CREATE_INFO};
    create.next = debugUtils ? &messengerInfo : nullptr;  // messages from inside xrCreateInstance too
    std::strncpy(create.applicationInfo.applicationName, "vaw", XR_MAX_APPLICATION_NAME_SIZE - 1);
    create.applicationInfo.applicationVersion = 1;
    std::strncpy(create.applicationInfo.engineName, "vaw", XR_MAX_ENGINE_NAME_SIZE - 1);
    create.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 0, 0);
    create.enabledExtensionCount = static_cast<std::uint32_t>(enabled.size());
    create.enabledExtensionNames = enabled.data();
    must(xrCreateInstance(&create, &instance_), "xrCreateInstance");
    if (debugUtils) {
      const auto createMessenger = proc<PFN_xrCreateDebugUtilsMessengerEXT>("xrCreateDebugUtilsMessengerEXT");
      destroyMessenger_ = proc<PFN_xrDestroyDebugUtilsMessengerEXT>("xrDestroyDebugUtilsMessengerEXT");
      messengerInfo.next = nullptr;
      must(createMessenger(instance_, &messengerInfo, &messenger_), "xrCreateDebugUtilsMessengerEXT");
    }

    XrInstanceProperties props{XR_TYPE_INSTANCE_PROPERTIES};
    must(xrGetInstanceProperties(instance_, &props), "xrGetInstanceProperties");
    info_.name = props.runtimeName;
    info_.version = versionText(props.runtimeVersion);

    XrSystemGetInfo systemInfo{XR_TYPE_SYSTEM_GET_INFO};
    systemInfo.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
    const XrResult sys = xrGetSystem(instance_, &systemInfo, &system_);
    if (sys == XR_ERROR_FORM_FACTOR_UNAVAILABLE || sys == XR_ERROR_FORM_FACTOR_UNSUPPORTED)
      throw StartError{Failure::NoHeadset, "the OpenXR runtime " + info_.name +
                                               " sees no headset: connect it, switch it on and try again (" + name(sys) + ")"};
    must(sys, "xrGetSystem", Failure::NoHeadset);

    XrSystemHandTrackingPropertiesEXT handProps{XR_TYPE_SYSTEM_HAND_TRACKING_PROPERTIES_EXT};
    XrSystemProperties sysProps{XR_TYPE_SYSTEM_PROPERTIES};
    if (handTrackingExt_) sysProps.next = &handProps;
    must(xrGetSystemProperties(instance_, system_, &sysProps), "xrGetSystemProperties");
    info_.system = sysProps.systemName;
    info_.handTracking = handTrackingExt_ && handProps.supportsHandTracking == XR_TRUE;

    must(xrEnumerateViewConfigurations(instance_, system_, 0, &count, nullptr), "xrEnumerateViewConfigurations");
    std::vector<XrViewConfigurationType> configs(count);
    must(xrEnumerateViewConfigurations(instance_, system_, count, &count, configs.data()), "xrEnumerateViewConfigurations");
    if (std::find(configs.begin(), configs.end(), kViewConfig) == configs.end())
      throw StartError{Failure::NoHeadset, "the headset of " + info_.name + " has no stereo view (PRIMARY_STEREO)"};
    must(xrEnumerateViewConfigurationViews(instance_, system_, kViewConfig, 0, &count, nullptr), "xrEnumerateViewConfigurationViews");
    std::vector<XrViewConfigurationView> views(count, {XR_TYPE_VIEW_CONFIGURATION_VIEW});
    must(xrEnumerateViewConfigurationViews(instance_, system_, kViewConfig, count, &count, views.data()),
         "xrEnumerateViewConfigurationViews");
    if (count != 2) throw StartError{Failure::RuntimeError, "PRIMARY_STEREO has " + std::to_string(count) + " views, not 2"};
    info_.eyeWidth = static_cast<int>(views[0].recommendedImageRectWidth);
    info_.eyeHeight = static_cast<int>(views[0].recommendedImageRectHeight);

    must(xrEnumerateEnvironmentBlendModes(instance_, system_, kViewConfig, 0, &count, nullptr), "xrEnumerateEnvironmentBlendModes");
    std::vector<XrEnvironmentBlendMode> modes(count);
    must(xrEnumerateEnvironmentBlendModes(instance_, system_, kViewConfig, count, &count, modes.data()),
         "xrEnumerateEnvironmentBlendModes");
    if (modes.empty()) throw StartError{Failure::RuntimeError, "the runtime offers no environment blend mode"};
    blendMode_ = std::find(modes.begin(), modes.end(), XR_ENVIRONMENT_BLEND_MODE_OPAQUE) != modes.end()
                     ? XR_ENVIRONMENT_BLEND_MODE_OPAQUE
                     : modes.front();
  }

  void createSession() {
    const auto requirementsFn = proc<PFN_xrGetOpenGLGraphicsRequirementsKHR>("xrGetOpenGLGraphicsRequirementsKHR");
    XrGraphicsRequirementsOpenGLKHR requirements{XR_TYPE_GRAPHICS_REQUIREMENTS_OPENGL_KHR};
    must(requirementsFn(instance_, system_, &requirements), "xrGetOpenGLGraphicsRequirementsKHR");

    Display* display = glXGetCurrentDisplay();
    const GLXContext context = glXGetCurrentContext();
    const GLXDrawable drawable = glXGetCurrentDrawable();
    if (display == nullptr || context == nullptr)
      throw StartError{Failure::OpenGLContext, "no GLX OpenGL context is current: the headset needs OpenGL through GLX "
                                               "on X11 (under Wayland, start vaw with --vr or QT_QPA_PLATFORM=xcb)"};
    GLint major = 0, minor = 0;
    glGetIntegerv(0x821B, &major);  // GL_MAJOR_VERSION
    glGetIntegerv(0x821C, &minor);  // GL_MINOR_VERSION
    const XrVersion have = XR_MAKE_VERSION(major, minor, 0);
    if (have < requirements.minApiVersionSupported ||
        XR_VERSION_MAJOR(have) > XR_VERSION_MAJOR(requirements.maxApiVersionSupported))
      throw StartError{Failure::OpenGLContext, "the OpenXR runtime " + info_.name + " needs OpenGL " +
                                                   versionText(requirements.minApiVersionSupported) + " to " +
                                                   versionText(requirements.maxApiVersionSupported) + ", this context is " +
                                                   std::to_string(major) + "." + std::to_string(minor)};
    int fbConfigId = 0, screen = 0;
    glXQueryContext(display, context, GLX_FBCONFIG_ID, &fbConfigId);
    glXQueryContext(display, context, GLX_SCREEN, &screen);
    const int attributes[] = {GLX_FBCONFIG_ID, fbConfigId, None};
    int configCount = 0;
    GLXFBConfig* configs = glXChooseFBConfig(display, screen, attributes, &configCount);
    if (configs == nullptr || configCount < 1)
      throw StartError{Failure::OpenGLContext, "the current GLX context's framebuffer configuration cannot be found"};
    const GLXFBConfig config = configs[0];
    int visual = 0;
    glXGetFBConfigAttrib(display, config, GLX_VISUAL_ID, &visual);
    XFree(configs);

    XrGraphicsBindingOpenGLXlibKHR binding{XR_TYPE_GRAPHICS_BINDING_OPENGL_XLIB_KHR};
    binding.xDisplay = display;
    binding.visualid = static_cast<std::uint32_t>(visual);
    binding.glxFBConfig = config;
    binding.glxDrawable = drawable;
    binding.glxContext = context;
    XrSessionCreateInfo create{XR_TYPE_SESSION_CREATE_INFO};
    create.next = &binding;
    create.systemId = system_;
    must(xrCreateSession(instance_, &create, &session_), "xrCreateSession");
  }

  void createSpaces() {
    std::uint32_t count = 0;
    must(xrEnumerateReferenceSpaces(session_, 0, &count, nullptr), "xrEnumerateReferenceSpaces");
    std::vector<XrReferenceSpaceType> spaces(count);
    must(xrEnumerateReferenceSpaces(session_, count, &count, spaces.data()), "xrEnumerateReferenceSpaces");
    info_.stage = std::find(spaces.begin(), spaces.end(), XR_REFERENCE_SPACE_TYPE_STAGE) != spaces.end();
    XrReferenceSpaceCreateInfo create{XR_TYPE_REFERENCE_SPACE_CREATE_INFO};
    create.referenceSpaceType = info_.stage ? XR_REFERENCE_SPACE_TYPE_STAGE : XR_REFERENCE_SPACE_TYPE_LOCAL;
    create.poseInReferenceSpace = kIdentityPose;
    must(xrCreateReferenceSpace(session_, &create, &space_), "xrCreateReferenceSpace");
    // The world is z up with the table top at z = 0; OpenXR spaces are y up with -z ahead. The user stands at
    // the space's origin facing -z, which is the world's +y; the table's centre is in front of them, at a
    // standing worker's bench height above a STAGE floor, or below the eyes in a LOCAL space.
    Eigen::Matrix3d spaceFromWorld;
    spaceFromWorld << 1, 0, 0, 0, 0, 1, 0, -1, 0;
    const double height = info_.stage ? options_.placement.tableHeight : -options_.placement.tableBelowEyes;
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = spaceFromWorld;
    p.translation() = Eigen::Vector3d(0.0, height, -options_.placement.tableDistance);
    worldFromSpace_ = p.inverse();
  }

  void recenter() override {
    if (!headInSpace_) return;  // no frame located the head yet: the first placement stays
    const Eigen::Vector3d up = Eigen::Vector3d::UnitY();
    Eigen::Vector3d ahead = headInSpace_->linear() * Eigen::Vector3d(0.0, 0.0, -1.0);
    ahead -= up * up.dot(ahead);
    // Looking straight down or up: the head's own up (its top) points the way it faces.
    if (ahead.norm() < 1e-3) ahead = headInSpace_->linear() * Eigen::Vector3d::UnitY() - up * up.dot(headInSpace_->linear() * Eigen::Vector3d::UnitY());
    if (ahead.norm() < 1e-9) return;
    ahead.normalize();
    const Eigen::Vector3d right = ahead.cross(up);
    Eigen::Isometry3d spaceFromWorld = Eigen::Isometry3d::Identity();
    spaceFromWorld.linear().col(0) = right;  // world x
    spaceFromWorld.linear().col(1) = ahead;  // world y
    spaceFromWorld.linear().col(2) = up;     // world z
    spaceFromWorld.translation() =
        headInSpace_->translation() + ahead * options_.placement.tableDistance - up * options_.placement.tableBelowEyes;
    worldFromSpace_ = spaceFromWorld.inverse();
  }

  void createSwapchains() {
    std::uint32_t count = 0;
    must(xrEnumerateSwapchainFormats(session_, 0, &count, nullptr), "xrEnumerateSwapchainFormats");
    std::vector<std::int64_t> formats(count);
    must(xrEnumerateSwapchainFormats(session_, count, &count, formats.data()), "xrEnumerateSwapchainFormats");
    std::int64_t format = 0;
    for (const std::int64_t wanted : {kGlSrgb8Alpha8, kGlRgba8})
      if (format == 0 && std::find(formats.begin(), formats.end(), wanted) != formats.end()) format = wanted;
    if (format == 0) throw StartError{Failure::RuntimeError, "the runtime offers no 8-bit RGBA swapchain format"};
    for (auto& sc : swapchains_) {
      XrSwapchainCreateInfo create{XR_TYPE_SWAPCHAIN_CREATE_INFO};
      create.usageFlags = XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_SAMPLED_BIT;
      create.format = format;
      create.sampleCount = 1;
      create.width = static_cast<std::uint32_t>(info_.eyeWidth);
      create.height = static_cast<std::uint32_t>(info_.eyeHeight);
      create.faceCount = 1;
      create.arraySize = 1;
      create.mipCount = 1;
      must(xrCreateSwapchain(session_, &create, &sc.handle), "xrCreateSwapchain");
      sc.width = info_.eyeWidth;
      sc.height = info_.eyeHeight;
      must(xrEnumerateSwapchainImages(sc.handle, 0, &count, nullptr), "xrEnumerateSwapchainImages");
      sc.images.assign(count, {XR_TYPE_SWAPCHAIN_IMAGE_OPENGL_KHR});
      must(xrEnumerateSwapchainImages(sc.handle, count, &count, reinterpret_cast<XrSwapchainImageBaseHeader*>(sc.images.data())),
           "xrEnumerateSwapchainImages");
    }
  }

  XrPath path(const char* text) {
    XrPath p = XR_NULL_PATH;
    must(xrStringToPath(instance_, text, &p), "xrStringToPath");
    return p;
  }

  void createInputs() {
    handPaths_ = {path("/user/hand/left"), path("/user/hand/right")};
    XrActionSetCreateInfo setInfo{XR_TYPE_ACTION_SET_CREATE_INFO};
    std::strcpy(setInfo.actionSetName, "vaw");
    std::strcpy(setInfo.localizedActionSetName, "Assembly");
    must(xrCreateActionSet(instance_, &setInfo, &actionSet_), "xrCreateActionSet");
    const auto action = [&](XrActionType type, const char* id, const char* label) {
      XrActionCreateInfo info{XR_TYPE_ACTION_CREATE_INFO};
      info.actionType = type;
      std::strcpy(info.actionName, id);
      std::strcpy(info.localizedActionName, label);
      info.countSubactionPaths = 2;
      info.subactionPaths = handPaths_.data();
      XrAction a = XR_NULL_HANDLE;
      must(xrCreateAction(actionSet_, &info, &a), "xrCreateAction");
      return a;
    };
    grabAction_ = action(XR_ACTION_TYPE_BOOLEAN_INPUT, "grab", "Grab");
    gripAction_ = action(XR_ACTION_TYPE_POSE_INPUT, "grip", "Hand pose");
    // The KHR simple controller: every runtime binds it to whatever controllers it has.
    const XrActionSuggestedBinding bindings[] = {
        {grabAction_, path("/user/hand/left/input/select/click")},
        {grabAction_, path("/user/hand/right/input/select/click")},
        {gripAction_, path("/user/hand/left/input/grip/pose")},
        {gripAction_, path("/user/hand/right/input/grip/pose")},
    };
    XrInteractionProfileSuggestedBinding suggested{XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING};
    suggested.interactionProfile = path("/interaction_profiles/khr/simple_controller");
    suggested.countSuggestedBindings = 4;
    suggested.suggestedBindings = bindings;
    must(xrSuggestInteractionProfileBindings(instance_, &suggested), "xrSuggestInteractionProfileBindings");
    XrSessionActionSetsAttachInfo attach{XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO};
    attach.countActionSets = 1;
    attach.actionSets = &actionSet_;
    must(xrAttachSessionActionSets(session_, &attach), "xrAttachSessionActionSets");
    for (std::size_t h = 0; h < 2; ++h) {
      XrActionSpaceCreateInfo spaceInfo{XR_TYPE_ACTION_SPACE_CREATE_INFO};
      spaceInfo.action = gripAction_;
      spaceInfo.subactionPath = handPaths_[h];
      spaceInfo.poseInActionSpace = kIdentityPose;
      must(xrCreateActionSpace(session_, &spaceInfo, &gripSpaces_[h]), "xrCreateActionSpace");
    }
    if (info_.handTracking) {
      createHandTracker_ = proc<PFN_xrCreateHandTrackerEXT>("xrCreateHandTrackerEXT");
      destroyHandTracker_ = proc<PFN_xrDestroyHandTrackerEXT>("xrDestroyHandTrackerEXT");
      locateHandJoints_ = proc<PFN_xrLocateHandJointsEXT>("xrLocateHandJointsEXT");
      for (std::size_t h = 0; h < 2; ++h) {
        XrHandTrackerCreateInfoEXT info{XR_TYPE_HAND_TRACKER_CREATE_INFO_EXT};
        info.hand = h == 0 ? XR_HAND_LEFT_EXT : XR_HAND_RIGHT_EXT;
        info.handJointSet = XR_HAND_JOINT_SET_DEFAULT_EXT;
        must(createHandTracker_(session_, &info, &handTrackers_[h]), "xrCreateHandTrackerEXT");
      }
    } else {
      note(handTrackingExt_ ? "the headset of " + info_.name + " does not track hands: use the controllers (grip pose, "
                                  "select to grab)"
                            : "the OpenXR runtime " + info_.name + " does not offer hand tracking (XR_EXT_hand_tracking): "
                                  "use the controllers (grip pose, select to grab)",
           false);
    }
  }

  // ---- the running session ----

  void sessionStateChanged(XrSessionState s) {
    if (s == XR_SESSION_STATE_READY) {
      XrSessionBeginInfo begin{XR_TYPE_SESSION_BEGIN_INFO};
      begin.primaryViewConfigurationType = kViewConfig;
      if (ok(xrBeginSession(session_, &begin), "xrBeginSession")) running_ = true;
    } else if (s == XR_SESSION_STATE_STOPPING) {
      running_ = false;
      ok(xrEndSession(session_), "xrEndSession");
    } else if (s == XR_SESSION_STATE_EXITING) {
      running_ = false;
      finished_ = true;
    } else if (s == XR_SESSION_STATE_LOSS_PENDING) {
      fail(Failure::SessionLost, "the OpenXR runtime " + info_.name + " is losing the session (the headset was "
                                 "disconnected or its compositor restarted)");
    }
  }

  void interactionProfileChanged() {
    for (std::size_t h = 0; h < 2; ++h) {
      XrInteractionProfileState profile{XR_TYPE_INTERACTION_PROFILE_STATE};
      if (!ok(xrGetCurrentInteractionProfile(session_, handPaths_[h], &profile), "xrGetCurrentInteractionProfile")) return;
      if (profile.interactionProfile == XR_NULL_PATH) continue;
      char text[XR_MAX_PATH_LENGTH] = {};
      std::uint32_t length = 0;
      if (!ok(xrPathToString(instance_, profile.interactionProfile, sizeof text, &length, text), "xrPathToString")) return;
      note(std::string(h == 0 ? "left" : "right") + " controller: " + text, false);
    }
  }

  void syncActions() {
    XrActiveActionSet active{actionSet_, XR_NULL_PATH};
    XrActionsSyncInfo sync{XR_TYPE_ACTIONS_SYNC_INFO};
    sync.countActiveActionSets = 1;
    sync.activeActionSets = &active;
    const XrResult r = xrSyncActions(session_, &sync);
    if (!ok(r, "xrSyncActions")) return;
    for (std::size_t h = 0; h < 2; ++h) {
      XrActionStateGetInfo get{XR_TYPE_ACTION_STATE_GET_INFO};
      get.action = grabAction_;
      get.subactionPath = handPaths_[h];
      XrActionStateBoolean state{XR_TYPE_ACTION_STATE_BOOLEAN};
      select_[h] = r == XR_SUCCESS && ok(xrGetActionStateBoolean(session_, &get, &state), "xrGetActionStateBoolean") &&
                   state.isActive == XR_TRUE && state.currentState == XR_TRUE;
    }
  }

  bool locateJoints(std::size_t h, std::int64_t time, HandSample& hand) {
    std::array<XrHandJointLocationEXT, kJointCount> locations{};
    std::array<XrHandJointVelocityEXT, kJointCount> velocities{};
    XrHandJointVelocitiesEXT velocityInfo{XR_TYPE_HAND_JOINT_VELOCITIES_EXT};
    velocityInfo.jointCount = kJointCount;
    velocityInfo.jointVelocities = velocities.data();
    XrHandJointLocationsEXT locationInfo{XR_TYPE_HAND_JOINT_LOCATIONS_EXT};
    locationInfo.next = &velocityInfo;
    locationInfo.jointCount = kJointCount;
    locationInfo.jointLocations = locations.data();
    XrHandJointsLocateInfoEXT locate{XR_TYPE_HAND_JOINTS_LOCATE_INFO_EXT};
    locate.baseSpace = space_;
    locate.time = time;
    if (!ok(locateHandJoints_(handTrackers_[h], &locate, &locationInfo), "xrLocateHandJointsEXT")) return false;
    if (locationInfo.isActive != XR_TRUE) return false;
    for (int j : {kPalm, kThumbTip, kIndexTip})
      if (!located(locations[static_cast<std::size_t>(j)].locationFlags)) return false;
    const Eigen::Matrix3d rotation = worldFromSpace_.linear();
    for (std::size_t j = 0; j < kJointCount; ++j) {
      hand.joints[j] = worldFromSpace_ * toEigen(locations[j].pose);
      hand.radii[j] = locations[j].radius;
      const XrSpaceVelocityFlags f = velocities[j].velocityFlags;
      hand.linearValid[j] = (f & XR_SPACE_VELOCITY_LINEAR_VALID_BIT) != 0;
      hand.angularValid[j] = (f & XR_SPACE_VELOCITY_ANGULAR_VALID_BIT) != 0;
      hand.linear[j] = rotation * toEigen(velocities[j].linearVelocity);
      hand.angular[j] = rotation * toEigen(velocities[j].angularVelocity);
    }
    hand.source = HandSample::Source::Joints;
    return true;
  }

  void locateController(std::size_t h, std::int64_t time, HandSample& hand) {
    XrSpaceVelocity velocity{XR_TYPE_SPACE_VELOCITY};
    XrSpaceLocation location{XR_TYPE_SPACE_LOCATION};
    location.next = &velocity;
    if (!ok(xrLocateSpace(gripSpaces_[h], space_, time, &location), "xrLocateSpace")) return;
    if (!located(location.locationFlags)) return;
    hand.source = HandSample::Source::Controller;
    hand.joints[kPalm] = worldFromSpace_ * toEigen(location.pose);
    hand.radii[kPalm] = 0.04f;
    hand.linearValid[kPalm] = (velocity.velocityFlags & XR_SPACE_VELOCITY_LINEAR_VALID_BIT) != 0;
    hand.angularValid[kPalm] = (velocity.velocityFlags & XR_SPACE_VELOCITY_ANGULAR_VALID_BIT) != 0;
    hand.linear[kPalm] = worldFromSpace_.linear() * toEigen(velocity.linearVelocity);
    hand.angular[kPalm] = worldFromSpace_.linear() * toEigen(velocity.angularVelocity);
    hand.select = select_[h];
  }

  // Children go with their instance, but the GL objects must go while the context is current, and the
  // runtime is told in order (trackers, swapchains, spaces, session) so it can release what it holds.
  void destroy() {
    renderer_.reset();
    for (auto& t : handTrackers_)
      if (t != XR_NULL_HANDLE && destroyHandTracker_ != nullptr) destroyHandTracker_(t);
    handTrackers_ = {};
    for (auto& sc : swapchains_)
      if (sc.handle != XR_NULL_HANDLE) xrDestroySwapchain(sc.handle);
    swapchains_ = {};
    for (auto& s : gripSpaces_)
      if (s != XR_NULL_HANDLE) xrDestroySpace(s);
    gripSpaces_ = {};
    if (space_ != XR_NULL_HANDLE) xrDestroySpace(space_);
    space_ = XR_NULL_HANDLE;
    if (actionSet_ != XR_NULL_HANDLE) xrDestroyActionSet(actionSet_);
    actionSet_ = XR_NULL_HANDLE;
    if (session_ != XR_NULL_HANDLE) xrDestroySession(session_);
    session_ = XR_NULL_HANDLE;
    if (messenger_ != XR_NULL_HANDLE && destroyMessenger_ != nullptr) destroyMessenger_(messenger_);
    messenger_ = XR_NULL_HANDLE;
    if (instance_ != XR_NULL_HANDLE) xrDestroyInstance(instance_);
    instance_ = XR_NULL_HANDLE;
    running_ = false;
  }

  StartOptions options_;
  RuntimeInfo info_;
  XrInstance instance_ = XR_NULL_HANDLE;
  XrSystemId system_ = XR_NULL_SYSTEM_ID;
  XrSession session_ = XR_NULL_HANDLE;
  XrSpace space_ = XR_NULL_HANDLE;
  XrDebugUtilsMessengerEXT messenger_ = XR_NULL_HANDLE;
  PFN_xrDestroyDebugUtilsMessengerEXT destroyMessenger_ = nullptr;
  XrEnvironmentBlendMode blendMode_ = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
  std::array<Swapchain, 2> swapchains_;
  Eigen::Isometry3d worldFromSpace_ = Eigen::Isometry3d::Identity();
  std::optional<Eigen::Isometry3d> headInSpace_;  // the last frame's, for recenter()
  XrSessionState state_ = XR_SESSION_STATE_UNKNOWN;
  bool running_ = false, finished_ = false;
  std::optional<Event> pendingFailure_;
  std::mutex messagesMutex_;  // the debug messenger may be called from the runtime's threads
  std::vector<std::pair<std::string, bool>> messages_;

  std::array<XrPath, 2> handPaths_{};
  XrActionSet actionSet_ = XR_NULL_HANDLE;
  XrAction grabAction_ = XR_NULL_HANDLE, gripAction_ = XR_NULL_HANDLE;
  std::array<XrSpace, 2> gripSpaces_{};
  std::array<bool, 2> select_{};
  bool handTrackingExt_ = false;
  PFN_xrCreateHandTrackerEXT createHandTracker_ = nullptr;
  PFN_xrDestroyHandTrackerEXT destroyHandTracker_ = nullptr;
  PFN_xrLocateHandJointsEXT locateHandJoints_ = nullptr;
  std::array<XrHandTrackerEXT, 2> handTrackers_{};

  std::unique_ptr<GlRenderer> renderer_;
};

}  // namespace

}  // namespace vaw::xr

extern "C" {
__attribute__((visibility("default"))) int vaw_xr_abi_version() { return vaw::xr::kAbiVersion; }
__attribute__((visibility("default"))) vaw::xr::Backend* vaw_xr_create_backend() { return new vaw::xr::OpenXrBackend(); }
}
