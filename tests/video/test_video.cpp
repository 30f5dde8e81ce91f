// Videos (docs/sharing.md) decoded back: the frame count, size and duration the options ask for, and the
// decoded pictures against the pictures the video was made from (the renderer's frame with its caption),
// within what H.264's lossy coding leaves. Bad options and files that cannot be written are named errors
// that leave no file.
#include <gtest/gtest.h>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libswscale/swscale.h>
}

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <QtGui/QImage>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "bundled.hpp"
#include "files.hpp"
#include "vaw/error.hpp"
#include "vaw/evaluation/sequence.hpp"
#include "vaw/gl/gl_renderer.hpp"
#include "vaw/gl/headless_gl.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/sim/scene.hpp"
#include "vaw/sim/session.hpp"
#include "vaw/video/video.hpp"

namespace fs = std::filesystem;

namespace {

struct Decoded {
  std::string codec;
  int width = 0, height = 0;
  double duration = 0.0;     // s, the container's
  std::vector<QImage> frames;  // RGBA, top row first
};

// Every frame of `file` through libavformat and libavcodec, converted to RGBA as a player shows it.
Decoded decode(const fs::path& file) {
  Decoded d;
  AVFormatContext* format = nullptr;
  if (avformat_open_input(&format, file.c_str(), nullptr, nullptr) < 0) return d;
  avformat_find_stream_info(format, nullptr);
  const int s = av_find_best_stream(format, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
  const AVCodecParameters* par = format->streams[s]->codecpar;
  const AVCodec* codec = avcodec_find_decoder(par->codec_id);
  AVCodecContext* ctx = avcodec_alloc_context3(codec);
  avcodec_parameters_to_context(ctx, par);
  avcodec_open2(ctx, codec, nullptr);
  d.codec = codec->name;
  d.width = par->width;
  d.height = par->height;
  d.duration = static_cast<double>(format->duration) / AV_TIME_BASE;
  AVPacket* packet = av_packet_alloc();
  AVFrame* frame = av_frame_alloc();
  SwsContext* scale = nullptr;
  const auto take = [&] {
    while (avcodec_receive_frame(ctx, frame) == 0) {
      scale = sws_getCachedContext(scale, frame->width, frame->height, static_cast<AVPixelFormat>(frame->format), frame->width, frame->height,
                                   AV_PIX_FMT_RGBA, SWS_BILINEAR, nullptr, nullptr, nullptr);
      QImage image(frame->width, frame->height, QImage::Format_RGBA8888);
      std::uint8_t* planes[1] = {image.bits()};
      const int strides[1] = {static_cast<int>(image.bytesPerLine())};
      sws_scale(scale, frame->data, frame->linesize, 0, frame->height, planes, strides);
      d.frames.push_back(image);
    }
  };
  while (av_read_frame(format, packet) >= 0) {
    if (packet->stream_index == s) {
      avcodec_send_packet(ctx, packet);
      take();
    }
    av_packet_unref(packet);
  }
  avcodec_send_packet(ctx, nullptr);
  take();
  sws_freeContext(scale);
  av_frame_free(&frame);
  av_packet_free(&packet);
  avcodec_free_context(&ctx);
  avformat_close_input(&format);
  return d;
}

// Peak signal to noise over the colour channels, dB: above 30 dB two pictures look alike.
double psnr(const QImage& a, const QImage& b) {
  double sum = 0.0;
  std::size_t n = 0;
  for (int y = 0; y < a.height(); ++y) {
    const std::uint8_t* p = a.constScanLine(y);
    const std::uint8_t* q = b.constScanLine(y);
    for (int x = 0; x < a.width(); ++x)
      for (int c = 0; c < 3; ++c, ++n) {
        const double e = static_cast<double>(p[4 * x + c]) - static_cast<double>(q[4 * x + c]);
        sum += e * e;
      }
  }
  const double mse = sum / static_cast<double>(n);
  return mse > 0.0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : 99.0;
}

// The bundled scene the session was recorded on, checked to be the one.
std::shared_ptr<const vaw::sim::Scene> sceneOf(const vaw::sim::Session& session) {
  auto scene = vaw::sim::Scene::build(vaw::test::loadBundled("sleeve-on-shaft.vaw.json"));
  vaw::sim::checkScene(session, *scene);
  return scene;
}

bool leftovers(const fs::path& dir) {
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().find(".writing") != std::string::npos) return true;
  return false;
}

}  // namespace

// The sleeve turned off its shaft (a recorded session), its first two seconds at 10 frames a second.
TEST(Video, ASessionDecodesBackAsTheFramesItWasMadeFrom) {
  const vaw::sim::Session session = vaw::sim::loadSession(fs::path(VAW_SOURCE_DIR) / "tests/sim/data/sleeve-turnover-v1.vaw-session.json");
  const auto scene = sceneOf(session);
  vaw::video::VideoOptions o;
  o.width = 320;
  o.height = 180;
  o.fps = 10;
  o.to = 2.0;
  const fs::path file = vaw::test::tempDir() / "sleeve.mp4";
  std::vector<double> heard;
  const vaw::video::VideoResult r = vaw::video::writeSessionVideo(scene, session, file, o, [&](double f, const std::string&) {
    heard.push_back(f);
    return true;
  });
  EXPECT_EQ(r.frames, 21);  // 0, 0.1, ..., 2.0 s
  EXPECT_EQ(r.encoder, "libx264");
  ASSERT_FALSE(heard.empty());
  EXPECT_DOUBLE_EQ(heard.back(), 1.0);
  const Decoded d = decode(file);
  EXPECT_EQ(d.codec, "h264");
  EXPECT_EQ(d.width, 320);
  EXPECT_EQ(d.height, 180);
  ASSERT_EQ(d.frames.size(), 21U);
  EXPECT_NEAR(d.duration, 2.1, 0.01);
  // The first and the middle frame, decoded, against the pictures they were made from: the scene at rest
  // and the base being turned, each with its caption.
  for (const std::int64_t k : {0, 10}) {
    const QImage made = vaw::video::sessionPicture(scene, session, o, k).convertToFormat(QImage::Format_RGBA8888);
    ASSERT_EQ(made.size(), d.frames[static_cast<std::size_t>(k)].size());
    const double db = psnr(made, d.frames[static_cast<std::size_t>(k)]);
    std::printf("frame %lld decoded against the picture made: %.1f dB\n", static_cast<long long>(k), db);
    EXPECT_GT(db, 30.0) << "frame " << k;
  }
  // Frames apart in time differ: the video moves.
  EXPECT_LT(psnr(d.frames[0], d.frames[20]), 30.0);
  EXPECT_FALSE(leftovers(file.parent_path()));
}

// The bundled bracket's order: one step after another, two seconds each at 5 frames a second.
TEST(Video, AnOrderPlaysEveryStepInItsTurn) {
  const auto scene = vaw::sim::Scene::build(vaw::loadAny(vaw::test::resources() / "step" / "bolted-bracket.stp", vaw::test::importers()));
  const vaw::eval::SequencePlan plan = vaw::eval::planSequence(scene->assembly());
  ASSERT_TRUE(plan.complete());
  vaw::video::VideoOptions o;
  o.width = 320;
  o.height = 180;
  o.fps = 5;
  o.stepSeconds = 1.0;
  const fs::path file = vaw::test::tempDir() / "order.mp4";
  const vaw::video::VideoResult r = vaw::video::writeOrderVideo(scene, plan, file, o);
  const auto expected = static_cast<std::int64_t>(plan.order.size()) * 5 + 1;
  EXPECT_EQ(r.frames, expected);
  const Decoded d = decode(file);
  ASSERT_EQ(static_cast<std::int64_t>(d.frames.size()), expected);
  // Each step adds a part: the picture at the end of a step differs from the one at its start.
  for (std::size_t i = 1; i < plan.order.size(); ++i)
    EXPECT_LT(psnr(d.frames[5 * i], d.frames[5 * i + 4]), 45.0) << "step " << i;
}

// With sweeps, each way's swept volume and nearest pass are drawn over its step: the gear's step looks
// different from the same step without them; the base's step (it has no way) does not.
TEST(Video, AnOrderWithSweepsShowsEachWaysVolumeInItsStep) {
  const auto scene = vaw::sim::Scene::build(vaw::test::loadBundled("gear-on-shaft.vaw.json"));
  const vaw::eval::SequencePlan plan = vaw::eval::planSequence(scene->assembly());
  ASSERT_EQ(plan.order.size(), 2U);
  vaw::video::VideoOptions o;
  o.width = 320;
  o.height = 180;
  o.fps = 5;
  o.stepSeconds = 1.0;
  const fs::path plainFile = vaw::test::tempDir() / "plain.mp4", sweptFile = vaw::test::tempDir() / "swept.mp4";
  (void)vaw::video::writeOrderVideo(scene, plan, plainFile, o);
  o.sweepVoxel = 0.003;
  std::vector<std::string> heard;
  const vaw::video::VideoResult r = vaw::video::writeOrderVideo(scene, plan, sweptFile, o, [&](double, const std::string& what) {
    heard.push_back(what);
    return true;
  });
  EXPECT_EQ(r.sweeps, 1);
  ASSERT_FALSE(heard.empty());
  EXPECT_EQ(heard.front().rfind("swept volumes: ", 0), 0U) << heard.front();
  const Decoded plain = decode(plainFile), swept = decode(sweptFile);
  ASSERT_EQ(plain.frames.size(), 11U);
  ASSERT_EQ(swept.frames.size(), 11U);
  EXPECT_GT(psnr(plain.frames[2], swept.frames[2]), 45.0) << "the base's step has no way";
  EXPECT_LT(psnr(plain.frames[7], swept.frames[7]), 40.0) << "the gear's way drawn over its step";
  o.sweepVoxel = -1.0;
  EXPECT_THROW((void)vaw::video::writeOrderVideo(scene, plan, sweptFile, o), vaw::InputError);
}

TEST(Video, WhatCannotBeWrittenIsANamedErrorAndLeavesNoFile) {
  const vaw::sim::Session session = vaw::sim::loadSession(fs::path(VAW_SOURCE_DIR) / "tests/sim/data/sleeve-turnover-v1.vaw-session.json");
  const auto scene = sceneOf(session);
  vaw::video::VideoOptions o;
  o.width = 160;
  o.height = 90;
  o.fps = 5;
  // A folder that is not there.
  const fs::path missing = vaw::test::tempDir() / "no-such-folder" / "v.mp4";
  try {
    (void)vaw::video::writeSessionVideo(scene, session, missing, o);
    FAIL() << "written into a folder that does not exist";
  } catch (const vaw::OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("no-such-folder/v.mp4: not written"), std::string::npos) << e.what();
  }
  // An odd height, a span outside the recording, a part the scene lacks: named, nothing written.
  const fs::path file = vaw::test::tempDir() / "bad.mp4";
  vaw::video::VideoOptions odd = o;
  odd.height = 91;
  EXPECT_THROW((void)vaw::video::writeSessionVideo(scene, session, file, odd), vaw::InputError);
  vaw::video::VideoOptions late = o;
  late.from = 1e4;
  try {
    (void)vaw::video::writeSessionVideo(scene, session, file, late);
    FAIL() << "a span after the recording was taken";
  } catch (const vaw::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("from/to"), std::string::npos) << e.what();
  }
  vaw::video::VideoOptions follow = o;
  follow.camera = *vaw::video::parseCamera("follow gear");
  try {
    (void)vaw::video::writeSessionVideo(scene, session, file, follow);
    FAIL() << "a camera following a part the scene lacks was taken";
  } catch (const vaw::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("\"gear\""), std::string::npos) << e.what();
  }
  EXPECT_FALSE(vaw::video::parseCamera("sideways"));
  // An eye on what it looks at, or with no field of view: named, nothing written.
  vaw::video::VideoOptions eye = o;
  eye.camera.kind = vaw::video::Camera::Kind::Eye;
  eye.camera.position = eye.camera.target = Eigen::Vector3d(0.1, 0.2, 0.3);
  for (const double fov : {35.0, 0.0}) {
    if (fov == 0.0) eye.camera.position = Eigen::Vector3d(0.5, -0.5, 0.5);
    eye.camera.verticalFovDeg = fov;
    try {
      (void)vaw::video::writeSessionVideo(scene, session, file, eye);
      FAIL() << "an eye camera that cannot see was taken (field of view " << fov << ")";
    } catch (const vaw::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("camera: expected an eye apart from what it looks at"), std::string::npos) << e.what();
    }
  }
  // Stopped after its third frame: no file, nothing half-written.
  int frames = 0;
  EXPECT_THROW((void)vaw::video::writeSessionVideo(scene, session, file, o, [&](double, const std::string&) { return ++frames < 3; }),
               vaw::LoadCancelled);
  EXPECT_EQ(frames, 3);
  EXPECT_FALSE(fs::exists(file));
  EXPECT_FALSE(leftovers(file.parent_path()));
}

namespace {

// `renderer`'s picture of `frame` from `eye`, read back (bottom row first, as OpenGL gives it).
QImage drawn(vaw::xr::GlRenderer& renderer, const vaw::xr::EyeView& eye, const vaw::view::Frame& frame, int width, int height) {
  GLuint texture = 0, fbo = 0;
  glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  renderer.render(texture, width, height, eye, &frame, vaw::xr::HandsSample{});
  glGenFramebuffers(1, &fbo);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
  glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
  QImage image(width, height, QImage::Format_RGBA8888);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, image.bits());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glDeleteFramebuffers(1, &fbo);
  glDeleteTextures(1, &texture);
  return image;
}

// Pixels whose colour differs by more than one level in a channel.
int differing(const QImage& a, const QImage& b) {
  int n = 0;
  for (int y = 0; y < a.height(); ++y) {
    const std::uint8_t* p = a.constScanLine(y);
    const std::uint8_t* q = b.constScanLine(y);
    for (int x = 0; x < a.width(); ++x) {
      bool d = false;
      for (int c = 0; c < 3; ++c) d = d || std::abs(static_cast<int>(p[4 * x + c]) - static_cast<int>(q[4 * x + c])) > 1;
      n += d ? 1 : 0;
    }
  }
  return n;
}

}  // namespace

// A video's camera holds still, so what did not move is drawn once into a layer and copied under each
// frame (GlRenderer's still layer). Drawn with and without the layer, a scene whose sleeve starts to move
// and moves on gives the same pictures, and the layer is made only when a part in it moves.
TEST(Video, TheStillLayerChangesNoPicture) {
  const auto scene = vaw::sim::Scene::build(vaw::test::loadBundled("sleeve-on-shaft.vaw.json"));
  const vaw::Assembly& a = scene->assembly();
  const vaw::view::SceneDescription described = vaw::view::describe(a);
  const vaw::PartId sleeve = *a.findPart("sleeve");
  vaw::gl::HeadlessGl gl;
  vaw::xr::GlRenderer layered, plain;
  layered.setScene(described);
  layered.keepStillLayer(true);
  plain.setScene(described);

  vaw::xr::EyeView eye;
  const Eigen::Vector3d centre = described.partsBounds.center();
  const Eigen::Vector3d back = Eigen::Vector3d(0.6, -0.9, 0.6).normalized(), right = Eigen::Vector3d::UnitZ().cross(back).normalized();
  eye.pose.linear().col(0) = right;
  eye.pose.linear().col(1) = back.cross(right);
  eye.pose.linear().col(2) = back;
  eye.pose.translation() = centre + 0.6 * back;
  eye.angleLeft = eye.angleDown = -0.4;
  eye.angleRight = eye.angleUp = 0.4;

  vaw::view::Frame frame;
  frame.parts.resize(a.parts.size());
  for (vaw::PartId p = 0; p < a.parts.size(); ++p) {
    frame.parts[p].pose = a.parts[p].pose;
    if (described.partDrawable[p]) frame.parts[p].color = described.drawables[*described.partDrawable[p]].color;
  }
  constexpr int kW = 320, kH = 240;
  // At rest twice (the layer made of everything), then the sleeve moved three times and held once.
  for (const double dx : {0.0, 0.0, 0.03, 0.06, 0.06}) {
    frame.parts[sleeve].pose.translation() = a.parts[sleeve].pose.translation() + Eigen::Vector3d(dx, 0.0, 0.0);
    const QImage withLayer = drawn(layered, eye, frame, kW, kH), without = drawn(plain, eye, frame, kW, kH);
    EXPECT_LE(differing(withLayer, without), kW * kH / 2000) << "sleeve moved " << dx << " m";
  }
  // Made for the scene at rest and again once the sleeve moved; every frame after the first over one.
  EXPECT_EQ(layered.stillLayerUse().made, 2);
  EXPECT_EQ(layered.stillLayerUse().drawnOver, 4);
  EXPECT_EQ(plain.stillLayerUse().made, 0);
  ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
}
