// The simulated OpenXR runtime: what the loader finds through the manifest that XR_RUNTIME_JSON names, and
// what vaw's VR mode talks to in the tests (tests/xr). It plays back the script that VAW_SIMXR_SCRIPT names
// (sim_script.hpp), drives the session's states as a runtime does, hands out OpenGL swapchain images, and
// records what the application did (sim_runtime.hpp).
//
// It follows the specification rather than what vaw happens to call: every handle is checked for being alive
// and of the right type, every input structure for its type, and the call order of the session and frame
// loop (begin only when READY, end only when STOPPING, wait/begin/end frame in order, acquire/wait/release
// swapchain images in order, the graphics requirements asked before the session, action sets attached
// before syncing). A breach answers with the result the specification names and is recorded as a violation,
// which the tests assert there are none of.
#include "sim_runtime.hpp"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

// Eigen (through sim_script.hpp) before Xlib: Xlib's macros (Success, None) break Eigen's headers.
#include "sim_script.hpp"

#include <GL/gl.h>
#include <GL/glx.h>
#include <X11/Xlib.h>

#define XR_USE_PLATFORM_XLIB
#define XR_USE_GRAPHICS_API_OPENGL
#include <openxr/openxr_platform.h>
#include <openxr/openxr_reflection.h>

// The loader's side of the runtime interface (the OpenXR loader documentation, "Runtime Interface
// Negotiation"). libopenxr-dev 1.0.20 does not install openxr_loader_negotiation.h, so the two structures
// are declared here as the loader lays them out.
extern "C" {
enum XrLoaderInterfaceStructs {
  XR_LOADER_INTERFACE_STRUCT_UNINTIALIZED = 0,
  XR_LOADER_INTERFACE_STRUCT_LOADER_INFO,
  XR_LOADER_INTERFACE_STRUCT_API_LAYER_REQUEST,
  XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST,
};
struct XrNegotiateLoaderInfo {
  XrLoaderInterfaceStructs structType;
  uint32_t structVersion;
  size_t structSize;
  uint32_t minInterfaceVersion, maxInterfaceVersion;
  XrVersion minApiVersion, maxApiVersion;
};
struct XrNegotiateRuntimeRequest {
  XrLoaderInterfaceStructs structType;
  uint32_t structVersion;
  size_t structSize;
  uint32_t runtimeInterfaceVersion;
  XrVersion runtimeApiVersion;
  PFN_xrGetInstanceProcAddr getInstanceProcAddr;
};
}

namespace vaw::simxr {
namespace {

constexpr const char* kRuntimeName = "vaw simulated runtime";
constexpr XrSystemId kSystem = 0x5157;
constexpr std::int64_t kEpoch = 1'000'000'000;  // XrTime of script time 0 (ns)
constexpr std::uint32_t kImagesPerSwapchain = 3;
constexpr std::int64_t kGlRgba8 = 0x8058, kGlSrgb8Alpha8 = 0x8C43;
constexpr double kIpd = 0.064;  // m between the eyes
constexpr XrEnvironmentBlendMode kBlend = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
constexpr const char* kSimpleController = "/interaction_profiles/khr/simple_controller";

Record g_record;

// ---- handles ----

enum class Kind { Instance, Session, Space, Swapchain, ActionSet, Action, HandTracker };

struct Object {
  explicit Object(Kind k, Object* p) : kind(k), parent(p) {}
  virtual ~Object() = default;
  Kind kind;
  Object* parent;
};

struct Session;

struct Instance : Object {
  using Object::Object;
  Script script;
  bool handTracking = false, opengl = false;
  bool systemAsked = false, requirementsAsked = false, lost = false;
  std::vector<std::string> paths{""};  // XrPath n is paths[n]; 0 is XR_NULL_PATH
  std::deque<XrEventDataBuffer> events;
  std::map<XrPath, std::vector<std::pair<struct Action*, XrPath>>> suggested;  // profile -> (action, binding)
  Session* session = nullptr;
};

struct ActionSet : Object {
  using Object::Object;
  bool attached = false;
};

struct Action : Object {
  using Object::Object;
  XrActionType type = XR_ACTION_TYPE_BOOLEAN_INPUT;
  std::vector<XrPath> subactions;
};

struct Swapchain : Object {
  using Object::Object;
  XrSwapchainCreateInfo info{};
  std::vector<GLuint> textures;
  std::deque<std::uint32_t> acquired;  // in acquisition order; the front is waited on, then released
  bool waited = false;
  std::optional<std::uint32_t> released;  // the image most recently released (what a layer shows)
  std::uint32_t next = 0;
};

struct Space : Object {
  using Object::Object;
  enum class Type { View, Local, Stage, Action } type = Type::Stage;
  Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();  // poseInReferenceSpace / poseInActionSpace
  Action* action = nullptr;
  XrPath subaction = XR_NULL_PATH;
};

struct HandTracker : Object {
  using Object::Object;
  int hand = 0;
};

struct Session : Object {
  using Object::Object;
  Display* display = nullptr;
  GLXContext context = nullptr;
  GLXDrawable drawable = 0;
  XrSessionState state = XR_SESSION_STATE_UNKNOWN;      // the runtime's latest (queued)
  XrSessionState delivered = XR_SESSION_STATE_UNKNOWN;  // what the application has been told by xrPollEvent
  bool running = false, exitRequested = false, windingDown = false, lost = false, actionSetsAttached = false;
  std::vector<ActionSet*> attached;
  std::int64_t frames = 0;  // frames waited on
  std::optional<std::int64_t> waitedTime;  // display time of a frame waited on and not begun
  std::optional<std::int64_t> begunTime;   // of a frame begun and not ended
  std::int64_t lastDisplayTime = 0;
  std::int64_t endedFrames = 0;
  std::size_t nextCapture = 0;
  std::array<bool, 2> select{};   // synced action state of the controllers
  std::array<bool, 2> focusedSync{};
  bool synced = false;
  std::array<XrPath, 2> profile{};  // current interaction profile per hand
};

std::unordered_map<const void*, std::unique_ptr<Object>> g_objects;
Instance* g_instance = nullptr;

void violation(const std::string& what) { g_record.violations.push_back(what); }

template <class T>
T* lookup(const void* handle, Kind kind, const char* fn) {
  auto it = g_objects.find(handle);
  if (handle == nullptr || it == g_objects.end() || it->second->kind != kind) {
    violation(std::string(fn) + ": invalid handle");
    return nullptr;
  }
  return static_cast<T*>(it->second.get());
}

template <class T, class H>
H handleOf(T* object) {
  return reinterpret_cast<H>(object);
}

template <class T>
T* create(Kind kind, Object* parent) {
  auto object = std::make_unique<T>(kind, parent);
  T* raw = object.get();
  g_objects.emplace(raw, std::move(object));
  g_record.liveHandles = g_objects.size();
  return raw;
}

bool descends(const Object* o, const Object* ancestor) {
  for (; o != nullptr; o = o->parent)
    if (o == ancestor) return true;
  return false;
}

void destroy(Object* root);

// Swapchain textures go while a context of the session is current (the application's, as the binding says).
struct CurrentContext {
  explicit CurrentContext(const Session* s) {
    if (s == nullptr || s->display == nullptr || glXGetCurrentContext() == s->context) return;
    display = glXGetCurrentDisplay();
    context = glXGetCurrentContext();
    draw = glXGetCurrentDrawable();
    read = glXGetCurrentReadDrawable();
    switched = glXMakeContextCurrent(s->display, s->drawable, s->drawable, s->context) == True;
  }
  ~CurrentContext() {
    if (switched && display != nullptr) glXMakeContextCurrent(display, draw, read, context);
  }
  CurrentContext(const CurrentContext&) = delete;
  CurrentContext& operator=(const CurrentContext&) = delete;
  Display* display = nullptr;
  GLXContext context = nullptr;
  GLXDrawable draw = 0, read = 0;
  bool switched = false;
};

void destroy(Object* root) {
  std::vector<Object*> doomed;
  for (auto& [key, object] : g_objects)
    if (descends(object.get(), root)) doomed.push_back(object.get());
  for (Object* o : doomed) {
    if (o->kind == Kind::Swapchain) {
      auto* sc = static_cast<Swapchain*>(o);
      auto* session = static_cast<Session*>(sc->parent);
      CurrentContext current(session);
      if (!sc->textures.empty() && glXGetCurrentContext() != nullptr)
        glDeleteTextures(static_cast<GLsizei>(sc->textures.size()), sc->textures.data());
    }
    if (o->kind == Kind::Session) {
      ++g_record.sessionsDestroyed;
      if (g_instance != nullptr && g_instance->session == o) g_instance->session = nullptr;
    }
    if (o->kind == Kind::Instance) {
      ++g_record.instancesDestroyed;
      if (g_instance == o) g_instance = nullptr;
    }
  }
  for (Object* o : doomed) g_objects.erase(o);
  g_record.liveHandles = g_objects.size();
}

// ---- recording calls ----

XrSessionState knownState() {
  return g_instance != nullptr && g_instance->session != nullptr ? g_instance->session->delivered : XR_SESSION_STATE_UNKNOWN;
}

XrResult record(const char* fn, XrResult r) {
  g_record.calls.push_back({fn, r, knownState()});
  return r;
}

// An input structure of the wrong type is the application's error.
bool typed(const void* s, XrStructureType type, const char* fn, const char* what) {
  if (s == nullptr) {
    violation(std::string(fn) + ": " + what + " is null");
    return false;
  }
  if (*static_cast<const XrStructureType*>(s) != type) {
    violation(std::string(fn) + ": " + what + " has type " + std::to_string(*static_cast<const XrStructureType*>(s)));
    return false;
  }
  return true;
}

// The two-call idiom for arrays (the specification, "Buffer Size Parameters").
template <class T, class Fill>
XrResult enumerate(std::uint32_t capacity, std::uint32_t* count, T* out, std::uint32_t n, Fill fill, const char* fn) {
  if (count == nullptr) {
    violation(std::string(fn) + ": count output is null");
    return XR_ERROR_VALIDATION_FAILURE;
  }
  *count = n;
  if (capacity == 0) return XR_SUCCESS;
  if (capacity < n) return XR_ERROR_SIZE_INSUFFICIENT;
  if (out == nullptr) {
    violation(std::string(fn) + ": array is null");
    return XR_ERROR_VALIDATION_FAILURE;
  }
  for (std::uint32_t i = 0; i < n; ++i) fill(out[i], i);
  return XR_SUCCESS;
}

// ---- time and poses ----

double scriptTime(XrTime t) { return static_cast<double>(t - kEpoch) * 1e-9; }
std::int64_t period(const Script& s) { return static_cast<std::int64_t>(std::llround(1e9 / s.refresh)); }

XrPosef toXr(const Eigen::Isometry3d& p) {
  const Eigen::Quaterniond q(p.linear());
  XrPosef out;
  out.orientation = {static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()), static_cast<float>(q.w())};
  out.position = {static_cast<float>(p.translation().x()), static_cast<float>(p.translation().y()),
                  static_cast<float>(p.translation().z())};
  return out;
}

Eigen::Isometry3d fromXr(const XrPosef& p) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = Eigen::Quaterniond(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z).normalized().toRotationMatrix();
  out.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return out;
}

XrVector3f toXr(const Eigen::Vector3d& v) { return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())}; }

bool validPose(const XrPosef& p) {
  const double n = std::sqrt(p.orientation.x * p.orientation.x + p.orientation.y * p.orientation.y +
                             p.orientation.z * p.orientation.z + p.orientation.w * p.orientation.w);
  return std::abs(n - 1.0) < 1e-3;  // the specification's "unit quaternion" within a float's reach
}

// A space's pose in STAGE at script time t; none when it is not tracked then.
std::optional<Eigen::Isometry3d> stagePose(const Instance& in, const Session& s, const Space& space, double t) {
  const Script& script = in.script;
  switch (space.type) {
    case Space::Type::Stage: return space.offset;
    case Space::Type::Local: return script.localOrigin * space.offset;
    case Space::Type::View: return script.headAt(t) * space.offset;
    case Space::Type::Action: {
      // A controller's pose is input: tracked only while the session has input focus and a profile is bound.
      if (space.action == nullptr || !s.running || s.delivered != XR_SESSION_STATE_FOCUSED) return std::nullopt;
      for (int h = 0; h < 2; ++h) {
        if (in.paths[space.subaction] != (h == 0 ? "/user/hand/left" : "/user/hand/right")) continue;
        if (s.profile[static_cast<std::size_t>(h)] == XR_NULL_PATH) return std::nullopt;
        const ControllerPose c = script.controllerAt(h, t);
        if (!c.active) return std::nullopt;
        return c.pose * space.offset;
      }
      return std::nullopt;
    }
  }
  return std::nullopt;
}

// Velocities by central differences over a millisecond of the script (the runtime "measures" them).
template <class PoseAt>
std::pair<Eigen::Vector3d, Eigen::Vector3d> velocityOf(PoseAt at, double t) {
  constexpr double dt = 1e-3;
  const Eigen::Isometry3d a = at(t - dt), b = at(t + dt);
  const Eigen::Vector3d linear = (b.translation() - a.translation()) / (2 * dt);
  const Eigen::AngleAxisd turn(Eigen::Quaterniond(b.linear() * a.linear().transpose()));
  return {linear, turn.axis() * turn.angle() / (2 * dt)};
}

// ---- events and session states ----

void push(Instance& in, const XrEventDataBuffer& e) { in.events.push_back(e); }

void queueState(Session& s, XrSessionState state, XrTime time) {
  if (g_instance == nullptr) return;
  s.state = state;
  XrEventDataBuffer buffer{XR_TYPE_EVENT_DATA_BUFFER};
  auto& e = *reinterpret_cast<XrEventDataSessionStateChanged*>(&buffer);
  e.type = XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED;
  e.next = nullptr;
  e.session = handleOf<Session, XrSession>(&s);
  e.state = state;
  e.time = time;
  push(*g_instance, buffer);
}

void queueProfileChanged(Session& s) {
  XrEventDataBuffer buffer{XR_TYPE_EVENT_DATA_BUFFER};
  auto& e = *reinterpret_cast<XrEventDataInteractionProfileChanged*>(&buffer);
  e.type = XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED;
  e.next = nullptr;
  e.session = handleOf<Session, XrSession>(&s);
  push(*g_instance, buffer);
}

// From FOCUSED down to STOPPING, one state at a time as the specification orders them.
void windDown(Session& s, XrTime time) {
  if (s.windingDown) return;
  s.windingDown = true;
  if (s.state == XR_SESSION_STATE_FOCUSED) queueState(s, XR_SESSION_STATE_VISIBLE, time);
  if (s.state == XR_SESSION_STATE_VISIBLE) queueState(s, XR_SESSION_STATE_SYNCHRONIZED, time);
  queueState(s, XR_SESSION_STATE_STOPPING, time);
}

// What the script says happens by display time `time`.
void scriptEvents(Instance& in, Session& s, XrTime time) {
  const double t = scriptTime(time);
  if (in.script.loseInstanceAt && t >= *in.script.loseInstanceAt && !in.lost) {
    in.lost = true;
    XrEventDataBuffer buffer{XR_TYPE_EVENT_DATA_BUFFER};
    auto& e = *reinterpret_cast<XrEventDataInstanceLossPending*>(&buffer);
    e.type = XR_TYPE_EVENT_DATA_INSTANCE_LOSS_PENDING;
    e.next = nullptr;
    e.lossTime = time;
    push(in, buffer);
    return;
  }
  if (in.script.loseSessionAt && t >= *in.script.loseSessionAt && !s.lost) {
    s.lost = true;
    queueState(s, XR_SESSION_STATE_LOSS_PENDING, time);
    return;
  }
  if (t >= in.script.duration && s.running) windDown(s, time);
}

// ---- the functions ----

#define CHECK_INSTANCE(fn, handle)                                   \
  Instance* in = lookup<Instance>(handle, Kind::Instance, fn);       \
  if (in == nullptr) return record(fn, XR_ERROR_HANDLE_INVALID);     \
  if (in->lost) return record(fn, XR_ERROR_INSTANCE_LOST);

#define CHECK_SESSION(fn, handle)                                                  \
  Session* s = lookup<Session>(handle, Kind::Session, fn);                          \
  if (s == nullptr) return record(fn, XR_ERROR_HANDLE_INVALID);                     \
  Instance* in = static_cast<Instance*>(s->parent);                                 \
  if (in->lost) return record(fn, XR_ERROR_INSTANCE_LOST);                          \
  if (s->lost) return record(fn, XR_ERROR_SESSION_LOST);

#define REQUIRE(cond, fn, what)                                 \
  do {                                                          \
    if (!(cond)) {                                              \
      violation(std::string(fn) + ": " + (what));               \
      return record(fn, XR_ERROR_VALIDATION_FAILURE);           \
    }                                                           \
  } while (false)

XrResult XRAPI_CALL enumerateExtensions(const char* layer, std::uint32_t capacity, std::uint32_t* count,
                                        XrExtensionProperties* out) {
  constexpr const char* fn = "xrEnumerateInstanceExtensionProperties";
  if (layer != nullptr) return record(fn, XR_ERROR_API_LAYER_NOT_PRESENT);
  // The script is read here too: a runtime without hand tracking does not list it.
  bool hands = true;
  if (const char* file = std::getenv("VAW_SIMXR_SCRIPT")) {
    try {
      hands = Script::load(file).handTracking;
    } catch (const std::exception&) {
      return record(fn, XR_ERROR_RUNTIME_FAILURE);
    }
  }
  std::vector<std::pair<const char*, std::uint32_t>> exts{{XR_KHR_OPENGL_ENABLE_EXTENSION_NAME, XR_KHR_opengl_enable_SPEC_VERSION}};
  if (hands) exts.emplace_back(XR_EXT_HAND_TRACKING_EXTENSION_NAME, XR_EXT_hand_tracking_SPEC_VERSION);
  for (std::uint32_t i = 0; capacity > 0 && out != nullptr && i < capacity; ++i)
    if (!typed(&out[i], XR_TYPE_EXTENSION_PROPERTIES, fn, "properties")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  return record(fn, enumerate(capacity, count, out, static_cast<std::uint32_t>(exts.size()),
                              [&](XrExtensionProperties& p, std::uint32_t i) {
                                std::strncpy(p.extensionName, exts[i].first, XR_MAX_EXTENSION_NAME_SIZE - 1);
                                p.extensionVersion = exts[i].second;
                              },
                              fn));
}

XrResult XRAPI_CALL enumerateLayers(std::uint32_t, std::uint32_t* count, XrApiLayerProperties*) {
  if (count == nullptr) return record("xrEnumerateApiLayerProperties", XR_ERROR_VALIDATION_FAILURE);
  *count = 0;
  return record("xrEnumerateApiLayerProperties", XR_SUCCESS);
}

XrResult XRAPI_CALL createInstance(const XrInstanceCreateInfo* info, XrInstance* instance) {
  constexpr const char* fn = "xrCreateInstance";
  if (!typed(info, XR_TYPE_INSTANCE_CREATE_INFO, fn, "createInfo") || instance == nullptr)
    return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (XR_VERSION_MAJOR(info->applicationInfo.apiVersion) != 1) return record(fn, XR_ERROR_API_VERSION_UNSUPPORTED);
  if (info->applicationInfo.applicationName[0] == '\0') return record(fn, XR_ERROR_NAME_INVALID);
  if (g_instance != nullptr) return record(fn, XR_ERROR_LIMIT_REACHED);  // one at a time, as a headset's runtime
  Script script;
  const char* file = std::getenv("VAW_SIMXR_SCRIPT");
  try {
    if (file != nullptr) script = Script::load(file);
  } catch (const std::exception& e) {
    violation(std::string("VAW_SIMXR_SCRIPT: ") + e.what());
    return record(fn, XR_ERROR_RUNTIME_FAILURE);
  }
  bool opengl = false, hands = false;
  for (std::uint32_t i = 0; i < info->enabledExtensionCount; ++i) {
    const std::string name = info->enabledExtensionNames[i];
    if (name == XR_KHR_OPENGL_ENABLE_EXTENSION_NAME) opengl = true;
    else if (name == XR_EXT_HAND_TRACKING_EXTENSION_NAME && script.handTracking) hands = true;
    else return record(fn, XR_ERROR_EXTENSION_NOT_PRESENT);
  }
  if (info->enabledApiLayerCount != 0) return record(fn, XR_ERROR_API_LAYER_NOT_PRESENT);
  auto* object = create<Instance>(Kind::Instance, nullptr);
  object->script = std::move(script);
  object->opengl = opengl;
  object->handTracking = hands;
  g_instance = object;
  g_record.script = file != nullptr ? file : "";
  ++g_record.instancesCreated;
  *instance = handleOf<Instance, XrInstance>(object);
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL destroyInstance(XrInstance instance) {
  Instance* in = lookup<Instance>(instance, Kind::Instance, "xrDestroyInstance");
  if (in == nullptr) return record("xrDestroyInstance", XR_ERROR_HANDLE_INVALID);
  destroy(in);
  return record("xrDestroyInstance", XR_SUCCESS);
}

XrResult XRAPI_CALL getInstanceProperties(XrInstance instance, XrInstanceProperties* props) {
  constexpr const char* fn = "xrGetInstanceProperties";
  CHECK_INSTANCE(fn, instance);
  if (!typed(props, XR_TYPE_INSTANCE_PROPERTIES, fn, "properties")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  props->runtimeVersion = XR_MAKE_VERSION(0, 1, 0);
  std::strncpy(props->runtimeName, kRuntimeName, XR_MAX_RUNTIME_NAME_SIZE - 1);
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL pollEvent(XrInstance instance, XrEventDataBuffer* buffer) {
  constexpr const char* fn = "xrPollEvent";
  Instance* in = lookup<Instance>(instance, Kind::Instance, fn);
  if (in == nullptr) return record(fn, XR_ERROR_HANDLE_INVALID);
  if (!typed(buffer, XR_TYPE_EVENT_DATA_BUFFER, fn, "eventData")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (in->events.empty()) {
    // Polling is allowed after an instance loss pending event; the loss itself then comes as the result.
    if (in->lost) return record(fn, XR_ERROR_INSTANCE_LOST);
    return record(fn, XR_EVENT_UNAVAILABLE);
  }
  *buffer = in->events.front();
  in->events.pop_front();
  if (buffer->type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED) {
    const auto& e = *reinterpret_cast<const XrEventDataSessionStateChanged*>(buffer);
    if (in->session != nullptr && e.session == handleOf<Session, XrSession>(in->session)) in->session->delivered = e.state;
    g_record.states.push_back(e.state);
  }
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL resultToString(XrInstance instance, XrResult value, char buffer[XR_MAX_RESULT_STRING_SIZE]) {
  Instance* in = lookup<Instance>(instance, Kind::Instance, "xrResultToString");
  if (in == nullptr) return XR_ERROR_HANDLE_INVALID;
  const char* name = nullptr;
#define VAW_RESULT_NAME(n, v) \
  case v: name = #n; break;
  switch (value) {
    XR_LIST_ENUM_XrResult(VAW_RESULT_NAME) default: break;
  }
#undef VAW_RESULT_NAME
  const std::string text = name != nullptr ? name : (value < 0 ? "XR_UNKNOWN_FAILURE_" : "XR_UNKNOWN_SUCCESS_") + std::to_string(value);
  std::strncpy(buffer, text.c_str(), XR_MAX_RESULT_STRING_SIZE - 1);
  buffer[XR_MAX_RESULT_STRING_SIZE - 1] = '\0';
  return XR_SUCCESS;
}

XrResult XRAPI_CALL structureTypeToString(XrInstance instance, XrStructureType value, char buffer[XR_MAX_STRUCTURE_NAME_SIZE]) {
  Instance* in = lookup<Instance>(instance, Kind::Instance, "xrStructureTypeToString");
  if (in == nullptr) return XR_ERROR_HANDLE_INVALID;
  const char* name = nullptr;
#define VAW_TYPE_NAME(n, v) \
  case v: name = #n; break;
  switch (value) {
    XR_LIST_ENUM_XrStructureType(VAW_TYPE_NAME) default: break;
  }
#undef VAW_TYPE_NAME
  const std::string text = name != nullptr ? name : "XR_UNKNOWN_STRUCTURE_TYPE_" + std::to_string(value);
  std::strncpy(buffer, text.c_str(), XR_MAX_STRUCTURE_NAME_SIZE - 1);
  buffer[XR_MAX_STRUCTURE_NAME_SIZE - 1] = '\0';
  return XR_SUCCESS;
}

XrResult XRAPI_CALL getSystem(XrInstance instance, const XrSystemGetInfo* info, XrSystemId* system) {
  constexpr const char* fn = "xrGetSystem";
  CHECK_INSTANCE(fn, instance);
  if (!typed(info, XR_TYPE_SYSTEM_GET_INFO, fn, "getInfo") || system == nullptr) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (info->formFactor != XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY) return record(fn, XR_ERROR_FORM_FACTOR_UNSUPPORTED);
  if (!in->script.headset) return record(fn, XR_ERROR_FORM_FACTOR_UNAVAILABLE);
  in->systemAsked = true;
  *system = kSystem;
  return record(fn, XR_SUCCESS);
}

bool knownSystem(Instance& in, XrSystemId system, const char* fn) {
  if (system == kSystem && in.systemAsked) return true;
  violation(std::string(fn) + ": systemId not from xrGetSystem");
  return false;
}

XrResult XRAPI_CALL getSystemProperties(XrInstance instance, XrSystemId system, XrSystemProperties* props) {
  constexpr const char* fn = "xrGetSystemProperties";
  CHECK_INSTANCE(fn, instance);
  if (!knownSystem(*in, system, fn)) return record(fn, XR_ERROR_SYSTEM_INVALID);
  if (!typed(props, XR_TYPE_SYSTEM_PROPERTIES, fn, "properties")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  props->systemId = system;
  props->vendorId = 0x5157;
  std::strncpy(props->systemName, "scripted headset", XR_MAX_SYSTEM_NAME_SIZE - 1);
  props->graphicsProperties = {static_cast<std::uint32_t>(in->script.eyeWidth * 2), static_cast<std::uint32_t>(in->script.eyeHeight * 2), 16};
  props->trackingProperties = {XR_TRUE, XR_TRUE};
  for (auto* next = static_cast<XrBaseOutStructure*>(props->next); next != nullptr; next = next->next) {
    if (next->type == XR_TYPE_SYSTEM_HAND_TRACKING_PROPERTIES_EXT) {
      if (!in->handTracking) {
        violation(std::string(fn) + ": XrSystemHandTrackingPropertiesEXT chained without enabling XR_EXT_hand_tracking");
        return record(fn, XR_ERROR_VALIDATION_FAILURE);
      }
      reinterpret_cast<XrSystemHandTrackingPropertiesEXT*>(next)->supportsHandTracking = XR_TRUE;
    }
  }
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL enumerateBlendModes(XrInstance instance, XrSystemId system, XrViewConfigurationType config,
                                        std::uint32_t capacity, std::uint32_t* count, XrEnvironmentBlendMode* modes) {
  constexpr const char* fn = "xrEnumerateEnvironmentBlendModes";
  CHECK_INSTANCE(fn, instance);
  if (!knownSystem(*in, system, fn)) return record(fn, XR_ERROR_SYSTEM_INVALID);
  if (config != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO) return record(fn, XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED);
  return record(fn, enumerate(capacity, count, modes, 1, [](XrEnvironmentBlendMode& m, std::uint32_t) { m = kBlend; }, fn));
}

XrResult XRAPI_CALL enumerateViewConfigurations(XrInstance instance, XrSystemId system, std::uint32_t capacity,
                                                std::uint32_t* count, XrViewConfigurationType* out) {
  constexpr const char* fn = "xrEnumerateViewConfigurations";
  CHECK_INSTANCE(fn, instance);
  if (!knownSystem(*in, system, fn)) return record(fn, XR_ERROR_SYSTEM_INVALID);
  return record(fn, enumerate(capacity, count, out, 1,
                              [](XrViewConfigurationType& t, std::uint32_t) { t = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO; }, fn));
}

XrResult XRAPI_CALL getViewConfigurationProperties(XrInstance instance, XrSystemId system, XrViewConfigurationType config,
                                                   XrViewConfigurationProperties* props) {
  constexpr const char* fn = "xrGetViewConfigurationProperties";
  CHECK_INSTANCE(fn, instance);
  if (!knownSystem(*in, system, fn)) return record(fn, XR_ERROR_SYSTEM_INVALID);
  if (config != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO) return record(fn, XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED);
  if (!typed(props, XR_TYPE_VIEW_CONFIGURATION_PROPERTIES, fn, "properties")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  props->viewConfigurationType = config;
  props->fovMutable = XR_FALSE;
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL enumerateViewConfigurationViews(XrInstance instance, XrSystemId system, XrViewConfigurationType config,
                                                    std::uint32_t capacity, std::uint32_t* count, XrViewConfigurationView* views) {
  constexpr const char* fn = "xrEnumerateViewConfigurationViews";
  CHECK_INSTANCE(fn, instance);
  if (!knownSystem(*in, system, fn)) return record(fn, XR_ERROR_SYSTEM_INVALID);
  if (config != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO) return record(fn, XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED);
  for (std::uint32_t i = 0; views != nullptr && i < std::min(capacity, 2u); ++i)
    if (!typed(&views[i], XR_TYPE_VIEW_CONFIGURATION_VIEW, fn, "views")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  const Script& sc = in->script;
  return record(fn, enumerate(capacity, count, views, 2,
                              [&](XrViewConfigurationView& v, std::uint32_t) {
                                v.recommendedImageRectWidth = static_cast<std::uint32_t>(sc.eyeWidth);
                                v.recommendedImageRectHeight = static_cast<std::uint32_t>(sc.eyeHeight);
                                v.maxImageRectWidth = static_cast<std::uint32_t>(sc.eyeWidth * 2);
                                v.maxImageRectHeight = static_cast<std::uint32_t>(sc.eyeHeight * 2);
                                v.recommendedSwapchainSampleCount = 1;
                                v.maxSwapchainSampleCount = 4;
                              },
                              fn));
}

XrResult XRAPI_CALL getOpenGLRequirements(XrInstance instance, XrSystemId system, XrGraphicsRequirementsOpenGLKHR* req) {
  constexpr const char* fn = "xrGetOpenGLGraphicsRequirementsKHR";
  CHECK_INSTANCE(fn, instance);
  if (!knownSystem(*in, system, fn)) return record(fn, XR_ERROR_SYSTEM_INVALID);
  if (!typed(req, XR_TYPE_GRAPHICS_REQUIREMENTS_OPENGL_KHR, fn, "graphicsRequirements")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  req->minApiVersionSupported = XR_MAKE_VERSION(3, 3, 0);
  req->maxApiVersionSupported = XR_MAKE_VERSION(4, 6, 0);
  in->requirementsAsked = true;
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL createSession(XrInstance instance, const XrSessionCreateInfo* info, XrSession* session) {
  constexpr const char* fn = "xrCreateSession";
  CHECK_INSTANCE(fn, instance);
  if (!typed(info, XR_TYPE_SESSION_CREATE_INFO, fn, "createInfo") || session == nullptr) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (!knownSystem(*in, info->systemId, fn)) return record(fn, XR_ERROR_SYSTEM_INVALID);
  if (!in->requirementsAsked) {
    violation(std::string(fn) + ": xrGetOpenGLGraphicsRequirementsKHR was not called first");
    return record(fn, XR_ERROR_GRAPHICS_REQUIREMENTS_CALL_MISSING);
  }
  const auto* binding = static_cast<const XrGraphicsBindingOpenGLXlibKHR*>(info->next);
  if (!in->opengl || binding == nullptr || binding->type != XR_TYPE_GRAPHICS_BINDING_OPENGL_XLIB_KHR) {
    violation(std::string(fn) + ": no XrGraphicsBindingOpenGLXlibKHR in the next chain");
    return record(fn, XR_ERROR_GRAPHICS_DEVICE_INVALID);
  }
  if (binding->xDisplay == nullptr || binding->glxContext == nullptr || binding->glxFBConfig == nullptr) {
    violation(std::string(fn) + ": the graphics binding names no display, context or framebuffer configuration");
    return record(fn, XR_ERROR_GRAPHICS_DEVICE_INVALID);
  }
  if (in->session != nullptr) return record(fn, XR_ERROR_LIMIT_REACHED);
  auto* s = create<Session>(Kind::Session, in);
  s->display = binding->xDisplay;
  s->context = binding->glxContext;
  s->drawable = binding->glxDrawable;
  in->session = s;
  ++g_record.sessionsCreated;
  *session = handleOf<Session, XrSession>(s);
  queueState(*s, XR_SESSION_STATE_IDLE, kEpoch);
  queueState(*s, XR_SESSION_STATE_READY, kEpoch);
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL destroySession(XrSession session) {
  Session* s = lookup<Session>(session, Kind::Session, "xrDestroySession");
  if (s == nullptr) return record("xrDestroySession", XR_ERROR_HANDLE_INVALID);
  // Events of a destroyed session are not delivered.
  if (g_instance != nullptr) {
    std::erase_if(g_instance->events, [&](const XrEventDataBuffer& e) {
      return e.type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED &&
             reinterpret_cast<const XrEventDataSessionStateChanged*>(&e)->session == session;
    });
  }
  const XrResult r = record("xrDestroySession", XR_SUCCESS);
  destroy(s);
  return r;
}

XrResult XRAPI_CALL beginSession(XrSession session, const XrSessionBeginInfo* info) {
  constexpr const char* fn = "xrBeginSession";
  CHECK_SESSION(fn, session);
  if (!typed(info, XR_TYPE_SESSION_BEGIN_INFO, fn, "beginInfo")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (info->primaryViewConfigurationType != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO)
    return record(fn, XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED);
  if (s->running) {
    violation(std::string(fn) + ": the session is already running");
    return record(fn, XR_ERROR_SESSION_RUNNING);
  }
  if (s->delivered != XR_SESSION_STATE_READY) {
    violation(std::string(fn) + ": called before the READY state was delivered");
    return record(fn, XR_ERROR_SESSION_NOT_READY);
  }
  s->running = true;
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL endSession(XrSession session) {
  constexpr const char* fn = "xrEndSession";
  CHECK_SESSION(fn, session);
  if (!s->running) {
    violation(std::string(fn) + ": the session is not running");
    return record(fn, XR_ERROR_SESSION_NOT_RUNNING);
  }
  if (s->delivered != XR_SESSION_STATE_STOPPING) {
    violation(std::string(fn) + ": called before the STOPPING state was delivered");
    return record(fn, XR_ERROR_SESSION_NOT_STOPPING);
  }
  s->running = false;
  s->waitedTime.reset();
  s->begunTime.reset();
  queueState(*s, XR_SESSION_STATE_IDLE, s->lastDisplayTime);
  // The wearer left (the script ended, or the application asked to exit): the runtime is done with it.
  queueState(*s, XR_SESSION_STATE_EXITING, s->lastDisplayTime);
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL requestExitSession(XrSession session) {
  constexpr const char* fn = "xrRequestExitSession";
  CHECK_SESSION(fn, session);
  if (!s->running) return record(fn, XR_ERROR_SESSION_NOT_RUNNING);
  s->exitRequested = true;
  windDown(*s, s->lastDisplayTime);
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL enumerateReferenceSpaces(XrSession session, std::uint32_t capacity, std::uint32_t* count,
                                             XrReferenceSpaceType* out) {
  constexpr const char* fn = "xrEnumerateReferenceSpaces";
  CHECK_SESSION(fn, session);
  std::vector<XrReferenceSpaceType> types{XR_REFERENCE_SPACE_TYPE_VIEW, XR_REFERENCE_SPACE_TYPE_LOCAL};
  if (in->script.stage) types.push_back(XR_REFERENCE_SPACE_TYPE_STAGE);
  return record(fn, enumerate(capacity, count, out, static_cast<std::uint32_t>(types.size()),
                              [&](XrReferenceSpaceType& t, std::uint32_t i) { t = types[i]; }, fn));
}

XrResult XRAPI_CALL createReferenceSpace(XrSession session, const XrReferenceSpaceCreateInfo* info, XrSpace* space) {
  constexpr const char* fn = "xrCreateReferenceSpace";
  CHECK_SESSION(fn, session);
  if (!typed(info, XR_TYPE_REFERENCE_SPACE_CREATE_INFO, fn, "createInfo") || space == nullptr) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (!validPose(info->poseInReferenceSpace)) return record(fn, XR_ERROR_POSE_INVALID);
  Space::Type type;
  switch (info->referenceSpaceType) {
    case XR_REFERENCE_SPACE_TYPE_VIEW: type = Space::Type::View; break;
    case XR_REFERENCE_SPACE_TYPE_LOCAL: type = Space::Type::Local; break;
    case XR_REFERENCE_SPACE_TYPE_STAGE:
      if (!in->script.stage) return record(fn, XR_ERROR_REFERENCE_SPACE_UNSUPPORTED);
      type = Space::Type::Stage;
      break;
    default: return record(fn, XR_ERROR_REFERENCE_SPACE_UNSUPPORTED);
  }
  auto* sp = create<Space>(Kind::Space, s);
  sp->type = type;
  sp->offset = fromXr(info->poseInReferenceSpace);
  *space = handleOf<Space, XrSpace>(sp);
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL getReferenceSpaceBoundsRect(XrSession session, XrReferenceSpaceType type, XrExtent2Df* bounds) {
  constexpr const char* fn = "xrGetReferenceSpaceBoundsRect";
  CHECK_SESSION(fn, session);
  REQUIRE(bounds != nullptr, fn, "bounds is null");
  if (type == XR_REFERENCE_SPACE_TYPE_STAGE && in->script.stage) {
    *bounds = {3.0f, 3.0f};
    return record(fn, XR_SUCCESS);
  }
  *bounds = {0.0f, 0.0f};
  return record(fn, XR_SPACE_BOUNDS_UNAVAILABLE);
}

XrResult XRAPI_CALL createActionSpace(XrSession session, const XrActionSpaceCreateInfo* info, XrSpace* space) {
  constexpr const char* fn = "xrCreateActionSpace";
  CHECK_SESSION(fn, session);
  if (!typed(info, XR_TYPE_ACTION_SPACE_CREATE_INFO, fn, "createInfo") || space == nullptr) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  auto* action = lookup<Action>(info->action, Kind::Action, fn);
  if (action == nullptr) return record(fn, XR_ERROR_HANDLE_INVALID);
  if (action->type != XR_ACTION_TYPE_POSE_INPUT) return record(fn, XR_ERROR_ACTION_TYPE_MISMATCH);
  if (info->subactionPath != XR_NULL_PATH &&
      std::find(action->subactions.begin(), action->subactions.end(), info->subactionPath) == action->subactions.end())
    return record(fn, XR_ERROR_PATH_UNSUPPORTED);
  if (!validPose(info->poseInActionSpace)) return record(fn, XR_ERROR_POSE_INVALID);
  auto* sp = create<Space>(Kind::Space, s);
  sp->type = Space::Type::Action;
  sp->action = action;
  sp->subaction = info->subactionPath;
  sp->offset = fromXr(info->poseInActionSpace);
  *space = handleOf<Space, XrSpace>(sp);
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL locateSpace(XrSpace spaceHandle, XrSpace baseHandle, XrTime time, XrSpaceLocation* location) {
  constexpr const char* fn = "xrLocateSpace";
  Space* space = lookup<Space>(spaceHandle, Kind::Space, fn);
  Space* base = lookup<Space>(baseHandle, Kind::Space, fn);
  if (space == nullptr || base == nullptr) return record(fn, XR_ERROR_HANDLE_INVALID);
  auto* s = static_cast<Session*>(space->parent);
  auto* in = static_cast<Instance*>(s->parent);
  if (in->lost) return record(fn, XR_ERROR_INSTANCE_LOST);
  if (s->lost) return record(fn, XR_ERROR_SESSION_LOST);
  if (base->parent != s) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (!typed(location, XR_TYPE_SPACE_LOCATION, fn, "location")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (time <= 0) return record(fn, XR_ERROR_TIME_INVALID);
  XrSpaceVelocity* velocity = nullptr;
  for (auto* next = static_cast<XrBaseOutStructure*>(location->next); next != nullptr; next = next->next)
    if (next->type == XR_TYPE_SPACE_VELOCITY) velocity = reinterpret_cast<XrSpaceVelocity*>(next);
  const double t = scriptTime(time);
  const auto a = stagePose(*in, *s, *space, t), b = stagePose(*in, *s, *base, t);
  location->locationFlags = 0;
  if (velocity != nullptr) velocity->velocityFlags = 0;
  if (!a || !b) return record(fn, XR_SUCCESS);
  location->pose = toXr(b->inverse() * *a);
  location->locationFlags = XR_SPACE_LOCATION_POSITION_VALID_BIT | XR_SPACE_LOCATION_ORIENTATION_VALID_BIT |
                            XR_SPACE_LOCATION_POSITION_TRACKED_BIT | XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT;
  if (velocity != nullptr && base->type != Space::Type::View && space->type == Space::Type::Action) {
    const auto [linear, angular] = velocityOf([&](double u) { return stagePose(*in, *s, *space, u).value_or(*a); }, t);
    velocity->linearVelocity = toXr(Eigen::Vector3d(b->linear().transpose() * linear));
    velocity->angularVelocity = toXr(Eigen::Vector3d(b->linear().transpose() * angular));
    velocity->velocityFlags = XR_SPACE_VELOCITY_LINEAR_VALID_BIT | XR_SPACE_VELOCITY_ANGULAR_VALID_BIT;
  }
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL destroySpace(XrSpace space) {
  Space* sp = lookup<Space>(space, Kind::Space, "xrDestroySpace");
  if (sp == nullptr) return record("xrDestroySpace", XR_ERROR_HANDLE_INVALID);
  destroy(sp);
  return record("xrDestroySpace", XR_SUCCESS);
}

XrResult XRAPI_CALL enumerateSwapchainFormats(XrSession session, std::uint32_t capacity, std::uint32_t* count, std::int64_t* formats) {
  constexpr const char* fn = "xrEnumerateSwapchainFormats";
  CHECK_SESSION(fn, session);
  const std::int64_t list[] = {kGlSrgb8Alpha8, kGlRgba8};
  return record(fn, enumerate(capacity, count, formats, 2, [&](std::int64_t& f, std::uint32_t i) { f = list[i]; }, fn));
}

XrResult XRAPI_CALL createSwapchain(XrSession session, const XrSwapchainCreateInfo* info, XrSwapchain* swapchain) {
  constexpr const char* fn = "xrCreateSwapchain";
  CHECK_SESSION(fn, session);
  if (!typed(info, XR_TYPE_SWAPCHAIN_CREATE_INFO, fn, "createInfo") || swapchain == nullptr) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (info->format != kGlRgba8 && info->format != kGlSrgb8Alpha8) return record(fn, XR_ERROR_SWAPCHAIN_FORMAT_UNSUPPORTED);
  REQUIRE(info->width > 0 && info->height > 0 && info->arraySize > 0 && info->mipCount > 0 && info->sampleCount > 0, fn,
          "a zero size, array size, mip count or sample count");
  REQUIRE(info->faceCount == 1 || info->faceCount == 6, fn, "faceCount is neither 1 nor 6");
  if (info->width > static_cast<std::uint32_t>(in->script.eyeWidth * 2) || info->height > static_cast<std::uint32_t>(in->script.eyeHeight * 2))
    return record(fn, XR_ERROR_SIZE_INSUFFICIENT);
  if (info->sampleCount > 4 || info->faceCount != 1 || info->arraySize != 1) return record(fn, XR_ERROR_FEATURE_UNSUPPORTED);
  CurrentContext current(s);
  if (glXGetCurrentContext() == nullptr) return record(fn, XR_ERROR_GRAPHICS_DEVICE_INVALID);
  auto* sc = create<Swapchain>(Kind::Swapchain, s);
  sc->info = *info;
  sc->info.next = nullptr;
  sc->textures.resize(kImagesPerSwapchain);
  glGenTextures(static_cast<GLsizei>(kImagesPerSwapchain), sc->textures.data());
  for (GLuint tex : sc->textures) {
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, static_cast<GLint>(info->format), static_cast<GLsizei>(info->width),
                 static_cast<GLsizei>(info->height), 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  }
  glBindTexture(GL_TEXTURE_2D, 0);
  *swapchain = handleOf<Swapchain, XrSwapchain>(sc);
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL destroySwapchain(XrSwapchain swapchain) {
  Swapchain* sc = lookup<Swapchain>(swapchain, Kind::Swapchain, "xrDestroySwapchain");
  if (sc == nullptr) return record("xrDestroySwapchain", XR_ERROR_HANDLE_INVALID);
  destroy(sc);
  return record("xrDestroySwapchain", XR_SUCCESS);
}

#define CHECK_SWAPCHAIN(fn, handle)                                         \
  Swapchain* sc = lookup<Swapchain>(handle, Kind::Swapchain, fn);           \
  if (sc == nullptr) return record(fn, XR_ERROR_HANDLE_INVALID);            \
  auto* s = static_cast<Session*>(sc->parent);                              \
  if (static_cast<Instance*>(s->parent)->lost) return record(fn, XR_ERROR_INSTANCE_LOST); \
  if (s->lost) return record(fn, XR_ERROR_SESSION_LOST);

XrResult XRAPI_CALL enumerateSwapchainImages(XrSwapchain swapchain, std::uint32_t capacity, std::uint32_t* count,
                                             XrSwapchainImageBaseHeader* images) {
  constexpr const char* fn = "xrEnumerateSwapchainImages";
  CHECK_SWAPCHAIN(fn, swapchain);
  auto* gl = reinterpret_cast<XrSwapchainImageOpenGLKHR*>(images);
  for (std::uint32_t i = 0; gl != nullptr && i < std::min(capacity, kImagesPerSwapchain); ++i)
    if (!typed(&gl[i], XR_TYPE_SWAPCHAIN_IMAGE_OPENGL_KHR, fn, "images")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  return record(fn, enumerate(capacity, count, gl, kImagesPerSwapchain,
                              [&](XrSwapchainImageOpenGLKHR& img, std::uint32_t i) { img.image = sc->textures[i]; }, fn));
}

XrResult XRAPI_CALL acquireSwapchainImage(XrSwapchain swapchain, const XrSwapchainImageAcquireInfo* info, std::uint32_t* index) {
  constexpr const char* fn = "xrAcquireSwapchainImage";
  CHECK_SWAPCHAIN(fn, swapchain);
  if ((info != nullptr && !typed(info, XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO, fn, "acquireInfo")) || index == nullptr)
    return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (sc->acquired.size() >= kImagesPerSwapchain) {
    violation(std::string(fn) + ": every image is already acquired");
    return record(fn, XR_ERROR_CALL_ORDER_INVALID);
  }
  *index = sc->next;
  sc->acquired.push_back(sc->next);
  sc->next = (sc->next + 1) % kImagesPerSwapchain;
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL waitSwapchainImage(XrSwapchain swapchain, const XrSwapchainImageWaitInfo* info) {
  constexpr const char* fn = "xrWaitSwapchainImage";
  CHECK_SWAPCHAIN(fn, swapchain);
  if (!typed(info, XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO, fn, "waitInfo")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (sc->acquired.empty() || sc->waited) {
    violation(std::string(fn) + ": no acquired image is waiting to be waited on");
    return record(fn, XR_ERROR_CALL_ORDER_INVALID);
  }
  sc->waited = true;
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL releaseSwapchainImage(XrSwapchain swapchain, const XrSwapchainImageReleaseInfo* info) {
  constexpr const char* fn = "xrReleaseSwapchainImage";
  CHECK_SWAPCHAIN(fn, swapchain);
  if (info != nullptr && !typed(info, XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO, fn, "releaseInfo")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (!sc->waited) {
    violation(std::string(fn) + ": no image has been waited on");
    return record(fn, XR_ERROR_CALL_ORDER_INVALID);
  }
  sc->released = sc->acquired.front();
  sc->acquired.pop_front();
  sc->waited = false;
  return record(fn, XR_SUCCESS);
}

// ---- the frame loop ----

XrResult XRAPI_CALL waitFrame(XrSession session, const XrFrameWaitInfo* info, XrFrameState* state) {
  constexpr const char* fn = "xrWaitFrame";
  CHECK_SESSION(fn, session);
  if ((info != nullptr && !typed(info, XR_TYPE_FRAME_WAIT_INFO, fn, "frameWaitInfo")) ||
      !typed(state, XR_TYPE_FRAME_STATE, fn, "frameState"))
    return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (!s->running) {
    violation(std::string(fn) + ": the session is not running");
    return record(fn, XR_ERROR_SESSION_NOT_RUNNING);
  }
  if (s->waitedTime) {
    // A second wait before the first frame began blocks forever in a single-threaded application.
    violation(std::string(fn) + ": called again before xrBeginFrame");
    return record(fn, XR_ERROR_CALL_ORDER_INVALID);
  }
  const std::int64_t p = period(in->script);
  const XrTime display = kEpoch + s->frames * p;
  ++s->frames;
  if (in->script.realtime) {
    // Paced as a headset is: the call returns one period before the frame is shown.
    static std::chrono::steady_clock::time_point start;
    if (s->frames == 1) start = std::chrono::steady_clock::now();
    std::this_thread::sleep_until(start + std::chrono::nanoseconds(display - kEpoch - p));
  }
  s->waitedTime = display;
  state->predictedDisplayTime = display;
  state->predictedDisplayPeriod = p;
  state->shouldRender = (s->state == XR_SESSION_STATE_VISIBLE || s->state == XR_SESSION_STATE_FOCUSED) ? XR_TRUE : XR_FALSE;
  s->lastDisplayTime = display;
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL beginFrame(XrSession session, const XrFrameBeginInfo* info) {
  constexpr const char* fn = "xrBeginFrame";
  CHECK_SESSION(fn, session);
  if (info != nullptr && !typed(info, XR_TYPE_FRAME_BEGIN_INFO, fn, "frameBeginInfo")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (!s->running) return record(fn, XR_ERROR_SESSION_NOT_RUNNING);
  if (!s->waitedTime) {
    violation(std::string(fn) + ": no xrWaitFrame before it");
    return record(fn, XR_ERROR_CALL_ORDER_INVALID);
  }
  const bool discarded = s->begunTime.has_value();
  s->begunTime = *s->waitedTime;
  s->waitedTime.reset();
  return record(fn, discarded ? XR_FRAME_DISCARDED : XR_SUCCESS);
}

Image readBack(GLuint texture, int width, int height) {
  Image img;
  img.width = width;
  img.height = height;
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width) * height * 4);
  glBindTexture(GL_TEXTURE_2D, texture);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
  glBindTexture(GL_TEXTURE_2D, 0);
  // OpenGL images start at the bottom row (the specification: the swapchain's origin is bottom-left).
  img.rgba.resize(pixels.size());
  const std::size_t row = static_cast<std::size_t>(width) * 4;
  for (int y = 0; y < height; ++y)
    std::memcpy(&img.rgba[static_cast<std::size_t>(y) * row], &pixels[static_cast<std::size_t>(height - 1 - y) * row], row);
  return img;
}

XrResult XRAPI_CALL endFrame(XrSession session, const XrFrameEndInfo* info) {
  constexpr const char* fn = "xrEndFrame";
  CHECK_SESSION(fn, session);
  if (!typed(info, XR_TYPE_FRAME_END_INFO, fn, "frameEndInfo")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (!s->running) return record(fn, XR_ERROR_SESSION_NOT_RUNNING);
  if (!s->begunTime) {
    violation(std::string(fn) + ": no xrBeginFrame before it");
    return record(fn, XR_ERROR_CALL_ORDER_INVALID);
  }
  if (info->displayTime != *s->begunTime) {
    violation(std::string(fn) + ": displayTime is not the predicted display time of the frame");
    return record(fn, XR_ERROR_TIME_INVALID);
  }
  if (info->environmentBlendMode != kBlend) return record(fn, XR_ERROR_ENVIRONMENT_BLEND_MODE_UNSUPPORTED);
  if (info->layerCount > 16) return record(fn, XR_ERROR_LAYER_LIMIT_EXCEEDED);
  REQUIRE(info->layerCount == 0 || info->layers != nullptr, fn, "layers is null");
  SubmittedFrame frame;
  frame.displayTime = info->displayTime;
  frame.t = scriptTime(info->displayTime);
  frame.layerCount = info->layerCount;
  std::array<std::pair<Swapchain*, XrRect2Di>, 2> shown{};
  for (std::uint32_t l = 0; l < info->layerCount; ++l) {
    const XrCompositionLayerBaseHeader* layer = info->layers[l];
    REQUIRE(layer != nullptr, fn, "a null layer");
    if (layer->type != XR_TYPE_COMPOSITION_LAYER_PROJECTION) {
      violation(std::string(fn) + ": layer of type " + std::to_string(layer->type) + " (only projection layers are offered)");
      return record(fn, XR_ERROR_LAYER_INVALID);
    }
    const auto* proj = reinterpret_cast<const XrCompositionLayerProjection*>(layer);
    if (lookup<Space>(proj->space, Kind::Space, fn) == nullptr) return record(fn, XR_ERROR_HANDLE_INVALID);
    REQUIRE(proj->viewCount == 2 && proj->views != nullptr, fn, "a projection layer of PRIMARY_STEREO needs 2 views");
    for (std::uint32_t v = 0; v < 2; ++v) {
      const XrCompositionLayerProjectionView& view = proj->views[v];
      if (!typed(&view, XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW, fn, "projection view")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
      if (!validPose(view.pose)) return record(fn, XR_ERROR_POSE_INVALID);
      Swapchain* sc = lookup<Swapchain>(view.subImage.swapchain, Kind::Swapchain, fn);
      if (sc == nullptr) return record(fn, XR_ERROR_HANDLE_INVALID);
      if (!sc->released) {
        violation(std::string(fn) + ": a swapchain none of whose images has been released");
        return record(fn, XR_ERROR_LAYER_INVALID);
      }
      const XrRect2Di& r = view.subImage.imageRect;
      if (r.offset.x < 0 || r.offset.y < 0 || r.extent.width <= 0 || r.extent.height <= 0 ||
          static_cast<std::uint32_t>(r.offset.x + r.extent.width) > sc->info.width ||
          static_cast<std::uint32_t>(r.offset.y + r.extent.height) > sc->info.height) {
        violation(std::string(fn) + ": imageRect outside the swapchain");
        return record(fn, XR_ERROR_SWAPCHAIN_RECT_INVALID);
      }
      REQUIRE(view.subImage.imageArrayIndex < sc->info.arraySize, fn, "imageArrayIndex beyond the swapchain's array");
      frame.eyePoses[v] = view.pose;
      frame.fovs[v] = view.fov;
      shown[v] = {sc, r};
    }
  }
  s->begunTime.reset();
  ++s->endedFrames;
  g_record.frames.push_back(frame);
  const Script& script = in->script;
  if (info->layerCount > 0 && s->nextCapture < script.captureAt.size() && frame.t + 1e-9 >= script.captureAt[s->nextCapture]) {
    ++s->nextCapture;
    Capture capture;
    capture.t = frame.t;
    CurrentContext current(s);
    for (std::size_t v = 0; v < 2; ++v)
      capture.eyes[v] = readBack(shown[v].first->textures[*shown[v].first->released], shown[v].second.extent.width,
                                 shown[v].second.extent.height);
    g_record.captures.push_back(std::move(capture));
  }
  // The compositor shows the frames: the session becomes SYNCHRONIZED, VISIBLE and FOCUSED, one per frame.
  if (!s->windingDown) {
    if (s->state == XR_SESSION_STATE_READY) queueState(*s, XR_SESSION_STATE_SYNCHRONIZED, info->displayTime);
    else if (s->state == XR_SESSION_STATE_SYNCHRONIZED) queueState(*s, XR_SESSION_STATE_VISIBLE, info->displayTime);
    else if (s->state == XR_SESSION_STATE_VISIBLE) {
      queueState(*s, XR_SESSION_STATE_FOCUSED, info->displayTime);
      if (s->actionSetsAttached && (script.controllers[0].size() + script.controllers[1].size()) > 0) {
        for (std::size_t h = 0; h < 2; ++h)
          if (!script.controllers[h].empty() && !in->suggested.empty()) {
            XrPath profile = XR_NULL_PATH;
            for (std::size_t i = 0; i < in->paths.size(); ++i)
              if (in->paths[i] == kSimpleController) profile = i;
            s->profile[h] = in->suggested.count(profile) != 0 ? profile : XR_NULL_PATH;
          }
        queueProfileChanged(*s);
      }
    }
  }
  scriptEvents(*in, *s, info->displayTime);
  return record(fn, XR_SUCCESS);
}

// Two views from the head: the eyes kIpd apart along its x axis, each with a slightly outward field of view.
XrResult XRAPI_CALL locateViews(XrSession session, const XrViewLocateInfo* info, XrViewState* viewState, std::uint32_t capacity,
                                std::uint32_t* count, XrView* views) {
  constexpr const char* fn = "xrLocateViews";
  CHECK_SESSION(fn, session);
  if (!typed(info, XR_TYPE_VIEW_LOCATE_INFO, fn, "viewLocateInfo") || !typed(viewState, XR_TYPE_VIEW_STATE, fn, "viewState"))
    return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (info->viewConfigurationType != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO) return record(fn, XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED);
  if (info->displayTime <= 0) return record(fn, XR_ERROR_TIME_INVALID);
  Space* base = lookup<Space>(info->space, Kind::Space, fn);
  if (base == nullptr) return record(fn, XR_ERROR_HANDLE_INVALID);
  for (std::uint32_t i = 0; views != nullptr && i < std::min(capacity, 2u); ++i)
    if (!typed(&views[i], XR_TYPE_VIEW, fn, "views")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  const double t = scriptTime(info->displayTime);
  const Eigen::Isometry3d head = in->script.headAt(t);
  const auto basePose = stagePose(*in, *s, *base, t);
  viewState->viewStateFlags = basePose ? (XR_VIEW_STATE_POSITION_VALID_BIT | XR_VIEW_STATE_ORIENTATION_VALID_BIT |
                                          XR_VIEW_STATE_POSITION_TRACKED_BIT | XR_VIEW_STATE_ORIENTATION_TRACKED_BIT)
                                       : 0;
  return record(fn, enumerate(capacity, count, views, 2,
                              [&](XrView& v, std::uint32_t eye) {
                                const double side = eye == 0 ? -1.0 : 1.0;
                                Eigen::Isometry3d pose = head;
                                pose.translate(Eigen::Vector3d(side * kIpd / 2, 0.0, 0.0));
                                v.pose = toXr(basePose ? Eigen::Isometry3d(basePose->inverse() * pose) : pose);
                                const float outward = 0.85f, inward = 0.75f;
                                v.fov.angleLeft = eye == 0 ? -outward : -inward;
                                v.fov.angleRight = eye == 0 ? inward : outward;
                                v.fov.angleUp = 0.80f;
                                v.fov.angleDown = -0.85f;
                              },
                              fn));
}

// ---- paths and actions ----

XrResult XRAPI_CALL stringToPath(XrInstance instance, const char* text, XrPath* path) {
  constexpr const char* fn = "xrStringToPath";
  CHECK_INSTANCE(fn, instance);
  REQUIRE(text != nullptr && path != nullptr, fn, "null argument");
  const std::string s = text;
  // Well-formed: starts with '/', no trailing '/', no empty component, lower-case letters, digits, -_./ only.
  bool ok = s.size() > 1 && s.front() == '/' && s.back() != '/' && s.find("//") == std::string::npos;
  for (char c : s) ok = ok && ((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_' || c == '.' || c == '/');
  if (!ok) return record(fn, XR_ERROR_PATH_FORMAT_INVALID);
  auto it = std::find(in->paths.begin(), in->paths.end(), s);
  if (it == in->paths.end()) it = in->paths.insert(in->paths.end(), s);
  *path = static_cast<XrPath>(it - in->paths.begin());
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL pathToString(XrInstance instance, XrPath path, std::uint32_t capacity, std::uint32_t* count, char* buffer) {
  constexpr const char* fn = "xrPathToString";
  CHECK_INSTANCE(fn, instance);
  if (path == XR_NULL_PATH || path >= in->paths.size()) return record(fn, XR_ERROR_PATH_INVALID);
  const std::string& s = in->paths[path];
  return record(fn, enumerate(capacity, count, buffer, static_cast<std::uint32_t>(s.size() + 1),
                              [&](char& c, std::uint32_t i) { c = i < s.size() ? s[i] : '\0'; }, fn));
}

bool goodName(const char* name, std::size_t max) {
  const std::size_t n = strnlen(name, max);
  if (n == 0 || n == max) return false;
  for (std::size_t i = 0; i < n; ++i) {
    const char c = name[i];
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_' || c == '.')) return false;
  }
  return true;
}

XrResult XRAPI_CALL createActionSet(XrInstance instance, const XrActionSetCreateInfo* info, XrActionSet* set) {
  constexpr const char* fn = "xrCreateActionSet";
  CHECK_INSTANCE(fn, instance);
  if (!typed(info, XR_TYPE_ACTION_SET_CREATE_INFO, fn, "createInfo") || set == nullptr) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (!goodName(info->actionSetName, XR_MAX_ACTION_SET_NAME_SIZE)) return record(fn, XR_ERROR_PATH_FORMAT_INVALID);
  if (info->localizedActionSetName[0] == '\0') return record(fn, XR_ERROR_LOCALIZED_NAME_INVALID);
  auto* a = create<ActionSet>(Kind::ActionSet, in);
  *set = handleOf<ActionSet, XrActionSet>(a);
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL destroyActionSet(XrActionSet set) {
  ActionSet* a = lookup<ActionSet>(set, Kind::ActionSet, "xrDestroyActionSet");
  if (a == nullptr) return record("xrDestroyActionSet", XR_ERROR_HANDLE_INVALID);
  destroy(a);
  return record("xrDestroyActionSet", XR_SUCCESS);
}

XrResult XRAPI_CALL createAction(XrActionSet set, const XrActionCreateInfo* info, XrAction* action) {
  constexpr const char* fn = "xrCreateAction";
  ActionSet* as = lookup<ActionSet>(set, Kind::ActionSet, fn);
  if (as == nullptr) return record(fn, XR_ERROR_HANDLE_INVALID);
  auto* in = static_cast<Instance*>(as->parent);
  if (in->lost) return record(fn, XR_ERROR_INSTANCE_LOST);
  if (!typed(info, XR_TYPE_ACTION_CREATE_INFO, fn, "createInfo") || action == nullptr) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (as->attached) return record(fn, XR_ERROR_ACTIONSETS_ALREADY_ATTACHED);
  if (!goodName(info->actionName, XR_MAX_ACTION_NAME_SIZE)) return record(fn, XR_ERROR_PATH_FORMAT_INVALID);
  if (info->localizedActionName[0] == '\0') return record(fn, XR_ERROR_LOCALIZED_NAME_INVALID);
  auto* a = create<Action>(Kind::Action, as);
  a->type = info->actionType;
  for (std::uint32_t i = 0; i < info->countSubactionPaths; ++i) {
    const XrPath p = info->subactionPaths[i];
    if (p == XR_NULL_PATH || p >= in->paths.size()) {
      destroy(a);
      return record(fn, XR_ERROR_PATH_INVALID);
    }
    a->subactions.push_back(p);
  }
  *action = handleOf<Action, XrAction>(a);
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL destroyAction(XrAction action) {
  Action* a = lookup<Action>(action, Kind::Action, "xrDestroyAction");
  if (a == nullptr) return record("xrDestroyAction", XR_ERROR_HANDLE_INVALID);
  destroy(a);
  return record("xrDestroyAction", XR_SUCCESS);
}

XrResult XRAPI_CALL suggestBindings(XrInstance instance, const XrInteractionProfileSuggestedBinding* info) {
  constexpr const char* fn = "xrSuggestInteractionProfileBindings";
  CHECK_INSTANCE(fn, instance);
  if (!typed(info, XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING, fn, "suggestedBindings")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (in->session != nullptr && in->session->actionSetsAttached) return record(fn, XR_ERROR_ACTIONSETS_ALREADY_ATTACHED);
  if (info->interactionProfile == XR_NULL_PATH || info->interactionProfile >= in->paths.size()) return record(fn, XR_ERROR_PATH_INVALID);
  if (in->paths[info->interactionProfile] != kSimpleController) return record(fn, XR_ERROR_PATH_UNSUPPORTED);
  REQUIRE(info->countSuggestedBindings > 0 && info->suggestedBindings != nullptr, fn, "no bindings");
  std::vector<std::pair<Action*, XrPath>> list;
  const std::string prefix[] = {"/user/hand/left/input/", "/user/hand/right/input/"};
  const char* inputs[] = {"select/click", "menu/click", "grip/pose", "aim/pose"};
  for (std::uint32_t i = 0; i < info->countSuggestedBindings; ++i) {
    const XrActionSuggestedBinding& b = info->suggestedBindings[i];
    Action* a = lookup<Action>(b.action, Kind::Action, fn);
    if (a == nullptr) return record(fn, XR_ERROR_HANDLE_INVALID);
    if (b.binding == XR_NULL_PATH || b.binding >= in->paths.size()) return record(fn, XR_ERROR_PATH_INVALID);
    bool known = false;
    for (const auto& pre : prefix)
      for (const char* input : inputs) known = known || in->paths[b.binding] == pre + input;
    if (!known) return record(fn, XR_ERROR_PATH_UNSUPPORTED);
    list.emplace_back(a, b.binding);
  }
  in->suggested[info->interactionProfile] = std::move(list);
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL attachActionSets(XrSession session, const XrSessionActionSetsAttachInfo* info) {
  constexpr const char* fn = "xrAttachSessionActionSets";
  CHECK_SESSION(fn, session);
  if (!typed(info, XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO, fn, "attachInfo")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (s->actionSetsAttached) return record(fn, XR_ERROR_ACTIONSETS_ALREADY_ATTACHED);
  REQUIRE(info->countActionSets > 0 && info->actionSets != nullptr, fn, "no action sets");
  for (std::uint32_t i = 0; i < info->countActionSets; ++i) {
    ActionSet* a = lookup<ActionSet>(info->actionSets[i], Kind::ActionSet, fn);
    if (a == nullptr) return record(fn, XR_ERROR_HANDLE_INVALID);
    a->attached = true;
    s->attached.push_back(a);
  }
  s->actionSetsAttached = true;
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL getCurrentInteractionProfile(XrSession session, XrPath topLevel, XrInteractionProfileState* state) {
  constexpr const char* fn = "xrGetCurrentInteractionProfile";
  CHECK_SESSION(fn, session);
  if (!typed(state, XR_TYPE_INTERACTION_PROFILE_STATE, fn, "interactionProfile")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (!s->actionSetsAttached) return record(fn, XR_ERROR_ACTIONSET_NOT_ATTACHED);
  if (topLevel == XR_NULL_PATH || topLevel >= in->paths.size()) return record(fn, XR_ERROR_PATH_INVALID);
  const std::string& p = in->paths[topLevel];
  if (p != "/user/hand/left" && p != "/user/hand/right") return record(fn, XR_ERROR_PATH_UNSUPPORTED);
  state->interactionProfile = s->profile[p == "/user/hand/left" ? 0 : 1];
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL syncActions(XrSession session, const XrActionsSyncInfo* info) {
  constexpr const char* fn = "xrSyncActions";
  CHECK_SESSION(fn, session);
  if (!typed(info, XR_TYPE_ACTIONS_SYNC_INFO, fn, "syncInfo")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  for (std::uint32_t i = 0; i < info->countActiveActionSets; ++i) {
    ActionSet* a = lookup<ActionSet>(info->activeActionSets[i].actionSet, Kind::ActionSet, fn);
    if (a == nullptr) return record(fn, XR_ERROR_HANDLE_INVALID);
    if (std::find(s->attached.begin(), s->attached.end(), a) == s->attached.end()) {
      violation(std::string(fn) + ": an action set not attached to the session");
      return record(fn, XR_ERROR_ACTIONSET_NOT_ATTACHED);
    }
  }
  const bool focused = s->delivered == XR_SESSION_STATE_FOCUSED;
  for (int h = 0; h < 2; ++h) {
    const ControllerPose c = in->script.controllerAt(h, scriptTime(s->lastDisplayTime));
    s->select[static_cast<std::size_t>(h)] = focused && c.active && c.select;
    s->focusedSync[static_cast<std::size_t>(h)] = focused && c.active && s->profile[static_cast<std::size_t>(h)] != XR_NULL_PATH;
  }
  s->synced = true;
  return record(fn, focused ? XR_SUCCESS : XR_SESSION_NOT_FOCUSED);
}

// The action's state for the hand `subaction` names (XR_NULL_PATH: either hand).
template <class State>
XrResult actionState(const char* fn, XrSession session, const XrActionStateGetInfo* info, State* state, XrStructureType type,
                     XrActionType actionType) {
  CHECK_SESSION(fn, session);
  if (!typed(info, XR_TYPE_ACTION_STATE_GET_INFO, fn, "getInfo") || !typed(state, type, fn, "state"))
    return record(fn, XR_ERROR_VALIDATION_FAILURE);
  Action* a = lookup<Action>(info->action, Kind::Action, fn);
  if (a == nullptr) return record(fn, XR_ERROR_HANDLE_INVALID);
  if (!static_cast<ActionSet*>(a->parent)->attached) return record(fn, XR_ERROR_ACTIONSET_NOT_ATTACHED);
  if (a->type != actionType) return record(fn, XR_ERROR_ACTION_TYPE_MISMATCH);
  if (info->subactionPath != XR_NULL_PATH &&
      std::find(a->subactions.begin(), a->subactions.end(), info->subactionPath) == a->subactions.end())
    return record(fn, XR_ERROR_PATH_UNSUPPORTED);
  bool active = false, value = false;
  for (int h = 0; h < 2; ++h) {
    const char* hand = h == 0 ? "/user/hand/left" : "/user/hand/right";
    if (info->subactionPath != XR_NULL_PATH && in->paths[info->subactionPath] != hand) continue;
    active = active || s->focusedSync[static_cast<std::size_t>(h)];
    value = value || s->select[static_cast<std::size_t>(h)];
  }
  state->isActive = active ? XR_TRUE : XR_FALSE;
  if constexpr (std::is_same_v<State, XrActionStateBoolean>) {
    state->currentState = active && value ? XR_TRUE : XR_FALSE;
    state->changedSinceLastSync = XR_FALSE;
    state->lastChangeTime = 0;
  } else if constexpr (std::is_same_v<State, XrActionStateFloat>) {
    state->currentState = active && value ? 1.0f : 0.0f;
    state->changedSinceLastSync = XR_FALSE;
    state->lastChangeTime = 0;
  } else if constexpr (std::is_same_v<State, XrActionStateVector2f>) {
    state->currentState = {0.0f, 0.0f};
    state->changedSinceLastSync = XR_FALSE;
    state->lastChangeTime = 0;
  }
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL getBoolean(XrSession s, const XrActionStateGetInfo* i, XrActionStateBoolean* st) {
  return actionState("xrGetActionStateBoolean", s, i, st, XR_TYPE_ACTION_STATE_BOOLEAN, XR_ACTION_TYPE_BOOLEAN_INPUT);
}
XrResult XRAPI_CALL getFloat(XrSession s, const XrActionStateGetInfo* i, XrActionStateFloat* st) {
  return actionState("xrGetActionStateFloat", s, i, st, XR_TYPE_ACTION_STATE_FLOAT, XR_ACTION_TYPE_FLOAT_INPUT);
}
XrResult XRAPI_CALL getVector2f(XrSession s, const XrActionStateGetInfo* i, XrActionStateVector2f* st) {
  return actionState("xrGetActionStateVector2f", s, i, st, XR_TYPE_ACTION_STATE_VECTOR2F, XR_ACTION_TYPE_VECTOR2F_INPUT);
}
XrResult XRAPI_CALL getPose(XrSession s, const XrActionStateGetInfo* i, XrActionStatePose* st) {
  return actionState("xrGetActionStatePose", s, i, st, XR_TYPE_ACTION_STATE_POSE, XR_ACTION_TYPE_POSE_INPUT);
}

XrResult XRAPI_CALL enumerateBoundSources(XrSession session, const XrBoundSourcesForActionEnumerateInfo* info, std::uint32_t capacity,
                                          std::uint32_t* count, XrPath* sources) {
  constexpr const char* fn = "xrEnumerateBoundSourcesForAction";
  CHECK_SESSION(fn, session);
  if (!typed(info, XR_TYPE_BOUND_SOURCES_FOR_ACTION_ENUMERATE_INFO, fn, "enumerateInfo")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  Action* a = lookup<Action>(info->action, Kind::Action, fn);
  if (a == nullptr) return record(fn, XR_ERROR_HANDLE_INVALID);
  if (!static_cast<ActionSet*>(a->parent)->attached) return record(fn, XR_ERROR_ACTIONSET_NOT_ATTACHED);
  std::vector<XrPath> bound;
  for (const auto& [profile, list] : in->suggested)
    for (const auto& [action, binding] : list)
      if (action == a && s->profile[in->paths[binding].rfind("/user/hand/left", 0) == 0 ? 0 : 1] == profile) bound.push_back(binding);
  return record(fn, enumerate(capacity, count, sources, static_cast<std::uint32_t>(bound.size()),
                              [&](XrPath& p, std::uint32_t i) { p = bound[i]; }, fn));
}

XrResult XRAPI_CALL getLocalizedName(XrSession session, const XrInputSourceLocalizedNameGetInfo* info, std::uint32_t capacity,
                                     std::uint32_t* count, char* buffer) {
  constexpr const char* fn = "xrGetInputSourceLocalizedName";
  CHECK_SESSION(fn, session);
  if (!typed(info, XR_TYPE_INPUT_SOURCE_LOCALIZED_NAME_GET_INFO, fn, "getInfo")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  if (info->sourcePath == XR_NULL_PATH || info->sourcePath >= in->paths.size()) return record(fn, XR_ERROR_PATH_INVALID);
  const std::string& name = in->paths[info->sourcePath];
  return record(fn, enumerate(capacity, count, buffer, static_cast<std::uint32_t>(name.size() + 1),
                              [&](char& c, std::uint32_t i) { c = i < name.size() ? name[i] : '\0'; }, fn));
}

XrResult XRAPI_CALL applyHaptic(XrSession session, const XrHapticActionInfo* info, const XrHapticBaseHeader* haptic) {
  constexpr const char* fn = "xrApplyHapticFeedback";
  CHECK_SESSION(fn, session);
  if (!typed(info, XR_TYPE_HAPTIC_ACTION_INFO, fn, "hapticActionInfo") || haptic == nullptr) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  Action* a = lookup<Action>(info->action, Kind::Action, fn);
  if (a == nullptr) return record(fn, XR_ERROR_HANDLE_INVALID);
  if (a->type != XR_ACTION_TYPE_VIBRATION_OUTPUT) return record(fn, XR_ERROR_ACTION_TYPE_MISMATCH);
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL stopHaptic(XrSession session, const XrHapticActionInfo* info) {
  constexpr const char* fn = "xrStopHapticFeedback";
  CHECK_SESSION(fn, session);
  if (!typed(info, XR_TYPE_HAPTIC_ACTION_INFO, fn, "hapticActionInfo")) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  Action* a = lookup<Action>(info->action, Kind::Action, fn);
  if (a == nullptr) return record(fn, XR_ERROR_HANDLE_INVALID);
  if (a->type != XR_ACTION_TYPE_VIBRATION_OUTPUT) return record(fn, XR_ERROR_ACTION_TYPE_MISMATCH);
  return record(fn, XR_SUCCESS);
}

// ---- XR_EXT_hand_tracking ----

XrResult XRAPI_CALL createHandTracker(XrSession session, const XrHandTrackerCreateInfoEXT* info, XrHandTrackerEXT* tracker) {
  constexpr const char* fn = "xrCreateHandTrackerEXT";
  CHECK_SESSION(fn, session);
  if (!in->handTracking) return record(fn, XR_ERROR_FUNCTION_UNSUPPORTED);
  if (!typed(info, XR_TYPE_HAND_TRACKER_CREATE_INFO_EXT, fn, "createInfo") || tracker == nullptr) return record(fn, XR_ERROR_VALIDATION_FAILURE);
  REQUIRE(info->hand == XR_HAND_LEFT_EXT || info->hand == XR_HAND_RIGHT_EXT, fn, "hand is neither left nor right");
  if (info->handJointSet != XR_HAND_JOINT_SET_DEFAULT_EXT) return record(fn, XR_ERROR_FEATURE_UNSUPPORTED);
  auto* t = create<HandTracker>(Kind::HandTracker, s);
  t->hand = info->hand == XR_HAND_LEFT_EXT ? 0 : 1;
  *tracker = handleOf<HandTracker, XrHandTrackerEXT>(t);
  return record(fn, XR_SUCCESS);
}

XrResult XRAPI_CALL destroyHandTracker(XrHandTrackerEXT tracker) {
  HandTracker* t = lookup<HandTracker>(tracker, Kind::HandTracker, "xrDestroyHandTrackerEXT");
  if (t == nullptr) return record("xrDestroyHandTrackerEXT", XR_ERROR_HANDLE_INVALID);
  destroy(t);
  return record("xrDestroyHandTrackerEXT", XR_SUCCESS);
}

XrResult XRAPI_CALL locateHandJoints(XrHandTrackerEXT tracker, const XrHandJointsLocateInfoEXT* info, XrHandJointLocationsEXT* out) {
  constexpr const char* fn = "xrLocateHandJointsEXT";
  HandTracker* t = lookup<HandTracker>(tracker, Kind::HandTracker, fn);
  if (t == nullptr) return record(fn, XR_ERROR_HANDLE_INVALID);
  auto* s = static_cast<Session*>(t->parent);
  auto* in = static_cast<Instance*>(s->parent);
  if (in->lost) return record(fn, XR_ERROR_INSTANCE_LOST);
  if (s->lost) return record(fn, XR_ERROR_SESSION_LOST);
  if (!typed(info, XR_TYPE_HAND_JOINTS_LOCATE_INFO_EXT, fn, "locateInfo") || !typed(out, XR_TYPE_HAND_JOINT_LOCATIONS_EXT, fn, "locations"))
    return record(fn, XR_ERROR_VALIDATION_FAILURE);
  Space* base = lookup<Space>(info->baseSpace, Kind::Space, fn);
  if (base == nullptr) return record(fn, XR_ERROR_HANDLE_INVALID);
  if (info->time <= 0) return record(fn, XR_ERROR_TIME_INVALID);
  REQUIRE(out->jointCount == kJoints && out->jointLocations != nullptr, fn, "jointCount is not XR_HAND_JOINT_COUNT_EXT");
  XrHandJointVelocitiesEXT* velocities = nullptr;
  for (auto* next = static_cast<XrBaseOutStructure*>(out->next); next != nullptr; next = next->next)
    if (next->type == XR_TYPE_HAND_JOINT_VELOCITIES_EXT) velocities = reinterpret_cast<XrHandJointVelocitiesEXT*>(next);
  if (velocities != nullptr) REQUIRE(velocities->jointCount == kJoints && velocities->jointVelocities != nullptr, fn,
                                     "XrHandJointVelocitiesEXT::jointCount is not XR_HAND_JOINT_COUNT_EXT");
  const double time = scriptTime(info->time);
  const HandPose hand = in->script.handAt(t->hand, time);
  const auto basePose = stagePose(*in, *s, *base, time);
  // Hands are tracked only while the session has input focus (the specification: no input otherwise).
  const bool active = hand.tracked && basePose && s->delivered == XR_SESSION_STATE_FOCUSED && !in->script.hands[static_cast<std::size_t>(t->hand)].empty();
  out->isActive = active ? XR_TRUE : XR_FALSE;
  for (std::size_t j = 0; j < kJoints; ++j) {
    XrHandJointLocationEXT& loc = out->jointLocations[j];
    loc.locationFlags = 0;
    if (velocities != nullptr) velocities->jointVelocities[j].velocityFlags = 0;
    if (!active) continue;
    const Eigen::Isometry3d inv = basePose->inverse();
    loc.pose = toXr(inv * hand.joints[j]);
    loc.radius = hand.radii[j];
    loc.locationFlags = XR_SPACE_LOCATION_POSITION_VALID_BIT | XR_SPACE_LOCATION_ORIENTATION_VALID_BIT |
                        XR_SPACE_LOCATION_POSITION_TRACKED_BIT | XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT;
    if (velocities != nullptr && in->script.jointVelocities) {
      const auto [linear, angular] = velocityOf([&](double u) { return in->script.handAt(t->hand, u).joints[j]; }, time);
      velocities->jointVelocities[j].linearVelocity = toXr(Eigen::Vector3d(inv.linear() * linear));
      velocities->jointVelocities[j].angularVelocity = toXr(Eigen::Vector3d(inv.linear() * angular));
      velocities->jointVelocities[j].velocityFlags = XR_SPACE_VELOCITY_LINEAR_VALID_BIT | XR_SPACE_VELOCITY_ANGULAR_VALID_BIT;
    }
  }
  return record(fn, XR_SUCCESS);
}

// ---- dispatch ----

XrResult XRAPI_CALL getInstanceProcAddr(XrInstance instance, const char* name, PFN_xrVoidFunction* function);

struct Entry {
  const char* name;
  PFN_xrVoidFunction fn;
  const char* extension;  // nullptr: core
};

#define VAW_ENTRY(n, f, ext) Entry{n, reinterpret_cast<PFN_xrVoidFunction>(&f), ext}
const Entry kEntries[] = {
    VAW_ENTRY("xrGetInstanceProcAddr", getInstanceProcAddr, nullptr),
    VAW_ENTRY("xrEnumerateApiLayerProperties", enumerateLayers, nullptr),
    VAW_ENTRY("xrEnumerateInstanceExtensionProperties", enumerateExtensions, nullptr),
    VAW_ENTRY("xrCreateInstance", createInstance, nullptr),
    VAW_ENTRY("xrDestroyInstance", destroyInstance, nullptr),
    VAW_ENTRY("xrGetInstanceProperties", getInstanceProperties, nullptr),
    VAW_ENTRY("xrPollEvent", pollEvent, nullptr),
    VAW_ENTRY("xrResultToString", resultToString, nullptr),
    VAW_ENTRY("xrStructureTypeToString", structureTypeToString, nullptr),
    VAW_ENTRY("xrGetSystem", getSystem, nullptr),
    VAW_ENTRY("xrGetSystemProperties", getSystemProperties, nullptr),
    VAW_ENTRY("xrEnumerateEnvironmentBlendModes", enumerateBlendModes, nullptr),
    VAW_ENTRY("xrCreateSession", createSession, nullptr),
    VAW_ENTRY("xrDestroySession", destroySession, nullptr),
    VAW_ENTRY("xrEnumerateReferenceSpaces", enumerateReferenceSpaces, nullptr),
    VAW_ENTRY("xrCreateReferenceSpace", createReferenceSpace, nullptr),
    VAW_ENTRY("xrGetReferenceSpaceBoundsRect", getReferenceSpaceBoundsRect, nullptr),
    VAW_ENTRY("xrCreateActionSpace", createActionSpace, nullptr),
    VAW_ENTRY("xrLocateSpace", locateSpace, nullptr),
    VAW_ENTRY("xrDestroySpace", destroySpace, nullptr),
    VAW_ENTRY("xrEnumerateViewConfigurations", enumerateViewConfigurations, nullptr),
    VAW_ENTRY("xrGetViewConfigurationProperties", getViewConfigurationProperties, nullptr),
    VAW_ENTRY("xrEnumerateViewConfigurationViews", enumerateViewConfigurationViews, nullptr),
    VAW_ENTRY("xrEnumerateSwapchainFormats", enumerateSwapchainFormats, nullptr),
    VAW_ENTRY("xrCreateSwapchain", createSwapchain, nullptr),
    VAW_ENTRY("xrDestroySwapchain", destroySwapchain, nullptr),
    VAW_ENTRY("xrEnumerateSwapchainImages", enumerateSwapchainImages, nullptr),
    VAW_ENTRY("xrAcquireSwapchainImage", acquireSwapchainImage, nullptr),
    VAW_ENTRY("xrWaitSwapchainImage", waitSwapchainImage, nullptr),
    VAW_ENTRY("xrReleaseSwapchainImage", releaseSwapchainImage, nullptr),
    VAW_ENTRY("xrBeginSession", beginSession, nullptr),
    VAW_ENTRY("xrEndSession", endSession, nullptr),
    VAW_ENTRY("xrRequestExitSession", requestExitSession, nullptr),
    VAW_ENTRY("xrWaitFrame", waitFrame, nullptr),
    VAW_ENTRY("xrBeginFrame", beginFrame, nullptr),
    VAW_ENTRY("xrEndFrame", endFrame, nullptr),
    VAW_ENTRY("xrLocateViews", locateViews, nullptr),
    VAW_ENTRY("xrStringToPath", stringToPath, nullptr),
    VAW_ENTRY("xrPathToString", pathToString, nullptr),
    VAW_ENTRY("xrCreateActionSet", createActionSet, nullptr),
    VAW_ENTRY("xrDestroyActionSet", destroyActionSet, nullptr),
    VAW_ENTRY("xrCreateAction", createAction, nullptr),
    VAW_ENTRY("xrDestroyAction", destroyAction, nullptr),
    VAW_ENTRY("xrSuggestInteractionProfileBindings", suggestBindings, nullptr),
    VAW_ENTRY("xrAttachSessionActionSets", attachActionSets, nullptr),
    VAW_ENTRY("xrGetCurrentInteractionProfile", getCurrentInteractionProfile, nullptr),
    VAW_ENTRY("xrGetActionStateBoolean", getBoolean, nullptr),
    VAW_ENTRY("xrGetActionStateFloat", getFloat, nullptr),
    VAW_ENTRY("xrGetActionStateVector2f", getVector2f, nullptr),
    VAW_ENTRY("xrGetActionStatePose", getPose, nullptr),
    VAW_ENTRY("xrSyncActions", syncActions, nullptr),
    VAW_ENTRY("xrEnumerateBoundSourcesForAction", enumerateBoundSources, nullptr),
    VAW_ENTRY("xrGetInputSourceLocalizedName", getLocalizedName, nullptr),
    VAW_ENTRY("xrApplyHapticFeedback", applyHaptic, nullptr),
    VAW_ENTRY("xrStopHapticFeedback", stopHaptic, nullptr),
    VAW_ENTRY("xrGetOpenGLGraphicsRequirementsKHR", getOpenGLRequirements, XR_KHR_OPENGL_ENABLE_EXTENSION_NAME),
    VAW_ENTRY("xrCreateHandTrackerEXT", createHandTracker, XR_EXT_HAND_TRACKING_EXTENSION_NAME),
    VAW_ENTRY("xrDestroyHandTrackerEXT", destroyHandTracker, XR_EXT_HAND_TRACKING_EXTENSION_NAME),
    VAW_ENTRY("xrLocateHandJointsEXT", locateHandJoints, XR_EXT_HAND_TRACKING_EXTENSION_NAME),
};
#undef VAW_ENTRY

// Without an instance only the functions that create one are offered; an extension's functions only when it
// was enabled (the specification, xrGetInstanceProcAddr).
XrResult XRAPI_CALL getInstanceProcAddr(XrInstance instance, const char* name, PFN_xrVoidFunction* function) {
  if (name == nullptr || function == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  *function = nullptr;
  const std::string n = name;
  if (instance == XR_NULL_HANDLE) {
    if (n != "xrEnumerateInstanceExtensionProperties" && n != "xrEnumerateApiLayerProperties" && n != "xrCreateInstance" &&
        n != "xrGetInstanceProcAddr")
      return XR_ERROR_HANDLE_INVALID;
  } else if (lookup<Instance>(instance, Kind::Instance, "xrGetInstanceProcAddr") == nullptr) {
    return XR_ERROR_HANDLE_INVALID;
  }
  for (const Entry& e : kEntries) {
    if (n != e.name) continue;
    if (e.extension != nullptr) {
      const Instance* in = static_cast<const Instance*>(g_objects.at(instance).get());
      const bool enabled = std::string(e.extension) == XR_KHR_OPENGL_ENABLE_EXTENSION_NAME ? in->opengl : in->handTracking;
      if (!enabled) return XR_ERROR_FUNCTION_UNSUPPORTED;
    }
    *function = e.fn;
    return XR_SUCCESS;
  }
  return XR_ERROR_FUNCTION_UNSUPPORTED;
}

}  // namespace
}  // namespace vaw::simxr

extern "C" {

__attribute__((visibility("default"))) XrResult xrNegotiateLoaderRuntimeInterface(const XrNegotiateLoaderInfo* loaderInfo,
                                                                                    XrNegotiateRuntimeRequest* request) {
  if (loaderInfo == nullptr || request == nullptr || loaderInfo->structType != XR_LOADER_INTERFACE_STRUCT_LOADER_INFO ||
      loaderInfo->structVersion != 1 || loaderInfo->structSize != sizeof(XrNegotiateLoaderInfo) ||
      request->structType != XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST || request->structVersion != 1 ||
      request->structSize != sizeof(XrNegotiateRuntimeRequest) || loaderInfo->minInterfaceVersion > 1 ||
      loaderInfo->maxInterfaceVersion < 1 || XR_VERSION_MAJOR(loaderInfo->maxApiVersion) < 1)
    return XR_ERROR_INITIALIZATION_FAILED;
  request->runtimeInterfaceVersion = 1;
  request->runtimeApiVersion = XR_CURRENT_API_VERSION;
  request->getInstanceProcAddr = &vaw::simxr::getInstanceProcAddr;
  return XR_SUCCESS;
}

__attribute__((visibility("default"))) vaw::simxr::Record* vaw_simxr_record() { return &vaw::simxr::g_record; }

__attribute__((visibility("default"))) void vaw_simxr_reset() { vaw::simxr::g_record = {}; }

}
