#include "blendbench/render/video.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

#include "support/scratch.hpp"

namespace blendbench {
namespace {

namespace fs = std::filesystem;

// A fresh directory per test, removed afterwards.
class VideoWriterTest : public ::testing::Test {
 protected:

  [[nodiscard]] std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename().string());
    return names;
  }

  const test::ScratchDir scratch_{"video"};
  const fs::path& dir_ = scratch_.path();
};

// A frame with a moving gradient, so the encoder has something to encode.
std::vector<std::uint8_t> frame(int width, int height, int k) {
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width * height * 3));
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const auto i = static_cast<std::size_t>((y * width + x) * 3);
      rgb[i] = static_cast<std::uint8_t>(x + 4 * k);
      rgb[i + 1] = static_cast<std::uint8_t>(y);
      rgb[i + 2] = static_cast<std::uint8_t>(128);
    }
  return rgb;
}

// ffprobe's key=value description of the first video stream.
std::map<std::string, std::string> probe(const fs::path& file) {
  const std::string command = "ffprobe -v error -select_streams v:0 -count_frames -show_entries "
                              "stream=codec_name,width,height,nb_read_frames,r_frame_rate,pix_fmt "
                              "-of default=noprint_wrappers=1 '" + file.string() + "'";
  std::map<std::string, std::string> out;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return out;
  char line[256];
  while (std::fgets(line, sizeof line, pipe) != nullptr) {
    std::string text(line);
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
    const auto eq = text.find('=');
    if (eq != std::string::npos) out[text.substr(0, eq)] = text.substr(eq + 1);
  }
  pclose(pipe);
  return out;
}

TEST_F(VideoWriterTest, ThirtyFramesMakeAnH264Mp4WithTheRightSizeCountAndRate) {
  const fs::path target = dir_ / "video.mp4";
  VideoWriter writer(target.string(), 320, 240, 30);
  for (int k = 0; k < 30; ++k) writer.write(frame(320, 240, k));
  writer.finish();
  EXPECT_EQ(writer.frames(), 30);
  ASSERT_TRUE(fs::exists(target));
  EXPECT_EQ(entries(), std::vector<std::string>{"video.mp4"});  // no temporary left behind

  const auto info = probe(target);
  EXPECT_EQ(info.at("codec_name"), "h264");
  EXPECT_EQ(info.at("width"), "320");
  EXPECT_EQ(info.at("height"), "240");
  EXPECT_EQ(info.at("pix_fmt"), "yuv420p");
  EXPECT_EQ(info.at("nb_read_frames"), "30");
  EXPECT_EQ(info.at("r_frame_rate"), "30/1");
}

// The video gets the mode of the run's other outputs, 0666 less the umask (mkostemp's 0600 would
// make it alone private), under a loose and a strict umask.
TEST_F(VideoWriterTest, VideoHasTheModeOfANewFileUnderTheUmask) {
  for (const mode_t mask : {mode_t{022}, mode_t{077}}) {
    const mode_t saved = ::umask(mask);
    const fs::path target = dir_ / ("video_" + std::to_string(mask) + ".mp4");
    VideoWriter writer(target.string(), 64, 48, 25);
    for (int k = 0; k < 3; ++k) writer.write(frame(64, 48, k));
    writer.finish();
    ::umask(saved);
    struct stat st {};
    ASSERT_EQ(::stat(target.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0666 & ~mask) << "umask " << std::oct << mask;
  }
}

TEST_F(VideoWriterTest, WriterDestroyedWithoutFinishLeavesNoFile) {
  const fs::path target = dir_ / "video.mp4";
  {
    VideoWriter writer(target.string(), 64, 48, 25);
    for (int k = 0; k < 5; ++k) writer.write(frame(64, 48, k));
    EXPECT_EQ(entries().size(), 1u);  // the temporary, under another name
    EXPECT_FALSE(fs::exists(target));
  }
  EXPECT_TRUE(entries().empty());
}

TEST_F(VideoWriterTest, FinishWithoutFramesIsAnErrorAndLeavesNoFile) {
  VideoWriter writer((dir_ / "video.mp4").string(), 64, 48, 25);
  EXPECT_THROW(writer.finish(), std::runtime_error);
  EXPECT_TRUE(entries().empty());
}

TEST_F(VideoWriterTest, WrongFrameSizeIsRejected) {
  VideoWriter writer((dir_ / "video.mp4").string(), 64, 48, 25);
  EXPECT_THROW(writer.write(frame(64, 47, 0)), std::invalid_argument);
}

TEST_F(VideoWriterTest, OddSizeIsPaddedToEven) {
  const fs::path target = dir_ / "odd.mp4";
  VideoWriter writer(target.string(), 65, 47, 24);
  for (int k = 0; k < 3; ++k) writer.write(frame(65, 47, k));
  writer.finish();
  const auto info = probe(target);
  EXPECT_EQ(info.at("width"), "66");
  EXPECT_EQ(info.at("height"), "48");
}

TEST_F(VideoWriterTest, MissingDirectoryIsAnError) {
  EXPECT_THROW(VideoWriter((dir_ / "no" / "such" / "video.mp4").string(), 64, 48, 25), std::runtime_error);
}

TEST_F(VideoWriterTest, FfmpegFailureIsReportedWithItsMessageAndDoesNotKillTheProcess) {
  // an "ffmpeg" first on PATH that complains and exits without reading: writes hit a closed pipe
  // (SIGPIPE must not end the test process) and the error carries its message
  const fs::path bin = dir_ / "bin";
  fs::create_directory(bin);
  {
    FILE* script = std::fopen((bin / "ffmpeg").c_str(), "w");
    ASSERT_NE(script, nullptr);
    std::fputs("#!/bin/sh\necho 'fake ffmpeg: encoder exploded' >&2\nexit 3\n", script);
    std::fclose(script);
  }
  fs::permissions(bin / "ffmpeg", fs::perms::owner_all);
  const std::string old_path = std::getenv("PATH") != nullptr ? std::getenv("PATH") : "";
  setenv("PATH", (bin.string() + ":" + old_path).c_str(), 1);
  std::string message;
  try {
    VideoWriter writer((dir_ / "video.mp4").string(), 320, 240, 25);
    for (int k = 0; k < 50; ++k) writer.write(frame(320, 240, k));
    writer.finish();
  } catch (const std::runtime_error& e) {
    message = e.what();
  }
  setenv("PATH", old_path.c_str(), 1);
  EXPECT_NE(message.find("encoder exploded"), std::string::npos) << message;
  EXPECT_EQ(entries(), std::vector<std::string>{"bin"});
}

}  // namespace
}  // namespace blendbench
