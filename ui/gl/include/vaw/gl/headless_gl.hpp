#pragma once
// An OpenGL 3.3 core context with no window and no display, through EGL: a GPU's driver on the device
// platform where there is one, else Mesa's software device or its surfaceless platform. The videos render
// in one (docs/sharing.md), and so does the headset renderer's benchmark.
#include <string>

namespace vaw::gl {

class HeadlessGl {
 public:
  // Made current on the calling thread. Throws std::runtime_error saying what EGL lacked.
  HeadlessGl();
  ~HeadlessGl();
  HeadlessGl(const HeadlessGl&) = delete;
  HeadlessGl& operator=(const HeadlessGl&) = delete;

  // Which platform gave the display ("device 0 of 2 (software)", "surfaceless").
  [[nodiscard]] const std::string& platform() const { return platform_; }

 private:
  void* display_ = nullptr;
  void* context_ = nullptr;
  std::string platform_;
};

}  // namespace vaw::gl
