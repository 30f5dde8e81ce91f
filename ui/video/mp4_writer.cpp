#include "vaw/video/mp4_writer.hpp"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include <system_error>

#include "vaw/error.hpp"

namespace vaw::video {

namespace {

std::string averror(int code) {
  char b[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, b, sizeof b);
  return b;
}

}  // namespace

struct Mp4Writer::Impl {
  AVFormatContext* format = nullptr;
  AVCodecContext* codec = nullptr;
  AVStream* stream = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* packet = nullptr;
  SwsContext* scale = nullptr;
  bool open = false;  // the file's AVIO

  // The packet from the encoder in the file's time base, each lasting one frame: without its duration the
  // file's length would end where its last frame starts, and players would drop that frame.
  void stamp() {
    if (packet->duration == 0) packet->duration = 1;
    av_packet_rescale_ts(packet, codec->time_base, stream->time_base);
    packet->stream_index = stream->index;
  }

  ~Impl() {
    sws_freeContext(scale);
    av_packet_free(&packet);
    av_frame_free(&frame);
    avcodec_free_context(&codec);
    if (format != nullptr) {
      if (open) avio_closep(&format->pb);
      avformat_free_context(format);
    }
  }
};

Mp4Writer::Mp4Writer(const std::filesystem::path& file, int width, int height, int fps)
    : impl_(std::make_unique<Impl>()), file_(file), part_(file.parent_path() / ("." + file.filename().string() + ".writing")) {
  const auto refuse = [&](const std::string& why) { throw OutputError(file.string() + ": not written: " + why); };
  if (width <= 0 || height <= 0 || width % 2 != 0 || height % 2 != 0)
    refuse("the picture must be an even number of pixels wide and high, not " + std::to_string(width) + " x " + std::to_string(height));
  if (fps <= 0) refuse("the frame rate must be positive, not " + std::to_string(fps));
  Impl& m = *impl_;
  // FFmpeg's own messages (libx264 prints its statistics at the end) would go to stderr past vaw's: the
  // errors come back through the calls' results instead.
  av_log_set_level(AV_LOG_ERROR);
  if (avformat_alloc_output_context2(&m.format, nullptr, "mp4", part_.c_str()) < 0 || m.format == nullptr) refuse("FFmpeg has no MP4 writer");
  const AVCodec* codec = avcodec_find_encoder_by_name("libx264");
  if (codec == nullptr) codec = avcodec_find_encoder(AV_CODEC_ID_H264);
  if (codec == nullptr) refuse("FFmpeg has no H.264 encoder (Debian's libavcodec has libx264)");
  encoder_ = codec->name;
  m.stream = avformat_new_stream(m.format, nullptr);
  m.codec = avcodec_alloc_context3(codec);
  m.frame = av_frame_alloc();
  m.packet = av_packet_alloc();
  if (m.stream == nullptr || m.codec == nullptr || m.frame == nullptr || m.packet == nullptr) throw std::bad_alloc();
  m.codec->width = width;
  m.codec->height = height;
  m.codec->time_base = AVRational{1, fps};
  m.codec->framerate = AVRational{fps, 1};
  m.codec->pix_fmt = AV_PIX_FMT_YUV420P;
  m.codec->gop_size = 2 * fps;  // a key frame every two seconds, so a player can seek
  // What libswscale's RGB to YUV conversion uses by default, said in the stream so players undo it.
  m.codec->colorspace = AVCOL_SPC_SMPTE170M;
  m.codec->color_range = AVCOL_RANGE_MPEG;
  if ((m.format->oformat->flags & AVFMT_GLOBALHEADER) != 0) m.codec->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
  if (encoder_ == "libx264") {
    // Fast enough to keep up with real time on two cores without a GPU (docs/benchmarks.md), sharp enough
    // for the caption's text.
    av_opt_set(m.codec->priv_data, "preset", "veryfast", 0);
    av_opt_set(m.codec->priv_data, "crf", "20", 0);
  }
  if (const int r = avcodec_open2(m.codec, codec, nullptr); r < 0) refuse("the " + encoder_ + " encoder does not open: " + averror(r));
  if (avcodec_parameters_from_context(m.stream->codecpar, m.codec) < 0) throw std::bad_alloc();
  m.stream->time_base = m.codec->time_base;
  if (const int r = avio_open(&m.format->pb, part_.c_str(), AVIO_FLAG_WRITE); r < 0) refuse("cannot write " + part_.string() + ": " + averror(r));
  m.open = true;
  if (const int r = avformat_write_header(m.format, nullptr); r < 0) refuse("cannot start the file: " + averror(r));
  m.frame->format = AV_PIX_FMT_YUV420P;
  m.frame->width = width;
  m.frame->height = height;
  if (av_frame_get_buffer(m.frame, 0) < 0) throw std::bad_alloc();
  m.scale = sws_getContext(width, height, AV_PIX_FMT_RGBA, width, height, AV_PIX_FMT_YUV420P, SWS_BILINEAR, nullptr, nullptr, nullptr);
  if (m.scale == nullptr) refuse("FFmpeg cannot convert RGBA pictures to YUV 4:2:0");
}

Mp4Writer::~Mp4Writer() {
  impl_.reset();
  std::error_code ec;
  std::filesystem::remove(part_, ec);  // nothing there once finish() has put the file in place
}

void Mp4Writer::add(const std::uint8_t* rgba, int stride) {
  Impl& m = *impl_;
  if (av_frame_make_writable(m.frame) < 0) throw std::bad_alloc();
  const std::uint8_t* const planes[1] = {rgba};
  const int strides[1] = {stride};
  sws_scale(m.scale, planes, strides, 0, m.codec->height, m.frame->data, m.frame->linesize);
  m.frame->pts = frames_++;
  const auto drain = [&](const AVFrame* f) {
    if (const int r = avcodec_send_frame(m.codec, f); r < 0) throw OutputError(file_.string() + ": not written: the encoder refused a picture: " + averror(r));
    for (;;) {
      const int r = avcodec_receive_packet(m.codec, m.packet);
      if (r == AVERROR(EAGAIN) || r == AVERROR_EOF) return;
      if (r < 0) throw OutputError(file_.string() + ": not written: the encoder failed: " + averror(r));
      m.stamp();
      const int w = av_interleaved_write_frame(m.format, m.packet);
      if (w < 0) throw OutputError(file_.string() + ": not written: cannot write " + part_.string() + ": " + averror(w));
    }
  };
  drain(m.frame);
}

void Mp4Writer::finish() {
  Impl& m = *impl_;
  if (avcodec_send_frame(m.codec, nullptr) >= 0) {
    while (avcodec_receive_packet(m.codec, m.packet) == 0) {
      m.stamp();
      if (const int w = av_interleaved_write_frame(m.format, m.packet); w < 0)
        throw OutputError(file_.string() + ": not written: cannot write " + part_.string() + ": " + averror(w));
    }
  }
  if (const int r = av_write_trailer(m.format); r < 0) throw OutputError(file_.string() + ": not written: cannot finish the file: " + averror(r));
  if (const int r = avio_closep(&m.format->pb); r < 0) throw OutputError(file_.string() + ": not written: cannot close " + part_.string() + ": " + averror(r));
  m.open = false;
  std::error_code ec;
  std::filesystem::rename(part_, file_, ec);
  if (ec) throw OutputError(file_.string() + ": cannot put the written file in place: " + ec.message());
}

}  // namespace vaw::video
