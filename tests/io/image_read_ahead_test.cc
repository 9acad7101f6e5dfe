#include "ocg/io/image_read_ahead.h"

#include <gtest/gtest.h>

#include <any>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "ocg/core/file_io.h"

namespace ocg {
namespace {

class ImageReadAheadTest : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ =
        std::filesystem::temp_directory_path() /
        ("ocg_read_ahead_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(folder_);
  }
  void TearDown() override { std::filesystem::remove_all(folder_); }

  // Image i is 32x24, every pixel i * 10 + its row: each image and each row differ.
  std::string WriteImage(int i) {
    cv::Mat image(24, 32, CV_8UC1);
    for (int row = 0; row < image.rows; ++row) image.row(row).setTo(i * 10 + row);
    const std::string path = (folder_ / (std::to_string(i) + ".png")).string();
    cv::imwrite(path, image);
    return path;
  }

  std::filesystem::path folder_;
};

TEST_F(ImageReadAheadTest, GivesTheImagesInOrderAsReadingThemOneByOne) {
  std::vector<std::string> paths;
  for (int i = 0; i < 12; ++i) paths.push_back(WriteImage(i));
  for (const std::size_t depth : {std::size_t{0}, std::size_t{3}}) {
    ImageReadAhead reader(paths, cv::IMREAD_GRAYSCALE, depth);
    for (const std::string& path : paths) {
      ASSERT_TRUE(reader.HasNext());
      const cv::Mat expected = cv::imread(path, cv::IMREAD_GRAYSCALE);
      const cv::Mat image = reader.Next();
      ASSERT_EQ(image.size(), expected.size());
      EXPECT_EQ(cv::countNonZero(image != expected), 0) << path << ", depth " << depth;
    }
    EXPECT_FALSE(reader.HasNext());
    EXPECT_THROW(reader.Next(), std::logic_error);
  }
}

TEST_F(ImageReadAheadTest, AnUnreadableImageFailsInItsTurnNamingTheFile) {
  std::vector<std::string> paths;
  for (int i = 0; i < 3; ++i) paths.push_back(WriteImage(i));
  const std::string broken = (folder_ / "broken.png").string();
  std::ofstream(broken) << "not a PNG";
  paths.push_back(broken);
  paths.push_back(WriteImage(4));
  for (const std::size_t depth : {std::size_t{0}, std::size_t{2}}) {
    ImageReadAhead reader(paths, cv::IMREAD_GRAYSCALE, depth);
    for (int i = 0; i < 3; ++i) EXPECT_FALSE(reader.Next().empty());
    try {
      reader.Next();
      FAIL() << "an unreadable image was returned";
    } catch (const FileError& error) {
      EXPECT_NE(std::string(error.what()).find("broken.png"), std::string::npos) << error.what();
    }
    // The images after it are still given.
    EXPECT_EQ(reader.Next().at<unsigned char>(0, 0), 40);
  }
}

// The prepare function's result comes with its own image, in order, at every depth, and
// its exception is rethrown when that image is taken, the later images still given.
TEST_F(ImageReadAheadTest, GivesWhatPrepareMadeOfEachImageWithIt) {
  std::vector<std::string> paths;
  for (int i = 0; i < 8; ++i) paths.push_back(WriteImage(i));
  const ImageReadAhead::Prepare first_pixel = [](std::size_t, const cv::Mat& image) -> std::any {
    const int value = image.at<unsigned char>(0, 0);
    if (value == 30) throw std::runtime_error("prepare failed on image 3");
    return value;
  };
  for (const std::size_t depth : {std::size_t{0}, std::size_t{3}}) {
    ImageReadAhead reader(paths, cv::IMREAD_GRAYSCALE, depth, first_pixel);
    for (int i = 0; i < 8; ++i) {
      if (i == 3) {
        EXPECT_THROW(reader.NextFrame(), std::runtime_error) << "depth " << depth;
        continue;
      }
      const ImageReadAhead::Frame frame = reader.NextFrame();
      EXPECT_EQ(frame.image.at<unsigned char>(0, 0), i * 10);
      ASSERT_TRUE(frame.prepared.has_value());
      EXPECT_EQ(std::any_cast<int>(frame.prepared), i * 10) << "image " << i << ", depth " << depth;
    }
  }
  ImageReadAhead plain(paths, cv::IMREAD_GRAYSCALE, 2);
  EXPECT_FALSE(plain.NextFrame().prepared.has_value());
}

// ocg_slam --realtime: an image the live camera replaced is neither read nor prepared
// (here its file does not exist, and prepare would fail on it), and comes empty.
TEST_F(ImageReadAheadTest, ASkippedImageIsNeitherReadNorPrepared) {
  std::vector<std::string> paths;
  for (int i = 0; i < 6; ++i) {
    paths.push_back(i % 2 == 1 ? (folder_ / "missing.png").string() : WriteImage(i));
  }
  const ImageReadAhead::Prepare prepare = [](std::size_t, const cv::Mat& image) -> std::any {
    const int value = image.at<unsigned char>(0, 0);
    if (value % 20 != 0) throw std::runtime_error("an odd image was prepared");
    return value;
  };
  const ImageReadAhead::Skip odd = [](std::size_t index) { return index % 2 == 1; };
  for (const std::size_t depth : {std::size_t{0}, std::size_t{2}}) {
    ImageReadAhead reader(paths, cv::IMREAD_GRAYSCALE, depth, prepare, odd);
    for (int i = 0; i < 6; ++i) {
      const ImageReadAhead::Frame frame = reader.NextFrame();
      if (i % 2 == 1) {
        EXPECT_TRUE(frame.image.empty()) << "image " << i << ", depth " << depth;
        EXPECT_FALSE(frame.prepared.has_value());
      } else {
        ASSERT_FALSE(frame.image.empty()) << "image " << i << ", depth " << depth;
        EXPECT_EQ(std::any_cast<int>(frame.prepared), i * 10);
      }
    }
  }
  // Without the skip the same files fail in their turn.
  ImageReadAhead reader(paths, cv::IMREAD_GRAYSCALE, 2, prepare);
  reader.Next();
  EXPECT_THROW(reader.Next(), FileError);
}

// ocg_slam --realtime starts the camera's clock once the first image is ready.
TEST_F(ImageReadAheadTest, WaitForNextReturnsOnceTheNextImageIsPrepared) {
  const std::vector<std::string> paths = {WriteImage(0), WriteImage(1)};
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  const ImageReadAhead::Prepare held = [released](std::size_t, const cv::Mat&) -> std::any {
    released.wait();
    return 0;
  };
  ImageReadAhead reader(paths, cv::IMREAD_GRAYSCALE, 2, held);
  std::atomic<bool> ready{false};
  std::thread waiter([&] {
    reader.WaitForNext();
    ready = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_FALSE(ready.load()) << "returned before the first image was prepared";
  release.set_value();
  waiter.join();
  EXPECT_TRUE(ready.load());
  EXPECT_EQ(reader.NextFrame().image.at<unsigned char>(0, 0), 0);
}

TEST_F(ImageReadAheadTest, StopsWithoutWaitingForImagesNobodyTakes) {
  std::vector<std::string> paths;
  for (int i = 0; i < 8; ++i) paths.push_back(WriteImage(i));
  {
    ImageReadAhead reader(paths, cv::IMREAD_GRAYSCALE, 1);
    EXPECT_EQ(reader.Next().at<unsigned char>(5, 0), 5);
  }  // the reader waits with a full queue; destruction must end it
  SUCCEED();
}

}  // namespace
}  // namespace ocg
