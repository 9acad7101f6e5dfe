// Decoders of the three output layouts on constructed tensors, layout choice from shapes,
// and class-wise NMS.

#include "ocg/detect/decode.h"

#include <gtest/gtest.h>

#include "boxes.h"

#include <stdexcept>

namespace ocg {
namespace {

using testing::Box;

cv::Mat Tensor(std::vector<int> shape) { return cv::Mat(3, shape.data(), CV_32F, cv::Scalar(0)); }

float& At(cv::Mat& m, int i, int j) {
  return m.ptr<float>(0)[static_cast<std::size_t>(i) * m.size[2] + j];
}

TEST(ChooseLayout, RecognisesTheThreeLayoutsFromTheirShapes) {
  const ModelOutputs v5 = ChooseLayout({{1, 25200, 85}}, {640, 640});
  EXPECT_EQ(v5.layout, OutputLayout::kYoloV5);
  EXPECT_EQ(v5.num_classes, 80);
  const ModelOutputs v8 = ChooseLayout({{1, 84, 8400}}, {640, 640});
  EXPECT_EQ(v8.layout, OutputLayout::kYoloV8);
  EXPECT_EQ(v8.num_classes, 80);
  const ModelOutputs nano = ChooseLayout(
      {{1, 169, 80}, {1, 2704, 44}, {1, 676, 80}, {1, 2704, 80}, {1, 676, 44}, {1, 169, 44}},
      {416, 416});
  EXPECT_EQ(nano.layout, OutputLayout::kNanoDet);
  EXPECT_EQ(nano.num_classes, 80);
}

TEST(ChooseLayout, RefusesShapesOfNoKnownLayoutNamingThem) {
  try {
    ChooseLayout({{1, 1000}}, {416, 416});
    FAIL() << "no exception";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("[1, 1000]"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("YOLOv8"), std::string::npos) << error.what();
  }
  // NanoDet-like pairs whose cell counts fit no stride of the input.
  EXPECT_THROW(ChooseLayout({{1, 170, 80}, {1, 170, 44}}, {416, 416}), std::invalid_argument);
}

TEST(DecodeYoloV5, BoxFromCentreAndScoreIsObjectnessTimesClass) {
  cv::Mat out = Tensor({1, 3, 85});
  // Anchor 0: a cup (41) at centre (100, 50), 40 x 20, objectness 0.9, class 0.8.
  At(out, 0, 0) = 100;
  At(out, 0, 1) = 50;
  At(out, 0, 2) = 40;
  At(out, 0, 3) = 20;
  At(out, 0, 4) = 0.9f;
  At(out, 0, 5 + 41) = 0.8f;
  At(out, 0, 5 + 2) = 0.3f;
  // Anchor 1: confident class but low objectness: 0.5 * 0.5 = 0.25 < 0.3.
  At(out, 1, 4) = 0.5f;
  At(out, 1, 5 + 7) = 0.5f;
  At(out, 1, 2) = 10;
  At(out, 1, 3) = 10;
  const ModelOutputs model{OutputLayout::kYoloV5, 80};
  const std::vector<Detection> boxes = DecodeOutputs(model, {out}, {640, 640}, 0.3);
  ASSERT_EQ(boxes.size(), 1u);
  EXPECT_EQ(boxes[0].class_id, 41);
  EXPECT_NEAR(boxes[0].confidence, 0.72, 1e-6);
  EXPECT_DOUBLE_EQ(boxes[0].x, 80);
  EXPECT_DOUBLE_EQ(boxes[0].y, 40);
  EXPECT_DOUBLE_EQ(boxes[0].width, 40);
  EXPECT_DOUBLE_EQ(boxes[0].height, 20);
}

TEST(DecodeYoloV8, ReadsChannelsFirstAndTakesTheBestClass) {
  cv::Mat out = Tensor({1, 84, 4});  // channel k of anchor a at (k, a)
  const int a = 2;
  At(out, 0, a) = 320;
  At(out, 1, a) = 240;
  At(out, 2, a) = 100;
  At(out, 3, a) = 60;
  At(out, 4 + 62, a) = 0.7f;  // tv
  At(out, 4 + 63, a) = 0.6f;  // laptop, less
  At(out, 4 + 0, 1) = 0.2f;   // anchor 1 below the threshold
  const ModelOutputs model{OutputLayout::kYoloV8, 80};
  const std::vector<Detection> boxes = DecodeOutputs(model, {out}, {640, 640}, 0.25);
  ASSERT_EQ(boxes.size(), 1u);
  EXPECT_EQ(boxes[0].class_id, 62);
  EXPECT_NEAR(boxes[0].confidence, 0.7, 1e-6);
  EXPECT_DOUBLE_EQ(boxes[0].x, 270);
  EXPECT_DOUBLE_EQ(boxes[0].y, 210);
  EXPECT_DOUBLE_EQ(boxes[0].width, 100);
  EXPECT_DOUBLE_EQ(boxes[0].height, 60);
}

TEST(DecodeNanoDet, SideDistancesFromTheBinDistributionAroundTheCellCentre) {
  // A 64 x 64 input: strides 8, 16, 32 give 64, 16 and 4 cells; 40 classes, 8 bins a side.
  const cv::Size input(64, 64);
  std::vector<cv::Mat> outputs;
  for (int cells : {64, 16, 4}) {
    outputs.push_back(Tensor({1, cells, 40}));
    outputs.push_back(Tensor({1, cells, 32}));
  }
  // Stride 16 level (outputs 2 and 3), cell 6 = row 1, column 2: centre (40, 24).
  At(outputs[2], 6, 1) = 0.9f;
  float* d = &At(outputs[3], 6, 0);
  d[0 * 8 + 1] = 50;  // left: bin 1 (softmax one-hot) -> 16 px
  d[1 * 8 + 0] = 50;  // top: bin 0 -> 0 px
  d[2 * 8 + 2] = 50;  // right: bin 2 -> 32 px
  d[3 * 8 + 0] = 50;  // bottom: half in bin 0, half in bin 2 -> 1 bin = 16 px
  d[3 * 8 + 2] = 50;
  const ModelOutputs model = ChooseLayout(
      {{1, 64, 40}, {1, 64, 32}, {1, 16, 40}, {1, 16, 32}, {1, 4, 40}, {1, 4, 32}}, input);
  ASSERT_EQ(model.layout, OutputLayout::kNanoDet);
  const std::vector<Detection> boxes = DecodeOutputs(model, outputs, input, 0.5);
  ASSERT_EQ(boxes.size(), 1u);
  EXPECT_EQ(boxes[0].class_id, 1);
  EXPECT_NEAR(boxes[0].x, 40 - 16, 1e-6);
  EXPECT_NEAR(boxes[0].y, 24 - 0, 1e-6);
  EXPECT_NEAR(boxes[0].width, 16 + 32, 1e-6);
  EXPECT_NEAR(boxes[0].height, 0 + 16, 1e-6);
}

TEST(ClassWiseNms, SuppressesOverlapsWithinAClassOnly) {
  const std::vector<Detection> kept =
      ClassWiseNms({Box(41, 0, 0, 10, 10, 0.6), Box(41, 1, 0, 10, 10, 0.9),
                    Box(39, 1, 0, 10, 10, 0.5), Box(41, 30, 0, 10, 10, 0.4)},
                   0.5);
  ASSERT_EQ(kept.size(), 3u);
  EXPECT_DOUBLE_EQ(kept[0].confidence, 0.9);  // the cup kept is the most confident
  EXPECT_EQ(kept[1].class_id, 39);            // the bottle on it is another class
  EXPECT_DOUBLE_EQ(kept[2].x, 30);            // the far cup does not overlap
}

TEST(ClassWiseNms, KeepsOverlapsAtOrBelowTheThreshold) {
  // IoU of these two: 5 * 10 / (100 + 100 - 50) = 1/3.
  EXPECT_EQ(ClassWiseNms({Box(0, 0, 0, 10, 10, 0.9), Box(0, 5, 0, 10, 10, 0.8)}, 0.5).size(), 2u);
  EXPECT_EQ(ClassWiseNms({Box(0, 0, 0, 10, 10, 0.9), Box(0, 5, 0, 10, 10, 0.8)}, 0.3).size(), 1u);
}

}  // namespace
}  // namespace ocg
