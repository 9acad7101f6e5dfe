// Colour signatures of objects in their detection boxes, and their part in pairing the
// objects of two sessions (issue 19: flat objects carried past each other).

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "ocg/objects/change_log.h"
#include "ocg/objects/colour_signature.h"
#include "ocg/objects/object_map.h"

namespace ocg {
namespace {

// BGR colours.
const cv::Vec3b kRed(30, 30, 200), kYellow(40, 210, 220), kGreen(60, 160, 50), kBlue(190, 90, 40),
    kWood(70, 120, 170);

// A table of colour b speckled with a (a texture, not a flat colour), 160 x 120 pixels.
cv::Mat Table(const cv::Vec3b& a, const cv::Vec3b& b, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  cv::Mat image(120, 160, CV_8UC3);
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) image.at<cv::Vec3b>(y, x) = random() % 3 == 0 ? a : b;
  }
  return image;
}

// A flat object seen at a grazing angle: a thin band across the middle of box, covering
// about a third of it (less than half: a whole-box histogram is mostly the table).
const Box2 kBox{40, 30, 120, 90};
cv::Mat WithObject(cv::Mat image, const cv::Vec3b& colour, double shade = 1.0) {
  const cv::Scalar bgr(colour[0] * shade, colour[1] * shade, colour[2] * shade);
  cv::rectangle(image, cv::Point(48, 50), cv::Point(111, 69), bgr, cv::FILLED);
  return image;
}

ColourHistogram SignatureOf(const cv::Mat& image) {
  const std::optional<ColourHistogram> signature =
      BoxColourSignature(image, kBox, ColourSignatureOptions{});
  EXPECT_TRUE(signature.has_value());
  return signature.value_or(ColourHistogram{});
}

// A whole-box histogram with the same bins, for comparison: what a signature without the
// ring would be.
ColourHistogram WholeBoxHistogram(const cv::Mat& image) {
  // A box as large as the image has no ring: take the box alone, padded by a ring of
  // plain black, which the centre-minus-ring signature then leaves out.
  cv::Mat padded(image.rows * 3, image.cols * 3, CV_8UC3, cv::Scalar(0, 0, 0));
  const cv::Rect inner(image.cols, image.rows, image.cols, image.rows);
  image(cv::Rect(40, 30, 80, 60)).copyTo(padded(cv::Rect(inner.x, inner.y, 80, 60)));
  ColourSignatureOptions options;
  options.centre_share = 1.0 / 3.0;
  const Box2 around{inner.x - 80.0, inner.y - 60.0, inner.x + 160.0, inner.y + 120.0};
  return BoxColourSignature(padded, around, options).value();
}

TEST(ColourSignature, TheTableAroundAFlatObjectCancelsSoSwappedObjectsPairRight) {
  // A red and a yellow remote carried past each other between two sessions: each new box
  // holds the other's old table.
  const cv::Mat red_before = WithObject(Table(kWood, kGreen, 1), kRed);
  const cv::Mat yellow_before = WithObject(Table(kWood, kBlue, 2), kYellow);
  const cv::Mat red_after = WithObject(Table(kWood, kBlue, 3), kRed, 0.8);
  const cv::Mat yellow_after = WithObject(Table(kWood, kGreen, 4), kYellow, 0.8);
  const ColourHistogram red = SignatureOf(red_before), yellow = SignatureOf(yellow_before);
  const ColourHistogram red_again = SignatureOf(red_after),
                        yellow_again = SignatureOf(yellow_after);
  EXPECT_GT(ColourSimilarity(red, red_again), 0.8);
  EXPECT_GT(ColourSimilarity(yellow, yellow_again), 0.8);
  EXPECT_LT(ColourSimilarity(red, yellow_again), 0.2);
  EXPECT_LT(ColourSimilarity(yellow, red_again), 0.2);
  // What the ring is for: the whole box is mostly table, and pairs them crosswise.
  EXPECT_GT(ColourSimilarity(WholeBoxHistogram(red_before), WholeBoxHistogram(yellow_after)),
            ColourSimilarity(WholeBoxHistogram(red_before), WholeBoxHistogram(red_after)));
}

TEST(ColourSignature, NoneForABoxWithoutAnObjectOrTooSmall) {
  const cv::Mat table = Table(kWood, kGreen, 5);
  EXPECT_FALSE(BoxColourSignature(table, kBox, ColourSignatureOptions{}).has_value())
      << "the centre looks like the ring";
  const cv::Mat image = WithObject(table, kRed);
  EXPECT_FALSE(BoxColourSignature(image, {50, 50, 54, 90}, ColourSignatureOptions{}));
  EXPECT_FALSE(BoxColourSignature(image, {200, 50, 260, 90}, ColourSignatureOptions{}))
      << "outside the image";
  cv::Mat grey;
  cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  EXPECT_THROW(BoxColourSignature(grey, kBox, ColourSignatureOptions{}), std::invalid_argument);
  ColourSignatureOptions wrong;
  wrong.centre_share = 1.0;
  EXPECT_THROW(wrong.Check(), std::invalid_argument);
}

TEST(ColourSignature, MeanAndSimilarity) {
  ColourHistogram a{}, b{};
  a[0] = 1.0f;
  b[1] = 1.0f;
  EXPECT_DOUBLE_EQ(ColourSimilarity(a, a), 1.0);
  EXPECT_DOUBLE_EQ(ColourSimilarity(a, b), 0.0);
  const ColourHistogram mean = MeanColour({a, b, b, b}).value();
  EXPECT_FLOAT_EQ(mean[0], 0.25f);
  EXPECT_FLOAT_EQ(mean[1], 0.75f);
  EXPECT_FALSE(MeanColour({}).has_value());
}

ObjectChange RemovedRemote(ObjectId id, double x) {
  ObjectChange change;
  change.type = "removed";
  change.session = 1;
  change.object_id = id;
  change.class_id = 65;  // remote
  change.timestamp = 2010;
  change.last_seen = 1010;
  change.cuboid.centre = Eigen::Vector3d(x, 0, 0.8);
  change.cuboid.size = Eigen::Vector3d(0.15, 0.05, 0.02);
  change.sightings = 20;
  return change;
}
ObjectRecord LiveRemote(ObjectId id, double x) {
  ObjectRecord record;
  record.id = id;
  record.class_id = 65;
  record.cuboid.centre = Eigen::Vector3d(x, 0, 0.8);
  record.cuboid.size = Eigen::Vector3d(0.15, 0.05, 0.02);
  record.first_seen = 2005;
  record.last_seen = 2010;
  record.first_session = 1;
  return record;
}

// Session 1 removed remotes 3 (red) and 4 (yellow), last seen in session 0, and found
// remotes 9 and 10 each 0.2 from the other's old place (pair 2 of issue 19). Their boxes'
// descriptors match nothing of either; their colours tell which is which.
TEST(ChangeLog, BetweenSessionsFlatObjectsPairByColourWhereDescriptorsTellNothing) {
  const std::vector<ObjectChange> changes = {RemovedRemote(3, 0.0), RemovedRemote(4, 1.0)};
  const std::vector<ObjectRecord> objects = {LiveRemote(9, 1.2), LiveRemote(10, -0.2)};
  ChangeLogContext context;
  context.session = 1;
  context.session_start = 2000;
  const auto moved_to = [&] {
    std::map<ObjectId, ObjectId> to;
    const nlohmann::json revised =
        nlohmann::json::parse(ChangeLogJson(ReviseChangeLog(changes, objects, context)));
    for (const nlohmann::json& entry : revised.at("changes")) {
      if (entry["type"] == "moved")
        to[entry["object_id"].get<ObjectId>()] = entry["to"]["object_id"].get<ObjectId>();
    }
    return to;
  };
  EXPECT_EQ(moved_to(), (std::map<ObjectId, ObjectId>{{3, 10}, {4, 9}}))
      << "without colour, the nearer pairs";
  const ColourHistogram red = SignatureOf(WithObject(Table(kWood, kGreen, 1), kRed));
  const ColourHistogram yellow = SignatureOf(WithObject(Table(kWood, kBlue, 2), kYellow));
  const ColourHistogram red_again = SignatureOf(WithObject(Table(kWood, kBlue, 3), kRed, 0.8));
  const ColourHistogram yellow_again =
      SignatureOf(WithObject(Table(kWood, kGreen, 4), kYellow, 0.8));
  context.colour = {{3, red}, {4, yellow}, {9, red_again}, {10, yellow_again}};
  EXPECT_EQ(moved_to(), (std::map<ObjectId, ObjectId>{{3, 9}, {4, 10}}));
  // The evidence says so.
  const nlohmann::json revised =
      nlohmann::json::parse(ChangeLogJson(ReviseChangeLog(changes, objects, context)));
  const nlohmann::json& move = revised["changes"][0];
  ASSERT_EQ(move["type"], "moved");
  EXPECT_GT(move["appearance"]["colour_similarity"].get<double>(), 0.8);
  // Descriptors that tell the objects apart outweigh colour: two remotes of one colour
  // whose textures differ pair by texture, whatever the colours say.
  std::mt19937_64 random(7);
  const auto texture = [&] {
    std::vector<Descriptor> descriptors(30);
    for (Descriptor& descriptor : descriptors) {
      for (std::uint64_t& word : descriptor) word = random();
    }
    return descriptors;
  };
  const std::vector<Descriptor> first = texture(), second = texture();
  context.box_appearance = {{3, first}, {4, second}, {9, second}, {10, first}};
  EXPECT_EQ(moved_to(), (std::map<ObjectId, ObjectId>{{3, 10}, {4, 9}}));
}

}  // namespace
}  // namespace ocg
