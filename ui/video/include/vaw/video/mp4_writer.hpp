#pragma once
// Pictures to an H.264 video in an MP4 file through FFmpeg's libraries (Debian's libavcodec, libavformat,
// libswscale; libx264 as the encoder). The file is written under a temporary name beside the target and
// renamed into place by finish(), so a video that fails (no room, a bad path, no encoder) or is stopped
// leaves no half file.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

namespace vaw::video {

class Mp4Writer {
 public:
  // `width` and `height` even (H.264's 4:2:0 colour), `fps` frames a second. Throws vaw::OutputError
  // naming the file: no H.264 encoder, a folder that cannot be written.
  Mp4Writer(const std::filesystem::path& file, int width, int height, int fps);
  ~Mp4Writer();
  Mp4Writer(const Mp4Writer&) = delete;
  Mp4Writer& operator=(const Mp4Writer&) = delete;

  // One picture: `height` rows of `width` RGBA pixels, top row first, `stride` bytes apart.
  void add(const std::uint8_t* rgba, int stride);
  // Flushes the encoder, writes the index and puts the file in place. Without it the file never appears.
  void finish();

  [[nodiscard]] std::int64_t frames() const { return frames_; }
  [[nodiscard]] const std::string& encoder() const { return encoder_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::filesystem::path file_, part_;
  std::int64_t frames_ = 0;
  std::string encoder_;
};

}  // namespace vaw::video
