#pragma once
// What the simulated OpenXR runtime (libvaw_simxr_runtime.so) saw and did, for the tests: every call with its
// result and the session state it was made in, every state the application was told of, every frame it
// submitted, the images of the frames the script asked for, and every breach of the specification it caught
// in the application's calls. The tests link the library, so the loader's dlopen of the same file shares
// this record with them; a test clears it with vaw_simxr_reset() before starting a session.
#include <openxr/openxr.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace vaw::simxr {

struct Call {
  const char* function = "";
  XrResult result = XR_SUCCESS;
  XrSessionState state = XR_SESSION_STATE_UNKNOWN;  // the session's state as the application knew it
};

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  // top row first
};

struct SubmittedFrame {
  std::int64_t displayTime = 0;
  double t = 0.0;  // s of script time
  std::uint32_t layerCount = 0;
  std::array<XrPosef, 2> eyePoses{};  // in the projection layer's space
  std::array<XrFovf, 2> fovs{};
};

struct Capture {
  double t = 0.0;
  std::array<Image, 2> eyes;
};

struct Record {
  std::string script;
  std::vector<Call> calls;
  std::vector<XrSessionState> states;  // delivered by xrPollEvent, in order
  std::vector<SubmittedFrame> frames;
  std::vector<Capture> captures;
  std::vector<std::string> violations;
  int instancesCreated = 0, instancesDestroyed = 0;
  int sessionsCreated = 0, sessionsDestroyed = 0;
  std::size_t liveHandles = 0;  // handles created and not yet destroyed (directly or with their parent)
};

}  // namespace vaw::simxr

extern "C" {
vaw::simxr::Record* vaw_simxr_record();
void vaw_simxr_reset();
}
