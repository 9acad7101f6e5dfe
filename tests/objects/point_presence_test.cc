// OCG.mode "points": an object the detector missed is present when its own map points are
// found, by descriptor, among the keyframe's keypoints near their projections
// (SearchPointsInFrame, PresentByPoints with a frame). Constructed frames: keypoints placed
// at the projections of an object's points, carrying its descriptors (still there) or
// other ones (its old place after a move).

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "ocg/objects/object_map.h"
#include "ocg/objects/point_presence.h"
#include "ocg/ocg/change_detector.h"
#include "test_support.h"

namespace ocg {
namespace {

constexpr double kPi = 3.14159265358979323846;

PinholeCamera Camera() { return testing::TestCamera(525.0, 319.5, 239.5); }

// The camera 1.5 m from the object, looking at it along world x (world z up).
SE3 FacingTheObject() {
  Eigen::Matrix3d R_wc;
  R_wc << Eigen::Vector3d(0, -1, 0), Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(1, 0, 0);
  return SE3(R_wc, Eigen::Vector3d(-1.5, 0, 0.8)).Inverse();
}

// The same camera turned round (the object behind it), and turned 60 degrees aside (the
// object's points project outside the image).
SE3 TurnedBy(const SE3& T_cw, double angle) {
  return SE3(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitY()).toRotationMatrix(),
             Eigen::Vector3d::Zero()) *
         T_cw;
}

Descriptor RandomDescriptor(std::mt19937_64& random) {
  return {random(), random(), random(), random()};
}

// A 0.1 m object of 10 map points (a 5 x 2 grid) at (0, 0, 0.8), voted for, each with a
// descriptor of its own.
MapObject TexturedObject(std::mt19937_64& random) {
  MapObject object;
  object.id = 1;
  object.class_id = 58;  // potted plant
  object.has_cuboid = true;
  object.cuboid.centre = Eigen::Vector3d(0, 0, 0.8);
  object.cuboid.size = Eigen::Vector3d(0.1, 0.1, 0.1);
  for (std::uint64_t id = 0; id < 10; ++id) {
    const Eigen::Vector3d offset(0.0, 0.02 * (static_cast<int>(id % 5) - 2),
                                 0.04 * static_cast<int>(id / 5) - 0.02);
    object.points.Vote(id, 3, object.cuboid.centre + offset);
    object.points.SetDescriptor(object.points.find(id), RandomDescriptor(random));
  }
  return object;
}

// A frame's features: keypoints at the given undistorted pixels, levels and descriptors.
ExtractedFeatures MakeFeatures(const std::vector<Eigen::Vector2d>& pixels,
                               const std::vector<int>& levels,
                               const std::vector<Descriptor>& descriptors) {
  ExtractedFeatures features;
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    cv::KeyPoint keypoint(static_cast<float>(pixels[i].x()), static_cast<float>(pixels[i].y()),
                          31.0f);
    keypoint.octave = levels[i];
    features.keypoints.push_back(keypoint);
  }
  features.undistorted = pixels;
  features.descriptors = descriptors;
  features.grid = FeatureGrid(pixels, levels, UndistortedImageBounds(Camera()));
  return features;
}

// What a keyframe at T_cw shows at the object's place: a keypoint 1.5 px off each of its
// points' projections, with the point's descriptor when still_there, else with other
// texture (its old place after a move: the table behind it), and some clutter elsewhere.
ExtractedFeatures FrameAtTheObjectsPlace(const MapObject& object, const SE3& T_cw, bool still_there,
                                         std::mt19937_64& random) {
  std::vector<Eigen::Vector2d> pixels;
  std::vector<Descriptor> descriptors;
  for (const auto& [id, point] : object.points) {
    pixels.push_back(Camera().ProjectUndistorted(T_cw * point.position) +
                     Eigen::Vector2d(1.5, -1.0));
    descriptors.push_back(still_there ? *point.descriptor : RandomDescriptor(random));
  }
  for (int i = 0; i < 50; ++i) {
    pixels.emplace_back(10.0 + 12.0 * i, 40.0 + 7.0 * (i % 9));
    descriptors.push_back(RandomDescriptor(random));
  }
  return MakeFeatures(pixels, std::vector<int>(pixels.size(), 0), descriptors);
}

FrameFeatureSearch SearchOf(const ExtractedFeatures& features) {
  FrameFeatureSearch search;
  search.features = &features;
  search.pyramid = MakeScalePyramid(8, 1.2);
  return search;  // radius 4, 100 bits, ratio 0.8: the defaults of the settings they come from
}

TEST(PointSearch, APointIsFoundWithinTheWindowOfTheKeypointsLevel) {
  std::mt19937_64 random(7);
  const Descriptor texture = RandomDescriptor(random);
  const Eigen::Vector2d projection(300, 200);
  // 6 px off: outside level 0's window (4 px), inside level 3's (4 x 1.2^3 = 6.9 px).
  for (const auto& [level, found] : {std::pair{0, false}, std::pair{3, true}}) {
    const ExtractedFeatures features =
        MakeFeatures({projection + Eigen::Vector2d(6, 0)}, {level}, {texture});
    const int match = MatchAtProjection(projection, texture, SearchOf(features), {false});
    EXPECT_EQ(match >= 0, found) << "level " << level;
  }
}

TEST(PointSearch, OtherTextureOrTwoLookAlikesAreNoMatch) {
  std::mt19937_64 random(8);
  const Descriptor texture = RandomDescriptor(random);
  const Eigen::Vector2d projection(300, 200);
  Descriptor near = texture;
  near[0] ^= 0xFFFFFULL;  // 20 bits off: the same texture seen again
  Descriptor far = texture;
  far[0] = ~far[0];  // 128 bits off: other texture, over Matcher.looseDistance (100)
  far[1] = ~far[1];
  const auto match = [&](const std::vector<Descriptor>& descriptors) {
    std::vector<Eigen::Vector2d> pixels;
    for (std::size_t i = 0; i < descriptors.size(); ++i)
      pixels.push_back(projection + Eigen::Vector2d(1.0 + i, 0));
    const ExtractedFeatures features =
        MakeFeatures(pixels, std::vector<int>(pixels.size(), 0), descriptors);
    return MatchAtProjection(projection, texture, SearchOf(features),
                             std::vector<bool>(pixels.size(), false));
  };
  EXPECT_EQ(match({near}), 0);
  EXPECT_EQ(match({far}), -1);
  EXPECT_EQ(match({near, near}), -1) << "two equal candidates: the ratio test refuses both";
  EXPECT_EQ(match({far, near}), 1);
}

// (a) An object the detector missed whose points are found at their projections is
// present, though tracking saw none of them (the tracker follows its local map).
TEST(PresentByPoints, ItsOwnPointsFoundInTheFrameSayPresentWithoutTracking) {
  std::mt19937_64 random(1);
  const MapObject object = TexturedObject(random);
  const SE3 T_cw = FacingTheObject();
  ASSERT_EQ(ObjectPointIds(object, 3).size(), 10u);
  const ExtractedFeatures features = FrameAtTheObjectsPlace(object, T_cw, true, random);
  const FrameFeatureSearch search = SearchOf(features);
  const ObjectsOptions options;
  EXPECT_FALSE(PresentByPoints(object, {}, T_cw, Camera(), options)) << "no frame to search";
  EXPECT_TRUE(PresentByPoints(object, {}, T_cw, Camera(), options, &search));
  std::vector<PointToFind> points;
  for (const auto& [id, point] : object.points)
    points.push_back({point.position, *point.descriptor});
  const PointSearchCount count = SearchPointsInFrame(points, T_cw, Camera(), search);
  EXPECT_EQ(count.in_image, 10);
  EXPECT_EQ(count.found, 10);
}

// (b) After the object was carried away its place shows other texture: nothing is found,
// and neither are its points when its texture is elsewhere in the image (at its new place).
TEST(PresentByPoints, TheOldPlaceOfAMovedObjectDoesNotSayPresent) {
  std::mt19937_64 random(2);
  const MapObject object = TexturedObject(random);
  const SE3 T_cw = FacingTheObject();
  const ObjectsOptions options;
  const ExtractedFeatures old_place = FrameAtTheObjectsPlace(object, T_cw, false, random);
  const FrameFeatureSearch search_old_place = SearchOf(old_place);
  EXPECT_FALSE(PresentByPoints(object, {}, T_cw, Camera(), options, &search_old_place));
  MapObject moved = object;  // 0.3 m to the side: its texture there, the table at its place
  moved.cuboid.centre += Eigen::Vector3d(0, 0.3, 0);
  for (auto point = moved.points.begin(); point != moved.points.end(); ++point)
    moved.points.Move(point, point->second.position + Eigen::Vector3d(0, 0.3, 0));
  const ExtractedFeatures new_place = FrameAtTheObjectsPlace(moved, T_cw, true, random);
  const FrameFeatureSearch search_new_place = SearchOf(new_place);
  EXPECT_TRUE(PresentByPoints(moved, {}, T_cw, Camera(), options, &search_new_place));
  EXPECT_FALSE(PresentByPoints(object, {}, T_cw, Camera(), options, &search_new_place));
}

// (c) Points behind the camera or outside the image are not searched: no evidence, even
// when the frame holds keypoints with their descriptors.
TEST(PresentByPoints, PointsOutOfViewGiveNoEvidence) {
  std::mt19937_64 random(3);
  const MapObject object = TexturedObject(random);
  const SE3 T_cw = FacingTheObject();
  const ExtractedFeatures features = FrameAtTheObjectsPlace(object, T_cw, true, random);
  const FrameFeatureSearch search = SearchOf(features);
  const ObjectsOptions options;
  std::vector<PointToFind> points;
  for (const auto& [id, point] : object.points)
    points.push_back({point.position, *point.descriptor});
  ASSERT_TRUE(PresentByPoints(object, {}, T_cw, Camera(), options, &search)) << "from in front";
  for (const SE3& away : {TurnedBy(T_cw, kPi), TurnedBy(T_cw, kPi / 3)}) {
    EXPECT_FALSE(PresentByPoints(object, {}, away, Camera(), options, &search));
    const PointSearchCount count = SearchPointsInFrame(points, away, Camera(), search);
    EXPECT_EQ(count.in_image, 0);
    EXPECT_EQ(count.found, 0);
  }
}

// The OCG with the evidence: the camera looks at the table (the object and three
// neighbours), turns to the shelf, and comes back twice while the detector finds the
// neighbours and misses the object; then it leaves. frame_shows_it: the keyframes at the
// table show the object's texture at its points (still there) or other texture (moved).
// Returns the removals.
std::vector<RemovalEvent> MissedAtTheTable(const std::string& mode, bool frame_shows_it) {
  std::mt19937_64 random(4);
  const MapObject object = TexturedObject(random);
  const SE3 table = FacingTheObject();
  const SE3 shelf = TurnedBy(table, kPi);
  const std::map<ObjectId, Eigen::Vector3d> places = {{1, {0, 0, 0.8}},    {2, {0, 0.3, 0.8}},
                                                      {3, {0, -0.3, 0.8}}, {4, {0.2, 0, 0.8}},
                                                      {5, {-3, 0, 0.8}},   {6, {-3, 0.3, 0.8}}};
  OcgOptions options;
  options.mode = mode;
  ObjectChangeDetector detector(options);
  const ExtractedFeatures features = FrameAtTheObjectsPlace(object, table, frame_shows_it, random);
  const FrameFeatureSearch search = SearchOf(features);
  struct Look {
    SE3 T_cw;
    std::vector<ObjectId> detected;
  };
  const std::vector<Look> looks = {{table, {1, 2, 3, 4}},
                                   {shelf, {5, 6}},
                                   {table, {2, 3, 4}},
                                   {table, {2, 3, 4}},
                                   {shelf, {5, 6}}};
  std::vector<RemovalEvent> removed;
  std::int64_t keyframe = 0;
  for (const Look& look : looks) {
    KeyframeObservation observation;
    observation.keyframe_id = keyframe;
    observation.timestamp = 0.5 * static_cast<double>(keyframe++);
    observation.T_cw = look.T_cw;
    observation.camera = Camera();
    observation.observed = look.detected;
    for (ObjectId id : look.detected) {
      observation.updates[id].centroid = places.at(id);
      observation.updates[id].size = Eigen::Vector3d(0.1, 0.1, 0.1);
    }
    const bool missed =
        std::find(look.detected.begin(), look.detected.end(), 1) == look.detected.end();
    if (missed && PresentByPoints(object, {}, look.T_cw, Camera(), ObjectsOptions{}, &search))
      observation.present_by_points.push_back(1);
    for (const RemovalEvent& event : detector.Process(observation).removed)
      removed.push_back(event);
  }
  return removed;
}

TEST(PointPresenceStory, AnObjectMissedWhoseTextureIsAtItsPointsStays) {
  ASSERT_EQ(MissedAtTheTable("fallback+in_image+guard+view+restore+dropout", true).size(), 1u)
      << "detections alone: removed";
  EXPECT_TRUE(MissedAtTheTable("improved", true).empty());
  EXPECT_TRUE(MissedAtTheTable("points", true).empty());
}

TEST(PointPresenceStory, AnObjectMovedAwayIsRemovedWithTheEvidenceOn) {
  for (const std::string mode : {"fallback+in_image+guard+view+restore+dropout", "improved"}) {
    const std::vector<RemovalEvent> removed = MissedAtTheTable(mode, false);
    ASSERT_EQ(removed.size(), 1u) << mode;
    EXPECT_EQ(removed[0].object_id, 1) << mode;
  }
}

}  // namespace
}  // namespace ocg
