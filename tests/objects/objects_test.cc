// The object layer: assignment, ray intersection, cuboid estimation, detection filtering,
// and the object map on a scene of known cuboids seen by a moving camera.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <tuple>

#include "ocg/io/trajectory.h"
#include "ocg/objects/assignment.h"
#include "ocg/objects/map_hygiene.h"
#include "ocg/objects/object_geometry.h"
#include "ocg/objects/object_map.h"
#include "test_support.h"

namespace ocg {
namespace {

constexpr double kPi = 3.14159265358979323846;

PinholeCamera Camera() { return testing::TestCamera(525.0, 319.5, 239.5); }

// A camera at centre looking at target (world z up).
SE3 LookFrom(const Eigen::Vector3d& centre, const Eigen::Vector3d& target) {
  const Eigen::Vector3d forward = (target - centre).normalized();
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Matrix3d R_wc;
  R_wc << right, down, forward;
  return SE3(R_wc, centre).Inverse();
}

SE3 OrbitPose(double azimuth, const Eigen::Vector3d& target = Eigen::Vector3d(0, 0, 0.8)) {
  // On a circle of radius 1.5 m at the given azimuth, 0.5 m above the target.
  return LookFrom(target + Eigen::Vector3d(1.5 * std::cos(azimuth), 1.5 * std::sin(azimuth), 0.5),
                  target);
}

TEST(Assignment, FindsTheLeastTotalCost) {
  Eigen::MatrixXd cost(3, 3);
  cost << 4, 1, 3,  //
      2, 0, 5,      //
      3, 2, 2;
  // Greedy would take (1,1)=0 then (0,?)...; the optimum is 0->1, 1->0, 2->2 (total 5).
  EXPECT_EQ(SolveAssignment(cost), (std::vector<int>{1, 0, 2}));
}

TEST(Assignment, RectangularAndForbiddenPairs) {
  Eigen::MatrixXd wide(2, 3);
  wide << 5, 1, 9,  //
      1, 2, 9;
  EXPECT_EQ(SolveAssignment(wide), (std::vector<int>{1, 0}));
  Eigen::MatrixXd tall = wide.transpose();  // 3 rows, 2 columns: one row unassigned
  EXPECT_EQ(SolveAssignment(tall), (std::vector<int>{1, 0, -1}));
  Eigen::MatrixXd forbidden(2, 2);
  forbidden << kForbiddenCost, kForbiddenCost,  //
      0.5, kForbiddenCost;
  EXPECT_EQ(SolveAssignment(forbidden), (std::vector<int>{-1, 0}));
  EXPECT_TRUE(SolveAssignment(Eigen::MatrixXd(0, 4)).empty());
}

TEST(IntersectRays, RecoversThePointAndRejectsAStrayRay) {
  const Eigen::Vector3d point(0.2, -0.1, 0.9);
  std::vector<Ray> rays;
  for (int i = 0; i < 8; ++i) {
    const SE3 T_cw = OrbitPose(0.1 * i);
    const Eigen::Vector3d origin = T_cw.Inverse().translation();
    rays.push_back({origin, (point - origin).normalized()});
  }
  const Eigen::Vector3d stray_origin = rays[3].origin;
  rays.push_back(
      {stray_origin, (point + Eigen::Vector3d(0.4, 0.3, 0) - stray_origin).normalized()});
  const RayIntersection result = IntersectRays(rays);
  ASSERT_TRUE(result.valid);
  EXPECT_LT((result.point - point).norm(), 1e-3);
  EXPECT_EQ(result.inlier_count, 8);
  EXPECT_FALSE(result.inliers.back());
  EXPECT_NEAR(result.parallax_deg, 0.7 * 180 / kPi, 3.0);  // the azimuths span 0.7 rad
}

// Issue 18 (fr3's mid-air bottle): the spread of the rays was twice the widest angle to
// their mean direction, which overstates it when most views sit at one end of the
// baseline: seven views within 0.3 degrees of azimuth and one 3 degrees away (rays 2.85
// degrees apart) read 4.7 degrees, past Objects.candidate_min_parallax_deg (4). On fr3 the
// shelf's bottles were promoted from 3.0-3.8 degrees read as 4.0-4.8.
TEST(IntersectRays, ParallaxIsTheLargestAngleBetweenTwoRaysWhenTheViewsAreLopsided) {
  const Eigen::Vector3d point(0, 0, 0.8);
  std::vector<Ray> rays;
  const double degree = kPi / 180;
  for (double azimuth : {0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 3.0}) {
    const Eigen::Vector3d origin = OrbitPose(azimuth * degree, point).Inverse().translation();
    rays.push_back({origin, (point - origin).normalized()});
  }
  const RayIntersection result = IntersectRays(rays);
  ASSERT_TRUE(result.valid);
  // The orbit's azimuth is about the vertical through the point, with the camera 0.5 m
  // above it at 1.5 m: the rays' angle is the azimuth step times cos(elevation).
  const double elevation = std::atan2(0.5, 1.5);
  EXPECT_NEAR(result.parallax_deg, 3.0 * std::cos(elevation), 0.02);
  EXPECT_LT(result.parallax_deg, ObjectsOptions().candidate_min_parallax_deg);
}

TEST(IntersectRays, ParallelRaysHaveNoIntersection) {
  std::vector<Ray> rays = {{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d::UnitX()},
                           {Eigen::Vector3d(0, 1, 0), Eigen::Vector3d::UnitX()}};
  EXPECT_FALSE(IntersectRays(rays).valid);
  EXPECT_FALSE(IntersectRays({rays[0]}).valid);
}

// A box of the given size on a table, turned by 0.5 rad.
Cuboid TurnedBox(const Eigen::Vector3d& size) {
  Cuboid box;
  box.centre = Eigen::Vector3d(0, 0, 0.8);
  box.size = size;
  box.yaw = 0.5;
  return box;
}

TEST(EstimateCuboid, SizeAndYawFromBoxesAllAround) {
  const Cuboid truth = TurnedBox(Eigen::Vector3d(0.4, 0.2, 0.15));
  const Eigen::Matrix3d R_wg = GravityFrame(Eigen::Vector3d::UnitZ());
  std::vector<BoxView> views;
  for (int i = 0; i < 24; ++i) {
    const SE3 T_cw = OrbitPose(2 * kPi * i / 24);
    views.push_back({T_cw, *ProjectCuboid(truth, R_wg, T_cw, Camera())});
  }
  const Cuboid estimate = EstimateCuboid(truth.centre, views, Camera(), R_wg);
  // Box extents seen in perspective are a little larger than the object: within 20 %.
  const double long_side = std::max(estimate.size.x(), estimate.size.y());
  const double short_side = std::min(estimate.size.x(), estimate.size.y());
  EXPECT_NEAR(long_side, 0.4, 0.08);
  EXPECT_NEAR(short_side, 0.2, 0.05);
  EXPECT_NEAR(estimate.size.z(), 0.15, 0.05);
  // Yaw of the long side, modulo 180 degrees.
  const double long_yaw =
      estimate.size.x() >= estimate.size.y() ? estimate.yaw : estimate.yaw + kPi / 2;
  const double difference = std::remainder(long_yaw - truth.yaw, kPi);
  EXPECT_LT(std::abs(difference), 10 * kPi / 180);
}

// A box's centre is not where the object's centre projects: seen from above and aside, a
// box shows more of the object's top and of one side, and that offset turns with the view.
// A turned teddy bear seen in two stretches of views 6 degrees apart: the rays through the
// box centres meet centimetres off it, mostly in depth; the cuboid fitted to the boxes'
// edges sits on it, also when one box of the stretch is another object's (a detector's
// box on a neighbour).
TEST(FitCuboidToBoxes, EdgesPlaceTheObjectWhereBoxCentreRaysMissIt) {
  Cuboid bear;
  bear.centre = Eigen::Vector3d(0.1, -0.05, 0.8);
  bear.size = Eigen::Vector3d(0.2, 0.15, 0.28);
  bear.yaw = 0.6;
  const Eigen::Matrix3d R_wg = GravityFrame(Eigen::Vector3d::UnitZ());
  std::vector<BoxView> views;
  std::vector<Ray> rays;
  // The camera turns as it goes: the teddy bear is left of the image centre in the first
  // stretch and right of it in the second.
  for (double azimuth : {0.0, 0.01, 0.02, 0.1, 0.11, 0.12}) {
    const SE3 T_cw = OrbitPose(azimuth, Eigen::Vector3d(0.0, azimuth < 0.05 ? 0.25 : -0.35, 0.8));
    const Box2 box = *ProjectCuboid(bear, R_wg, T_cw, Camera());
    views.push_back({T_cw, box});
    rays.push_back(PixelRay(box.Centre(), T_cw, Camera()));
  }
  const RayIntersection meet = IntersectRays(rays);
  ASSERT_TRUE(meet.valid);
  const double rays_error = (meet.point - bear.centre).norm();
  EXPECT_GT(rays_error, 0.02);
  const Cuboid start = EstimateCuboid(meet.point, views, Camera(), R_wg, bear.yaw);
  const Cuboid fitted = FitCuboidToBoxes(start, views, Camera(), R_wg);
  std::printf("teddy bear: rays meet %.3f m off, the edges' cuboid %.3f m off\n", rays_error,
              (fitted.centre - bear.centre).norm());
  EXPECT_LT((fitted.centre - bear.centre).norm(), 0.2 * rays_error);
  EXPECT_LT((fitted.centre - bear.centre).norm(), 0.01);

  // One box of the second stretch is a neighbour's, 0.3 m aside.
  Cuboid neighbour = bear;
  neighbour.centre += Eigen::Vector3d(0.0, 0.3, 0.0);
  std::vector<BoxView> with_stray = views;
  with_stray[4].box = *ProjectCuboid(neighbour, R_wg, with_stray[4].T_cw, Camera());
  const Cuboid robust = FitCuboidToBoxes(start, with_stray, Camera(), R_wg);
  EXPECT_LT((robust.centre - bear.centre).norm(), 0.02);

  // Nothing to fit: the start comes back.
  EXPECT_EQ(FitCuboidToBoxes(start, {}, Camera(), R_wg).centre, start.centre);
}

// A box continues a track of boxes of unknown depth when, at some depth on the track's rays,
// the track's object projects onto it. From one view the depth is free: the cup seen again
// 11 degrees further round fits, a box twice its size there (an object of the class twice
// as near) does not, nor does one 0.25 m higher; but a cup 0.3 m beside it, which lies
// along the first view's ray as the second view sees it, fits too. Two views fix the depth,
// and then only the cup fits.
TEST(FitOfBoxToTrack, ABoxWhereTheTracksObjectProjectsFitsAndOthersDoNot) {
  Cuboid cup;
  cup.centre = Eigen::Vector3d(0.15, 0.1, 0.8);
  cup.size = Eigen::Vector3d(0.08, 0.08, 0.1);
  Cuboid beside = cup, above = cup;
  beside.centre += Eigen::Vector3d(-0.1, 0.28, 0.0);
  above.centre += Eigen::Vector3d(0.0, 0.0, 0.25);
  const Eigen::Matrix3d R_wg = GravityFrame(Eigen::Vector3d::UnitZ());
  const auto view_of = [&](const Cuboid& cuboid, double azimuth) {
    const SE3 T_cw = OrbitPose(azimuth);
    return BoxView{T_cw, *ProjectCuboid(cuboid, R_wg, T_cw, Camera())};
  };
  const double min_iou = 0.4, share = 0.75;
  const std::vector<BoxView> one = {view_of(cup, 0.0)};
  const BoxView again = view_of(cup, 0.2);
  EXPECT_GT(FitOfBoxToTrack(one, again, Camera(), min_iou, share).iou, 0.6);
  BoxView doubled = again;
  const Eigen::Vector2d centre = again.box.Centre();
  doubled.box = {centre.x() - again.box.Width(), centre.y() - again.box.Height(),
                 centre.x() + again.box.Width(), centre.y() + again.box.Height()};
  EXPECT_EQ(FitOfBoxToTrack(one, doubled, Camera(), min_iou, share).iou, 0.0);
  EXPECT_EQ(FitOfBoxToTrack(one, view_of(above, 0.2), Camera(), min_iou, share).iou, 0.0);
  EXPECT_GT(FitOfBoxToTrack(one, view_of(beside, 0.2), Camera(), min_iou, share).iou, 0.0);

  const std::vector<BoxView> two = {one[0], again};
  EXPECT_GT(FitOfBoxToTrack(two, view_of(cup, 0.4), Camera(), min_iou, share).iou, 0.6);
  EXPECT_EQ(FitOfBoxToTrack(two, view_of(beside, 0.4), Camera(), min_iou, share).iou, 0.0);
}

TEST(BesideAMoreConfidentBoxOfItsClass, ASharedAreaWithAMoreConfidentBoxOfItsClassOnly) {
  const auto detection = [](int class_id, double x0, double x1, double confidence) {
    return ObjectDetection{class_id, Box2{x0, 100, x1, 180}, confidence, false};
  };
  // Bottles (39): 100-120 (0.9) and 115-135 (0.8) overlap; 135-150 (0.5) touches the
  // second along an edge only; a cup (41, 0.95) overlaps the first; two bottles as
  // confident, 200-220 and 210-230, overlap: the earlier wins.
  const std::vector<ObjectDetection> detections = {
      detection(39, 100, 120, 0.9),  detection(39, 115, 135, 0.8), detection(39, 135, 150, 0.5),
      detection(41, 105, 125, 0.95), detection(39, 200, 220, 0.7), detection(39, 210, 230, 0.7)};
  EXPECT_FALSE(BesideAMoreConfidentBoxOfItsClass(detections, 0));
  EXPECT_TRUE(BesideAMoreConfidentBoxOfItsClass(detections, 1));
  EXPECT_FALSE(BesideAMoreConfidentBoxOfItsClass(detections, 2));
  EXPECT_FALSE(BesideAMoreConfidentBoxOfItsClass(detections, 3));
  EXPECT_FALSE(BesideAMoreConfidentBoxOfItsClass(detections, 4));
  EXPECT_TRUE(BesideAMoreConfidentBoxOfItsClass(detections, 5));
}

// A bottle 0.3 m in front of target, seen from the orbit's azimuth `azimuth`.
Cuboid BottleInFrontOf(const Eigen::Vector3d& target, double azimuth) {
  Cuboid bottle;
  bottle.centre = target - 0.3 * Eigen::Vector3d(std::cos(azimuth), std::sin(azimuth), 0);
  bottle.size = Eigen::Vector3d(0.08, 0.08, 0.25);
  return bottle;
}

// A bottle box (class 39) of `real`'s size that stays 9 pixels right of where target
// projects, whatever the view: its rays meet near target, not at the bottle.
Detection BoxFixedNearTarget(const SE3& T_cw, const Eigen::Vector3d& target, const Box2& real,
                             double confidence) {
  const Eigen::Vector2d centre = Camera().ProjectUndistorted(T_cw * target);
  return {39,
          centre.x() + 9 - 0.5 * real.Width(),
          centre.y() - 0.5 * real.Height(),
          real.Width(),
          real.Height(),
          confidence};
}

// Issue 18 (fr3 long_office, ground-truth poses): a detector puts a second box on a
// bottle, or a box that slides from one bottle onto its neighbour as the view changes;
// such a box overlaps a more confident box of its class, and its centre stays where neither
// bottle is. Here it stays 9 pixels right of the image centre while the camera orbits the
// point it looks at, 0.3 m in front of the bottle: its rays meet near that point with 8
// degrees of spread, and it became a bottle in mid-air that no merge could take (detected
// beside the real one, IoU below Objects.duplicate_box_iou). A candidate now triangulates
// from boxes beside no more confident box of their class: the real bottle is mapped, the
// box in mid-air never is.
TEST(ObjectMap, ACandidateDoesNotTriangulateFromBoxesBesideAMoreConfidentOneOfItsClass) {
  ObjectsOptions options;
  ObjectMap map(options, Camera());
  const Eigen::Vector3d target(0, 0, 0.8);
  const Cuboid bottle = BottleInFrontOf(target, 0.15);
  const Eigen::Matrix3d R_wg = GravityFrame(Eigen::Vector3d::UnitZ());
  for (int frame = 0; frame < 40; ++frame) {
    const SE3 T_cw = OrbitPose(0.02 * frame, target);
    const Box2 real = *ProjectCuboid(bottle, R_wg, T_cw, Camera());
    std::vector<Detection> detections = {{39, real.x0, real.y0, real.Width(), real.Height(), 0.9}};
    // The second box: the bottle's size, at a fixed place in the image.
    if (frame < 8) detections.push_back(BoxFixedNearTarget(T_cw, target, real, 0.8));
    const std::vector<ObjectDetection> kept = FilterDetections(detections, options, Camera());
    ASSERT_EQ(kept.size(), detections.size()) << frame;  // both kept (below Objects.nms_iou)
    if (kept.size() == 2) {
      ASSERT_TRUE(BesideAMoreConfidentBoxOfItsClass(kept, 1)) << frame;
      ASSERT_FALSE(BesideAMoreConfidentBoxOfItsClass(kept, 0)) << frame;
    }
    map.AddFrame(frame, frame / 30.0, T_cw, kept);
  }
  ASSERT_EQ(map.objects().size(), 1u);
  EXPECT_LT((map.objects().begin()->second.cuboid.centre - bottle.centre).norm(),
            0.15 * bottle.size.maxCoeff());
}

// The map's hygiene (Objects.min_sightings after Objects.probation_keyframes) counts the
// boxes beside no more confident box of their class: such a box may be the neighbour's
// (issue 18, fr3: a bottle in mid-air promoted from 8 boxes and kept by 13 beside the real
// bottle's). Here a box stays at one place in the image, alone for 12 frames (it becomes
// an object where its rays meet, 0.3 m in front of a bottle), then for 8 frames beside the
// bottle's box: 20 sightings, 12 of its own. The bottle is seen for 48 frames.
TEST(ObjectMap, HygieneCountsOnlyTheSightingsBesideNoMoreConfidentBoxOfTheClass) {
  ObjectsOptions options;
  options.probation_keyframes = 5;
  ObjectMap map(options, Camera());
  const Eigen::Vector3d target(0, 0, 0.8);
  const Cuboid bottle = BottleInFrontOf(target, 0.033);
  const Eigen::Matrix3d R_wg = GravityFrame(Eigen::Vector3d::UnitZ());
  int crowded_frames = 0;
  for (int frame = 0; frame < 60; ++frame) {
    const SE3 T_cw = OrbitPose(0.02 * frame, target);
    const Box2 real = *ProjectCuboid(bottle, R_wg, T_cw, Camera());
    std::vector<Detection> detections;
    if (frame >= 12) detections.push_back({39, real.x0, real.y0, real.Width(), real.Height(), 0.9});
    // The box at a fixed place in the image, the bottle's size.
    if (frame < 20) detections.push_back(BoxFixedNearTarget(T_cw, target, real, 0.8));
    const std::vector<ObjectDetection> kept = FilterDetections(detections, options, Camera());
    ASSERT_EQ(kept.size(), detections.size()) << frame;
    crowded_frames += kept.size() == 2 && BesideAMoreConfidentBoxOfItsClass(kept, 1) ? 1 : 0;
    map.AddFrame(frame, frame / 30.0, T_cw, kept);
    if (frame % 5 == 4) map.MakeKeyframeObservation(frame / 5, frame / 30.0, T_cw, nullptr);
  }
  EXPECT_EQ(crowded_frames, 8);
  ASSERT_EQ(map.objects().size(), 1u);
  EXPECT_LT((map.objects().begin()->second.cuboid.centre - bottle.centre).norm(),
            0.15 * bottle.size.maxCoeff());
}

TEST(FilterDetections, ClassConfidenceBorderAndDuplicates) {
  ObjectsOptions options;
  options.classes = {41, 63};
  options.min_confidence = 0.5;
  const std::vector<Detection> detections = {
      {41, 100, 100, 50, 60, 0.9},   // kept
      {41, 104, 102, 50, 60, 0.7},   // duplicate of the first: suppressed
      {63, 104, 102, 50, 60, 0.7},   // another class at the same place: kept
      {41, 300, 100, 40, 40, 0.3},   // not confident enough
      {0, 200, 200, 40, 90, 0.95},   // a class not mapped
      {63, 600, 400, 60, 100, 0.8},  // runs off the image: clipped and truncated
  };
  const std::vector<ObjectDetection> kept = FilterDetections(detections, options, Camera());
  ASSERT_EQ(kept.size(), 3u);
  EXPECT_EQ(kept[0].class_id, 41);
  EXPECT_FALSE(kept[0].truncated);
  EXPECT_EQ(kept[1].class_id, 63);
  EXPECT_TRUE(kept[2].truncated);
  EXPECT_DOUBLE_EQ(kept[2].box.x1, 640.0);
  EXPECT_DOUBLE_EQ(kept[2].box.y1, 480.0);
  options.classes.clear();  // default: everything but person
  EXPECT_EQ(FilterDetections(detections, options, Camera()).size(), 3u);
  options.min_confidence = 0.0;
  EXPECT_EQ(FilterDetections(detections, options, Camera()).size(), 4u);
}

TEST(FitOfBox, ACornerOfTheObjectIsAPartialView) {
  // The object's top right quarter, its left and bottom hidden by something nearer: the
  // box spans neither axis, but is flush with the projection's right and top edges (here
  // 5 pixels out, within the projection's error).
  const Box2 projected{100, 100, 200, 300};
  EXPECT_EQ(FitOfBox({155, 96, 204, 190}, projected, 0.4), BoxFit::kPartial);
  // As small, flush with the right edge only, or with no edge (a farther object of the
  // class on the same ray): not this object.
  EXPECT_EQ(FitOfBox({155, 150, 204, 244}, projected, 0.4), BoxFit::kNone);
  EXPECT_EQ(FitOfBox({125, 150, 175, 250}, projected, 0.4), BoxFit::kNone);
}

TEST(FitOfBox, ASideViewSpansAProjectionTooLargeByItsErrorAsAPartialView) {
  // A flat object mapped from a short stretch of views: its footprint taken square, its
  // projection a quarter too large on both axes. The real object's right part, its left
  // hidden by a nearer one: the box spans the real object's height (15 of 18 pixels) but
  // only 65 % of the projection's, and is flush with neither of its vertical edges (round_2's
  // cell phone behind the potted plant, issue 18).
  const Box2 projected{156, 214, 216, 237};
  EXPECT_EQ(FitOfBox({182, 214, 206, 229}, projected, 0.4), BoxFit::kPartial);
  // The object's size is known only to the slack: a box half the projection on both axes
  // (a farther object of the class on the same ray) is still not this object.
  EXPECT_EQ(FitOfBox({171, 220, 201, 231}, projected, 0.4), BoxFit::kNone);
}

TEST(ObjectsOptions, ADuplicateBoxIouOutsideZeroToOneIsRefusedNamingTheKey) {
  ObjectsOptions options;
  options.duplicate_box_iou = 0.0;
  try {
    options.Check();
    FAIL() << "accepted 0";
  } catch (const std::exception& error) {
    EXPECT_NE(std::string(error.what()).find("Objects.duplicate_box_iou"), std::string::npos);
  }
  options.duplicate_box_iou = 1.0;
  EXPECT_NO_THROW(options.Check());
}

TEST(FitOfBox, WholePartialOrNone) {
  const Box2 projected{100, 100, 200, 300};
  EXPECT_EQ(FitOfBox({105, 95, 205, 290}, projected, 0.4), BoxFit::kWhole);
  // The right 30 % of the object, its left side hidden: inside, spanning its height.
  EXPECT_EQ(FitOfBox({170, 102, 200, 298}, projected, 0.4), BoxFit::kPartial);
  // Its top third, the rest behind something: spanning its width.
  EXPECT_EQ(FitOfBox({101, 100, 199, 160}, projected, 0.4), BoxFit::kPartial);
  // The whole shape shrunk to half about the centre (an object of the class twice as far
  // on the same ray): no partial view, and the IoU of 0.25 is too small.
  EXPECT_EQ(FitOfBox({125, 150, 175, 250}, projected, 0.4), BoxFit::kNone);
  // Beside it, or sticking out of it.
  EXPECT_EQ(FitOfBox({210, 100, 300, 300}, projected, 0.4), BoxFit::kNone);
  EXPECT_EQ(FitOfBox({170, 102, 260, 298}, projected, 0.4), BoxFit::kNone);
}

TEST(FitOfBox, ASliverPokingOutOfTheProjectionByItsErrorIsAPartialView) {
  // The first 14 pixels of an object coming out from behind another on its left, while
  // the projected cuboid lies 7 pixels (7 % of its width) left of the object: half the
  // sliver is outside the projection itself, all of it within the projection's error.
  const Box2 projected{100, 100, 200, 300};
  EXPECT_EQ(FitOfBox({193, 110, 207, 290}, projected, 0.4), BoxFit::kPartial);
  // The same sliver 15 pixels out (beyond the slack): not this object.
  EXPECT_EQ(FitOfBox({201, 110, 215, 290}, projected, 0.4), BoxFit::kNone);
}

// Two cuboids on a table, seen by a camera circling them; detections are the projected
// boxes (what an ideal detector returns).
class TwoObjectScene : public ::testing::Test {
 protected:
  TwoObjectScene() {
    cup_.centre = Eigen::Vector3d(0.15, 0.1, 0.8);
    cup_.size = Eigen::Vector3d(0.08, 0.08, 0.1);
    laptop_.centre = Eigen::Vector3d(-0.2, -0.1, 0.77);
    laptop_.size = Eigen::Vector3d(0.33, 0.23, 0.03);
    laptop_.yaw = 0.3;
  }
  std::vector<Detection> DetectionsAt(const SE3& T_cw, bool cup_visible = true) const {
    std::vector<Detection> detections;
    const Eigen::Matrix3d R_wg = GravityFrame(Eigen::Vector3d::UnitZ());
    for (const auto& [cuboid, class_id] : {std::pair{cup_, 41}, std::pair{laptop_, 63}}) {
      if (class_id == 41 && !cup_visible) continue;
      const Box2 box = *ProjectCuboid(cuboid, R_wg, T_cw, Camera());
      detections.push_back({class_id, box.x0, box.y0, box.Width(), box.Height(), 0.9});
    }
    return detections;
  }
  // The cup objects after 60 frames of the orbit in which the detector's box on the cup
  // is, from frame 20 on, one shifted by a quarter of its width and 15 % of its height (the
  // box settled elsewhere on the object), and in the frames `beside` a box shifted by
  // (extra_x, extra_y) of the cup's size is detected as well. The overlap rule is off: the
  // two cups share most of their space here; in the cases of these rules (straight_2's
  // cup, two objects 7 cm apart) they do not.
  std::ptrdiff_t CupsWithASecondBox(ObjectsOptions options, const std::set<int>& beside,
                                    double extra_x, double extra_y) const {
    options.merge_overlap = 1.0;
    ObjectMap map(options, Camera());
    for (int frame = 0; frame < 60; ++frame) {
      const SE3 T_cw = OrbitPose(0.02 * frame);
      std::vector<Detection> detections = DetectionsAt(T_cw);
      const Detection cup = detections[0];
      const Detection second{
          41, cup.x + 0.25 * cup.width, cup.y + 0.15 * cup.height, cup.width, cup.height, 0.7};
      const Detection extra{
          41, cup.x + extra_x * cup.width, cup.y + extra_y * cup.height, cup.width, cup.height,
          0.7};
      if (frame >= 20) detections[0] = second;
      if (beside.count(frame) > 0) detections.push_back(extra);
      map.AddFrame(frame, frame / 30.0, T_cw, FilterDetections(detections, options, Camera()));
    }
    map.MakeKeyframeObservation(0, 2.0, OrbitPose(1.18), nullptr);
    return std::count_if(map.objects().begin(), map.objects().end(),
                         [](const auto& entry) { return entry.second.class_id == 41; });
  }
  // The points in front of the camera, as tracking would report them.
  static std::vector<PointObservation> Tracked(
      const SE3& T_cw, const std::vector<std::pair<std::uint64_t, Eigen::Vector3d>>& points) {
    std::vector<PointObservation> tracked;
    for (const auto& [id, position] : points) {
      const Eigen::Vector3d p_c = T_cw * position;
      if (p_c.z() > 0.1) tracked.push_back({id, Camera().ProjectUndistorted(p_c), position});
    }
    return tracked;
  }
  // A camera going back and forth over the orbit's first 40 steps for `frames` frames, a
  // keyframe every 10, with the tracked map points when given; returns the hygiene's merges.
  std::vector<ObjectChange> BackAndForth(
      ObjectMap& map, const ObjectsOptions& options, int frames,
      const std::vector<std::pair<std::uint64_t, Eigen::Vector3d>>* points = nullptr) const {
    std::vector<ObjectChange> merges;
    for (int frame = 0; frame < frames; ++frame) {
      const int step = frame % 80 < 40 ? frame % 80 : 80 - frame % 80;  // forward and back
      const SE3 T_cw = OrbitPose(0.02 * step);
      const std::vector<PointObservation> tracked =
          points != nullptr ? Tracked(T_cw, *points) : std::vector<PointObservation>{};
      map.AddFrame(frame, frame / 30.0, T_cw,
                   FilterDetections(DetectionsAt(T_cw), options, Camera()),
                   points != nullptr ? &tracked : nullptr);
      if (frame % 10 == 9) map.MakeKeyframeObservation(frame / 10, frame / 30.0, T_cw, &merges);
    }
    return merges;
  }
  // Frames first..last-1 of the orbit into the map (the cup hidden if asked), with the
  // tracked map points when given.
  void Watch(ObjectMap& map, const ObjectsOptions& options, int first, int last,
             bool cup_visible = true,
             const std::vector<std::pair<std::uint64_t, Eigen::Vector3d>>* points = nullptr) const {
    for (int frame = first; frame < last; ++frame) {
      const SE3 T_cw = OrbitPose(0.02 * frame);
      std::vector<PointObservation> tracked;
      if (points != nullptr) {
        for (const auto& [id, position] : *points) {
          const Eigen::Vector3d p_c = T_cw * position;
          if (p_c.z() > 0.1) tracked.push_back({id, Camera().ProjectUndistorted(p_c), position});
        }
      }
      map.AddFrame(frame, frame / 30.0, T_cw,
                   FilterDetections(DetectionsAt(T_cw, cup_visible), options, Camera()),
                   points != nullptr ? &tracked : nullptr);
    }
  }
  // Map points on the cuboids' top faces (ids 100.. cup, 200.. laptop) and on a wall far
  // behind them (ids 1000..), which the boxes catch from some azimuths only.
  std::vector<std::pair<std::uint64_t, Eigen::Vector3d>> ScenePoints() const {
    std::vector<std::pair<std::uint64_t, Eigen::Vector3d>> points;
    for (int i = 0; i < 16; ++i) {
      const double u = (i % 4) / 3.0 - 0.5, v = (i / 4) / 3.0 - 0.5;
      points.push_back(
          {100 + i, cup_.centre + Eigen::Vector3d(0.8 * cup_.size.x() * u, 0.8 * cup_.size.y() * v,
                                                  0.5 * cup_.size.z())});
      points.push_back({200 + i, laptop_.centre + Eigen::Vector3d(0.5 * laptop_.size.x() * u,
                                                                  0.5 * laptop_.size.y() * v,
                                                                  0.5 * laptop_.size.z())});
    }
    for (int i = 0; i < 800; ++i) {  // where the rays through the objects meet the wall
      const double angle = 2 * kPi * (i / 8) / 100;
      points.push_back({1000 + i, Eigen::Vector3d(-4 * std::cos(angle), -4 * std::sin(angle),
                                                  -0.75 + 0.06 * (i % 8))});
    }
    return points;
  }
  Cuboid cup_, laptop_;
};

// A hand-held camera turning on the spot (fr1_rpy): 60 frames from one place (5 mm of
// drift), the view swept between the laptop and the cup. Their rays barely diverge, so
// no depth comes from them; the map points in the boxes (SLAM's, triangulated over a
// longer baseline), a far wall's included, place the objects along their rays.
TEST_F(TwoObjectScene, ACameraTurningOnTheSpotPlacesObjectsByTheirMapPoints) {
  const Eigen::Vector3d eye(1.2, 0.3, 1.3);
  const auto watch = [&](ObjectMap& map, const ObjectsOptions& options) {
    const auto points = ScenePoints();
    for (int frame = 0; frame < 60; ++frame) {
      const double share = 0.5 + 0.5 * std::sin(frame * 0.15);
      const Eigen::Vector3d target = laptop_.centre + share * (cup_.centre - laptop_.centre);
      const SE3 T_cw = LookFrom(eye + Eigen::Vector3d(0, 0.005 * frame / 60.0, 0), target);
      const std::vector<PointObservation> tracked = Tracked(T_cw, points);
      map.AddFrame(frame, frame / 30.0, T_cw,
                   FilterDetections(DetectionsAt(T_cw), options, Camera()), &tracked);
    }
  };
  ObjectsOptions without;
  without.candidate_min_points = 100000;  // the rule off: rays alone
  ObjectMap rays_only(without, Camera());
  watch(rays_only, without);
  EXPECT_EQ(rays_only.objects().size(), 0u);

  ObjectsOptions options;
  ObjectMap map(options, Camera());
  watch(map, options);
  ASSERT_EQ(map.objects().size(), 2u);
  for (const auto& [id, object] : map.objects()) {
    const Cuboid& truth = object.class_id == 41 ? cup_ : laptop_;
    EXPECT_LT((object.cuboid.centre - truth.centre).norm(), 0.1 * (truth.centre - eye).norm())
        << "class " << object.class_id;
  }
}

TEST_F(TwoObjectScene, CandidatesBecomeObjectsAtTheirPlaces) {
  ObjectsOptions options;
  ObjectMap map(options, Camera());
  Watch(map, options, 0, 40);
  ASSERT_EQ(map.objects().size(), 2u);
  EXPECT_EQ(map.CandidateCount(), 0u);
  for (const auto& [id, object] : map.objects()) {
    const Cuboid& truth = object.class_id == 41 ? cup_ : laptop_;
    // Box centres are not projections of the object's centre (perspective): the rays meet
    // a few percent of the object's size away from it, well inside the SPEC 4 radius.
    EXPECT_LT((object.cuboid.centre - truth.centre).norm(), 0.15 * truth.size.maxCoeff())
        << object.class_id;
    EXPECT_GE(object.sightings.size(), 38u);  // every frame after the first is associated
  }
  std::vector<ObjectChange> merges;
  const KeyframeObservation observation =
      map.MakeKeyframeObservation(0, 1.0, OrbitPose(0.78), &merges);
  EXPECT_TRUE(merges.empty());
  EXPECT_EQ(observation.observed, (std::vector<ObjectId>{1, 2}));
  ASSERT_EQ(observation.updates.size(), 2u);
  EXPECT_TRUE(observation.updates.at(1).centroid.has_value());
}

TEST_F(TwoObjectScene, UnseenObjectIsNotObservedAndRemovalEntersTheChangeLog) {
  ObjectsOptions options;
  ObjectMap map(options, Camera());
  Watch(map, options, 0, 40);
  map.MakeKeyframeObservation(0, 1.0, OrbitPose(0.78), nullptr);
  ObjectId cup = 0;
  for (const auto& [id, object] : map.objects()) {
    if (object.class_id == 41) cup = id;
  }
  Watch(map, options, 40, 50, /*cup_visible=*/false);
  const KeyframeObservation observation =
      map.MakeKeyframeObservation(1, 2.0, OrbitPose(0.98), nullptr);
  EXPECT_EQ(observation.observed.size(), 1u);
  EXPECT_NE(observation.observed[0], cup);
  RemovalEvent event;
  event.object_id = cup;
  event.keyframe_id = 1;
  event.doubt = 60;
  map.Remove(event);
  EXPECT_EQ(map.objects().count(cup), 0u);
  ASSERT_EQ(map.changes().size(), 1u);
  EXPECT_EQ(map.changes()[0].type, "removed");
  EXPECT_LT((map.changes()[0].cuboid.centre - cup_.centre).norm(), 0.15 * cup_.size.maxCoeff());
}

TEST_F(TwoObjectScene, ANewSessionReportsNoDetectionOfTheEarlierOneAsObserved) {
  // Session 0 ends a few frames after its last OCG keyframe; its detections of those
  // frames must not reach the OCG as observations of session 1's first keyframe.
  ObjectsOptions options;
  ObjectMap map(options, Camera());
  Watch(map, options, 0, 40);
  map.MakeKeyframeObservation(0, 1.0, OrbitPose(0.78), nullptr);
  Watch(map, options, 40, 45);
  map.StartSession(1, 45);
  Watch(map, options, 45, 50, /*cup_visible=*/false);
  const KeyframeObservation observation =
      map.MakeKeyframeObservation(1, 2.0, OrbitPose(0.98), nullptr);
  ASSERT_EQ(observation.observed.size(), 1u);
  EXPECT_EQ(map.objects().at(observation.observed[0]).class_id, 63);  // the laptop only
  EXPECT_EQ(map.objects().at(observation.observed[0]).sightings.back().session, 1);
  for (const auto& [id, object] : map.objects()) {
    if (object.class_id == 41) {
      EXPECT_EQ(object.sightings.back().session, 0);
    }
  }
}

// Between the sessions the cup was carried 0.25 m away along the ray of the first view of
// session 1: its box there overlaps the old cup's projected cuboid (one view has no depth).
// Within a session that detection is the cup found again; in a later session the old
// cup's own map points, tracked at its place if it stayed, are not in the box: no match.
TEST_F(TwoObjectScene, InALaterSessionAnObjectIsFoundAgainOnlyWithItsOwnPoints) {
  ObjectsOptions options;
  const auto points = ScenePoints();
  const SE3 T_cw = OrbitPose(0.02 * 60);
  Cuboid carried = cup_;
  carried.centre += 0.25 * (cup_.centre - T_cw.Inverse().translation()).normalized();
  const Eigen::Matrix3d R_wg = GravityFrame(Eigen::Vector3d::UnitZ());
  // One frame of session 1: the cup where it stands (stayed) or where it was carried.
  const auto frame = [&](ObjectMap& map, bool stayed) {
    const Cuboid& cup = stayed ? cup_ : carried;
    const Box2 box = *ProjectCuboid(cup, R_wg, T_cw, Camera());
    const std::vector<Detection> detections = {
        {41, box.x0, box.y0, box.Width(), box.Height(), 0.9}};
    std::vector<PointObservation> tracked;
    for (const auto& [id, position] : points) {
      Eigen::Vector3d where = position;
      if (id >= 100 && id < 200) {  // the cup's top
        if (!stayed) continue;      // gone from there: tracking finds none of these
      }
      const Eigen::Vector3d p_c = T_cw * where;
      if (p_c.z() > 0.1) tracked.push_back({id, Camera().ProjectUndistorted(p_c), where});
    }
    if (!stayed) {  // the carried cup's top: new points
      for (int i = 0; i < 16; ++i) {
        const Eigen::Vector3d p =
            carried.centre + Eigen::Vector3d(0.03 * (i % 4 - 1.5), 0.03 * (i / 4 - 1.5), 0.05);
        tracked.push_back(
            {static_cast<std::uint64_t>(300 + i), Camera().ProjectUndistorted(T_cw * p), p});
      }
    }
    return map.AddFrame(60, 3.0, T_cw, FilterDetections(detections, options, Camera()), &tracked);
  };
  const auto matched_to_cup = [](const ObjectMap& map, const FrameAssociation& association) {
    for (const auto& [index, id] : association.matched) {
      if (index == 0 && map.objects().at(id).class_id == 41) return true;
    }
    return false;
  };
  const auto first_session = [&]() {
    ObjectMap map(options, Camera());
    Watch(map, options, 0, 40, true, &points);
    map.MakeKeyframeObservation(0, 1.0, OrbitPose(0.78), nullptr);
    return map;
  };
  {
    ObjectMap map = first_session();  // the same session, 20 frames on
    EXPECT_TRUE(matched_to_cup(map, frame(map, false)));
  }
  {
    ObjectMap map = first_session();
    map.StartSession(1, 60);
    EXPECT_FALSE(matched_to_cup(map, frame(map, false)));
  }
  {
    ObjectMap map = first_session();
    map.StartSession(1, 60);
    EXPECT_TRUE(matched_to_cup(map, frame(map, true)));
  }
}

TEST_F(TwoObjectScene, TheSameObjectMappedTwiceIsMerged) {
  ObjectsOptions options;
  options.min_reacquire_iou = 1.0;  // after a gap, nothing is found again: new objects
  options.join_candidates = false;  // and the candidates become objects of their own
  ObjectMap map(options, Camera());
  Watch(map, options, 0, 20);
  Watch(map, options, 30, 60);          // the detector was blind for frames 20-29
  ASSERT_EQ(map.objects().size(), 4u);  // each object twice, never seen together
  std::vector<ObjectChange> merges;
  const KeyframeObservation observation =
      map.MakeKeyframeObservation(0, 2.0, OrbitPose(1.18), &merges);
  ASSERT_EQ(map.objects().size(), 2u);
  ASSERT_EQ(merges.size(), 2u);
  for (const ObjectChange& change : merges) {
    EXPECT_EQ(change.type, "merged");
    EXPECT_EQ(map.objects().count(change.object_id), 0u);
    EXPECT_EQ(map.objects().count(change.merged_into), 1u);
  }
  // The OCG is told to forget the absorbed objects.
  std::vector<ObjectId> forgotten = observation.forgotten;
  std::sort(forgotten.begin(), forgotten.end());
  std::vector<ObjectId> absorbed{merges[0].object_id, merges[1].object_id};
  std::sort(absorbed.begin(), absorbed.end());
  EXPECT_EQ(forgotten, absorbed);
  for (const auto& [id, object] : map.objects()) EXPECT_EQ(object.sightings.size(), 50u);
}

// A persistent class flip: for frames 30-41 the detector calls the cup a bowl, with boxes
// that drift sideways by a few pixels (as real boxes do). The bowl's few rays, 13 degrees
// apart, meet far from the cup in depth, so it is an object of its own, beyond the merge
// distance; yet it lived within the cup's life, never beside it, and every box of it
// covers the cup's projection: it is the cup, merged. A cup moved away (found elsewhere
// after its last sighting) is not.
TEST_F(TwoObjectScene, AnObjectSeenUnderAnotherClassForAWhileIsMergedIntoIt) {
  const auto run = [this](bool merge_along_rays, const Eigen::Vector3d& moved,
                          bool join_candidates = false) {
    ObjectsOptions options;
    options.merge_along_rays = merge_along_rays;
    options.join_candidates = join_candidates;
    ObjectMap map(options, Camera());
    for (int frame = 0; frame < 70; ++frame) {
      const SE3 T_cw = OrbitPose(0.02 * frame);
      if (frame == 40) cup_.centre += moved;
      std::vector<Detection> detections = DetectionsAt(T_cw);
      if (frame >= 30 && frame < 42 && moved.isZero()) {
        detections[0].class_id = 45;
        detections[0].x += 0.5 * (frame - 30);
      }
      map.AddFrame(frame, frame / 30.0, T_cw, FilterDetections(detections, options, Camera()));
    }
    cup_.centre -= moved;
    std::vector<ObjectChange> merges;
    map.MakeKeyframeObservation(0, 70 / 30.0, OrbitPose(1.4), &merges);
    return std::make_pair(map.objects(), merges);
  };
  const auto [kept, none] = run(false, Eigen::Vector3d::Zero());
  ASSERT_EQ(kept.size(), 3u);
  EXPECT_TRUE(none.empty());
  const MapObject* cup = nullptr;
  const MapObject* bowl = nullptr;
  for (const auto& [id, object] : kept) {
    if (object.class_id == 41) cup = &object;
    if (object.class_id == 45) bowl = &object;
  }
  ASSERT_TRUE(cup != nullptr && bowl != nullptr);
  EXPECT_GT((bowl->cuboid.centre - cup->cuboid.centre).norm(),
            ObjectsOptions().merge_distance * cup->cuboid.size.maxCoeff())
      << "the case needs a stand-in beyond the merge distance";

  const auto [merged, merges] = run(true, Eigen::Vector3d::Zero());
  ASSERT_EQ(merged.size(), 2u);
  ASSERT_EQ(merges.size(), 1u);
  EXPECT_EQ(merges[0].object_id, bowl->id);
  EXPECT_EQ(merges[0].merged_into, cup->id);
  EXPECT_EQ(merged.at(cup->id).class_id, 41);  // the majority of its sightings
  EXPECT_EQ(merged.at(cup->id).sightings.size(), 70u);

  const auto [after_move, move_merges] = run(true, Eigen::Vector3d(0.2, -0.15, 0));
  EXPECT_EQ(after_move.size(), 3u);  // the cup at its old place and at its new one
  EXPECT_TRUE(move_merges.empty());

  // Objects.join_candidates: the bowl's track fits the cup's projection before it is ever
  // promoted, so its first 8 boxes join the cup at once (no object, no merge), whose class
  // stays the majority of its sightings; the last 4 bowl boxes start a candidate too short
  // to be promoted, which, waiting for a box (Objects.candidate_gap_seconds), fits the
  // cup's projection too and joins it at the keyframe (before that rule it was dropped: 66
  // sightings). Moved, the cup at its new place is an object of its own.
  const auto [joined, no_merges] = run(false, Eigen::Vector3d::Zero(), true);
  ASSERT_EQ(joined.size(), 2u);
  EXPECT_TRUE(no_merges.empty());
  for (const auto& [id, object] : joined) {
    if (object.class_id == 63) continue;
    EXPECT_EQ(object.class_id, 41);
    EXPECT_EQ(object.sightings.size(), 70u);
  }
  EXPECT_EQ(run(false, Eigen::Vector3d(0.2, -0.15, 0), true).first.size(), 3u);
}

// A cup's place emptied (a move) and a false box of another class there later joins the
// cup left in the map: the cup's last sighting moves on, but not its last sighting as a
// cup, which orders a move in changes.json.
TEST_F(TwoObjectScene, SeenAsClassLeavesOutSightingsOfAnotherClass) {
  ObjectsOptions options;
  ObjectMap map(options, Camera());
  for (int frame = 0; frame < 60; ++frame) {
    const SE3 T_cw = OrbitPose(0.02 * frame);
    std::vector<Detection> detections = DetectionsAt(T_cw);
    if (frame >= 45) detections[0].class_id = 45;  // a bowl where the cup stands
    map.AddFrame(frame, 1000 + frame / 30.0, T_cw, FilterDetections(detections, options, Camera()));
  }
  std::vector<ObjectChange> merges;
  map.MakeKeyframeObservation(0, 1002.0, OrbitPose(1.2), &merges);
  const MapObject* cup = nullptr;
  for (const auto& [id, object] : map.objects()) {
    if (object.class_id == 41) cup = &object;
  }
  ASSERT_NE(cup, nullptr);
  ASSERT_GT(cup->last_timestamp, 1000 + 50 / 30.0) << "the bowl's boxes must join the cup";
  const SeenAsClass seen = map.SeenAsClassThisSession();
  // With support: the second last box as a cup (frame 43), the second box (frame 1).
  EXPECT_NEAR(seen.last.at(cup->id), 1000 + 43 / 30.0, 1e-9);
  EXPECT_NEAR(seen.first.at(cup->id), cup->first_timestamp + 1 / 30.0, 1e-9);
}

// Issue 19, pair 2: a potted plant carried away between the sessions was never removed.
// In session 1 a teddy bear was put down beside its old place, within the merge distance;
// hygiene merged the new teddy bear (never seen with the plant: they lived in different
// sessions) into the plant as a class confusion, and the plant counted as seen in session
// 1, its doubt reset. Here: the cup is carried away, a teddy bear stands 2 cm from its old
// place. In one session the two are one object the detector named twice, merged; across
// sessions they are two, and the cup is not observed in session 1. Both ways of making
// one object of two are checked: the keyframe hygiene's merge (Objects.join_candidates
// off) and the join of a candidate whose boxes fit the object's projection.
TEST_F(TwoObjectScene, AnObjectOfAnotherClassAtTheOldPlaceOfOneSeenInAnEarlierSessionIsNotMerged) {
  Cuboid bear = cup_;
  bear.centre += Eigen::Vector3d(0.02, 0.0, 0.0);
  bear.size = Eigen::Vector3d(0.09, 0.09, 0.1);
  const auto run = [&](bool new_session, bool join_candidates) {
    ObjectsOptions options;
    options.join_candidates = join_candidates;
    ObjectMap map(options, Camera());
    Watch(map, options, 0, 40);
    map.MakeKeyframeObservation(0, 40 / 30.0, OrbitPose(0.78), nullptr);
    if (new_session) map.StartSession(1, 60);
    for (int frame = 60; frame < 100; ++frame) {
      const SE3 T_cw = OrbitPose(0.02 * frame);
      std::vector<Detection> detections = DetectionsAt(T_cw, /*cup_visible=*/false);
      const Box2 box = *ProjectCuboid(bear, GravityFrame(Eigen::Vector3d::UnitZ()), T_cw, Camera());
      detections.push_back({77, box.x0, box.y0, box.Width(), box.Height(), 0.9});
      map.AddFrame(frame, frame / 30.0, T_cw, FilterDetections(detections, options, Camera()));
    }
    std::vector<ObjectChange> merges;
    const KeyframeObservation observation =
        map.MakeKeyframeObservation(1, 100 / 30.0, OrbitPose(1.98), &merges);
    bool cup_observed = false;
    for (ObjectId id : observation.observed) {
      if (map.objects().count(id) > 0 && map.objects().at(id).class_id == 41) cup_observed = true;
    }
    return std::make_tuple(map.objects().size(), merges, cup_observed);
  };
  for (const bool join : {false, true}) {
    SCOPED_TRACE(join ? "join of candidates" : "hygiene merge");
    const auto [objects_one, merges_one, cup_seen_one] = run(false, join);
    if (!join) {
      ASSERT_EQ(merges_one.size(), 1u) << "the case needs a merge within one session";
      EXPECT_EQ(merges_one[0].type, "merged");
    }
    EXPECT_EQ(objects_one, 2u);  // the cup (named teddy bear for a while) and the laptop
    EXPECT_TRUE(cup_seen_one);
    const auto [objects_two, merges_two, cup_seen_two] = run(true, join);
    EXPECT_TRUE(merges_two.empty());
    EXPECT_EQ(objects_two, 3u);  // the cup at its old place, the teddy bear, the laptop
    EXPECT_FALSE(cup_seen_two);
  }
}

// A detector's second box on the cup (shifted by a quarter of its width and 15 % of its
// height: IoU 0.47, so non-maximum suppression keeps both) in frames 18 and 19, and from
// frame 20 on only that box (the detector's box settled elsewhere on the object): the
// second box starts a candidate that keeps the track by its predicted box and becomes a
// second cup object a few centimetres from the first. The two frames they share, boxes on
// one object, do not make them two objects: they are merged (before: "seen together").
TEST_F(TwoObjectScene, ObjectsDetectedTogetherOnlyThroughADuplicateBoxAreMerged) {
  ObjectsOptions options;
  options.duplicate_box_iou = 1.0;
  EXPECT_EQ(CupsWithASecondBox(options, {18, 19}, 0.25, 0.15), 2);  // the frames keep them apart
  options.duplicate_box_iou = 0.3;
  EXPECT_EQ(CupsWithASecondBox(options, {18, 19}, 0.25, 0.15), 1);
}

// A mouse-sized object (6 x 10 x 4 cm) seen in one stretch of views spanning 3 degrees of
// azimuth (too little parallax to fix the depth), its boxes jittered by up to 1.5 px, made
// into a map object of its own (frames from first_frame on: two stretches are never seen
// together) whose centre its narrow rays placed depth_error metres along their mean line
// of sight from the truth.
MapObject StretchOfViews(ObjectId id, const Eigen::Vector3d& truth, double first_azimuth,
                         double depth_error, std::int64_t first_frame) {
  const Eigen::Matrix3d R_wg = GravityFrame(Eigen::Vector3d::UnitZ());
  Cuboid cuboid;
  cuboid.centre = truth;
  cuboid.size = Eigen::Vector3d(0.06, 0.1, 0.04);
  MapObject object;
  object.id = id;
  object.class_id = 64;
  Eigen::Vector3d line_of_sight = Eigen::Vector3d::Zero();
  for (int i = 0; i < 12; ++i) {
    const SE3 T_cw = OrbitPose(first_azimuth + i * 0.25 * kPi / 180.0, truth);
    const double jitter_x = 1.5 * std::sin(2.3 * i + static_cast<double>(id));
    const double jitter_y = 1.5 * std::cos(1.7 * i + static_cast<double>(id));
    Box2 box = *ProjectCuboid(cuboid, R_wg, T_cw, Camera());
    box = {box.x0 + jitter_x, box.y0 + jitter_y, box.x1 + jitter_x, box.y1 + jitter_y};
    ObjectSighting sighting;
    sighting.frame = first_frame + i;
    sighting.T_cw = T_cw;
    sighting.box = box;
    sighting.class_id = 64;
    object.sightings.Add(sighting, 0);
    line_of_sight += (truth - T_cw.Inverse().translation()).normalized();
  }
  object.has_cuboid = true;
  object.cuboid = cuboid;
  object.cuboid.centre = truth + depth_error * line_of_sight.normalized();
  return object;
}

// One small object, two stretches of views from azimuths 40 degrees apart: each stretch
// alone fixes its depth poorly, so the two objects it made stand 14 cm apart (beyond
// Objects.merge_distance x 10 cm) and neither one's boxes fit the other's cuboid. Pooled,
// their rays meet at the object as closely as each stretch's do: one object, merged.
// Two such objects 30 cm apart, each placed right, give two bundles of rays: not merged.
TEST(FindDuplicate, AnObjectTwoStretchesOfViewsTriangulatedApartIsOneByItsRays) {
  const Eigen::Matrix3d R_wg = GravityFrame(Eigen::Vector3d::UnitZ());
  const Eigen::Vector3d truth(0.1, -0.2, 0.78);
  const auto duplicate = [&](const std::map<ObjectId, MapObject>& objects, double ratio) {
    ObjectsOptions options;
    options.merge_rays_ratio = ratio;
    const PinholeCamera camera = Camera();
    return FindDuplicate(objects, ObjectMapContext{options, camera, R_wg});
  };
  std::map<ObjectId, MapObject> one;
  one[1] = StretchOfViews(1, truth, 0.0, 0.1, 0);
  one[2] = StretchOfViews(2, truth, 40.0 * kPi / 180.0, -0.1, 100);
  ASSERT_GT((one[1].cuboid.centre - one[2].cuboid.centre).norm(), 0.1);
  const auto merged = duplicate(one, 1.5);
  ASSERT_TRUE(merged.has_value());
  EXPECT_EQ(std::set<ObjectId>({merged->first, merged->second}), std::set<ObjectId>({1, 2}));
  EXPECT_FALSE(duplicate(one, 0.0).has_value());  // merge_distance alone: too far apart

  std::map<ObjectId, MapObject> two;
  two[1] = StretchOfViews(1, truth, 0.0, 0.0, 0);
  two[2] = StretchOfViews(2, truth + Eigen::Vector3d(0.3, 0.0, 0.0), 40.0 * kPi / 180.0, 0.0, 100);
  EXPECT_FALSE(duplicate(two, 1.5).has_value());
}

// As above, but in the one frame the two are detected together (19) the second box is a
// stray one, shifted by 45 % of the cup's width and 20 % of its height (IoU 0.28, below
// Objects.duplicate_box_iou); the boxes after it (shifted by a quarter of the width and
// 15 % of the height) continue its track. One frame of a stray second box does not make
// two objects (Objects.seen_together_frames 2): merged; with 1 that frame kept them apart.
TEST_F(TwoObjectScene, ObjectsDetectedTogetherInOneFrameOnlyAreMerged) {
  ObjectsOptions options;
  options.seen_together_frames = 1;
  EXPECT_EQ(CupsWithASecondBox(options, {19}, 0.45, 0.2), 2);
  options.seen_together_frames = 2;
  EXPECT_EQ(CupsWithASecondBox(options, {19}, 0.45, 0.2), 1);
}

// A real detector's double box: with every box of the cup, a second one on its upper part
// (IoU 0.44, so non-maximum suppression keeps both), and in one frame of three the second
// box alone (a candidate triangulates from boxes beside no more confident box of its
// class). Each box feeds its own object; both are detected together in most frames, so
// "never seen together" cannot tell them apart. Two solid objects cannot share the space
// the smaller one takes up: they are merged.
TEST_F(TwoObjectScene, AnObjectInsideAnotherOfItsClassIsMergedEvenIfSeenTogether) {
  const auto objects_after_hygiene = [this](double merge_overlap) {
    ObjectsOptions options;
    options.merge_overlap = merge_overlap;
    // The nested box overlaps the cup's by IoU 0.44: with the duplicate-box rule on, its
    // candidate joins the cup at once. Off, it makes an object of its own, which is the
    // case of this rule.
    options.duplicate_box_iou = 1.0;
    ObjectMap map(options, Camera());
    for (int frame = 0; frame < 40; ++frame) {
      const SE3 T_cw = OrbitPose(0.02 * frame);
      std::vector<Detection> detections = DetectionsAt(T_cw);
      const Detection cup = detections[0];
      detections.push_back(
          {41, cup.x + 0.1 * cup.width, cup.y, 0.8 * cup.width, 0.55 * cup.height, 0.8});
      if (frame % 3 == 0) detections.erase(detections.begin());
      map.AddFrame(frame, frame / 30.0, T_cw, FilterDetections(detections, options, Camera()));
    }
    EXPECT_EQ(map.objects().size(), 3u) << "the nested boxes made an object of their own";
    map.MakeKeyframeObservation(0, 1.0, OrbitPose(0.78), nullptr);
    return map.objects().size();
  };
  EXPECT_EQ(objects_after_hygiene(1.0), 3u);  // the rule off: the duplicate cup stays
  EXPECT_EQ(objects_after_hygiene(0.5), 2u);
}

TEST_F(TwoObjectScene, MapPointsFormEachObjectsPointSetWithoutTheBackground) {
  ObjectsOptions options;
  ObjectMap without_points(options, Camera());
  Watch(without_points, options, 0, 40);
  ObjectMap map(options, Camera());
  const auto points = ScenePoints();
  Watch(map, options, 0, 40, true, &points);
  ASSERT_EQ(map.objects().size(), 2u);
  int wall_votes = 0;
  for (const auto& [id, object] : map.objects()) {
    const Cuboid& truth = object.class_id == 41 ? cup_ : laptop_;
    for (const auto& [point_id, point] : object.points) wall_votes += point_id >= 1000 ? 1 : 0;
    const std::vector<Eigen::Vector3d> point_set = ObjectPointSet(object, options.min_point_votes);
    EXPECT_GE(point_set.size(), 8u) << object.class_id;
    for (const Eigen::Vector3d& point : point_set) {
      // On the object's top face, never the wall 4 m away.
      EXPECT_LT((point - truth.centre).norm(), truth.size.maxCoeff()) << object.class_id;
    }
    // The point cues agree with the boxes: every frame is associated as without them.
    EXPECT_EQ(object.sightings.size(), without_points.objects().at(id).sightings.size());
  }
  EXPECT_GT(wall_votes, 0);  // the boxes did catch the background
}

TEST_F(TwoObjectScene, ObjectsFollowTheirCamerasAndPointsWhenTheMapIsOptimized) {
  ObjectsOptions options;
  ObjectMap map(options, Camera());
  const auto points = ScenePoints();
  Watch(map, options, 0, 40, true, &points);
  map.EstimatePending();  // the estimates of every sighting (Objects.reestimate_share)
  std::map<ObjectId, Eigen::Vector3d> before;
  for (const auto& [id, object] : map.objects()) before[id] = object.cuboid.centre;
  // Bundle adjustment moved the whole map by 0.3 m along x: every camera and point moved
  // with it; point 100 (on the cup) was fused into another and is gone.
  const Eigen::Vector3d shift(0.3, 0, 0);
  std::map<std::uint64_t, Eigen::Vector3d> moved;
  for (const auto& [id, position] : points) moved[id] = position + shift;
  moved.erase(100);
  map.FollowMap(
      [&](std::int64_t frame) -> std::optional<SE3> {
        return OrbitPose(0.02 * frame) * SE3(Eigen::Matrix3d::Identity(), -shift);
      },
      [&](std::uint64_t id) -> std::optional<Eigen::Vector3d> {
        const auto found = moved.find(id);
        if (found == moved.end()) return {};
        return found->second;
      });
  int points_checked = 0;
  for (const auto& [id, object] : map.objects()) {
    EXPECT_LT((object.cuboid.centre - (before[id] + shift)).norm(), 1e-6) << id;
    EXPECT_EQ(object.points.count(100), 0u);
    for (const auto& [point_id, point] : object.points) {
      EXPECT_LT((point.position - moved.at(point_id)).norm(), 1e-12) << point_id;
      ++points_checked;
    }
  }
  EXPECT_GT(points_checked, 20);
  // The OCG hears of the new centroids at the next keyframe.
  std::vector<ObjectChange> merges;
  const KeyframeObservation observation =
      map.MakeKeyframeObservation(0, 1.0, OrbitPose(0.78), &merges);
  EXPECT_EQ(observation.updates.size(), 2u);
}

// The id of the map's object of this class (the highest, when there are more); 0: none.
ObjectId IdOfClass(const ObjectMap& map, int class_id) {
  ObjectId found = 0;
  for (const auto& [id, object] : map.objects()) found = object.class_id == class_id ? id : found;
  return found;
}

// The ids of the points the object counts (at least min_votes votes), in id order.
std::vector<std::uint64_t> CountedPointIds(const MapObject& object, int min_votes) {
  std::vector<std::uint64_t> ids;
  for (const auto& [id, point] : object.points) {
    if (point.votes >= min_votes) ids.push_back(id);
  }
  return ids;
}

// FollowMap's changed points with their states, from positions (ids of points missing
// there: gone from the map). positions must outlive the result.
std::vector<ObjectMap::ChangedPoint> ChangedPointsOf(
    const std::vector<std::uint64_t>& ids,
    const std::map<std::uint64_t, Eigen::Vector3d>& positions) {
  std::vector<ObjectMap::ChangedPoint> changed;
  for (const std::uint64_t id : ids) {
    const auto found = positions.find(id);
    changed.push_back({id, found == positions.end() ? nullptr : &found->second, nullptr});
  }
  std::sort(changed.begin(), changed.end(),
            [](const auto& a, const auto& b) { return a.id < b.id; });
  return changed;
}

// A local adjustment deep in a revisited map moves many points by tiny amounts: a point
// that moved less than Objects.follow_tolerance keeps the position its object was
// estimated with and re-estimates nothing; once its moves add up past the tolerance (the
// copy compares with what it holds, not with the last move) it follows. With tolerance 0
// every move is followed.
TEST_F(TwoObjectScene, PointsThatMovedLessThanTheFollowToleranceLeaveTheirObjects) {
  const auto points = ScenePoints();
  for (const double tolerance : {0.001, 0.0}) {
    ObjectsOptions options;
    options.follow_tolerance = tolerance;
    ObjectMap map(options, Camera());
    Watch(map, options, 0, 40, true, &points);
    std::map<std::uint64_t, Eigen::Vector3d> positions(points.begin(), points.end());
    std::map<std::int64_t, SE3> poses;
    for (int frame = 0; frame < 40; ++frame) poses[frame] = OrbitPose(0.02 * frame);
    const auto follow = [&](const std::vector<std::uint64_t>& changed) {
      const std::vector<std::int64_t> no_frames;
      const std::vector<ObjectMap::ChangedPoint> states = ChangedPointsOf(changed, positions);
      map.FollowMap(
          [&](std::int64_t frame) -> std::optional<SE3> { return poses.at(frame); },
          [&](std::uint64_t id) -> std::optional<Eigen::Vector3d> { return positions.at(id); }, {},
          &no_frames, &states);
    };
    map.SetUp(Eigen::Vector3d::UnitZ());
    follow({});
    ASSERT_EQ(map.objects().size(), 2u);
    const ObjectId cup = IdOfClass(map, 41);
    ASSERT_GT(cup, 0);
    const MapObject before = map.objects().at(cup);
    ASSERT_GT(before.points.size(), 4u);
    // The cup's counted points (those FollowMap follows) sink 0.6 mm, twice over.
    const std::vector<std::uint64_t> changed = CountedPointIds(before, options.min_point_votes);
    for (const std::uint64_t id : changed) positions[id] -= Eigen::Vector3d(0, 0, 0.0006);
    ASSERT_GT(changed.size(), 4u);
    follow(changed);
    const MapObject& once = map.objects().at(cup);
    for (const std::uint64_t id : changed) {
      const Eigen::Vector3d expected =
          tolerance > 0.0 ? before.points.at(id).position : positions.at(id);
      EXPECT_EQ(once.points.at(id).position, expected)
          << "tolerance " << tolerance << ", point " << id;
    }
    if (tolerance > 0.0) {
      EXPECT_EQ(once.cuboid.centre, before.cuboid.centre);
    }
    for (const std::uint64_t id : changed) positions[id] -= Eigen::Vector3d(0, 0, 0.0006);
    follow(changed);
    for (const std::uint64_t id : changed) {
      EXPECT_EQ(map.objects().at(cup).points.at(id).position, positions.at(id))
          << "tolerance " << tolerance << ", point " << id;
    }
  }
}

// Given a keyframe's changes (the frames and points that moved), FollowMap visits only
// those (the points through its point -> objects index) and estimates again only the
// objects whose sightings or points moved, and all of them once up turned by more than a
// tenth of a degree: with up unchanged, that is what following everything gives.
TEST_F(TwoObjectScene, IncrementalFollowMapEqualsEstimatingEveryObject) {
  ObjectsOptions options;
  options.yaw_min_elongation = 1.2;  // the laptop's points give its yaw
  ObjectMap full(options, Camera()), incremental(options, Camera());
  const auto points = ScenePoints();
  std::map<std::uint64_t, Eigen::Vector3d> positions(points.begin(), points.end());
  std::map<std::int64_t, SE3> poses;
  for (ObjectMap* map : {&full, &incremental}) {
    Watch(*map, options, 0, 40, true, &points);
    Watch(*map, options, 40, 60, false, &points);  // the laptop alone
  }
  for (int frame = 0; frame < 60; ++frame) poses[frame] = OrbitPose(0.02 * frame);
  ASSERT_EQ(full.objects().size(), 2u);
  // full: every sighting, every point, every object; incremental: what changed.
  const auto follow = [&](ObjectMap& map, const std::vector<std::int64_t>& frames,
                          const std::vector<std::uint64_t>& changed_points) {
    const bool all = &map == &full;
    const std::vector<ObjectMap::ChangedPoint> states = ChangedPointsOf(changed_points, positions);
    map.FollowMap(
        [&](std::int64_t frame) -> std::optional<SE3> { return poses.at(frame); },
        [&](std::uint64_t id) -> std::optional<Eigen::Vector3d> { return positions.at(id); }, {},
        all ? nullptr : &frames, all ? nullptr : &states);
  };
  const auto cuboids = [](const ObjectMap& map) {
    std::map<ObjectId, Cuboid> result;
    for (const auto& [id, object] : map.objects()) result[id] = object.cuboid;
    return result;
  };
  const auto expect_equal = [&](const char* step) {
    const auto a = cuboids(full), b = cuboids(incremental);
    ASSERT_EQ(a.size(), b.size()) << step;
    for (const auto& [id, cuboid] : a) {
      EXPECT_EQ(cuboid.centre, b.at(id).centre) << step << ": object " << id;
      EXPECT_EQ(cuboid.size, b.at(id).size) << step << ": object " << id;
      EXPECT_EQ(cuboid.yaw, b.at(id).yaw) << step << ": object " << id;
    }
  };
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const auto turned = [&](double degrees) {
    return Eigen::AngleAxisd(degrees * kPi / 180.0, Eigen::Vector3d::UnitX()) * up;
  };
  // The first call estimates every object in both.
  for (ObjectMap* map : {&full, &incremental}) {
    map->SetUp(up);
    follow(*map, {}, {});
  }
  expect_equal("first call");
  const ObjectId laptop = IdOfClass(full, 63);
  ASSERT_GT(laptop, 0);
  // A local adjustment moved the frames where the laptop was seen alone.
  std::vector<std::int64_t> moved_frames;
  for (int frame = 40; frame < 60; ++frame) {
    poses[frame] = SE3(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.05, 0, 0)) * poses[frame];
    moved_frames.push_back(frame);
  }
  Cuboid before = full.objects().at(laptop).cuboid;
  for (ObjectMap* map : {&full, &incremental}) follow(*map, moved_frames, {});
  ASSERT_GT((full.objects().at(laptop).cuboid.centre - before.centre).norm(), 1e-4);
  expect_equal("frames moved");
  // It moved the laptop's points alone (turned about its centre): its yaw follows them.
  std::vector<std::uint64_t> moved_points;
  for (auto& [id, position] : positions) {
    if (id >= 200 && id < 216) moved_points.push_back(id);
    if (id >= 200 && id < 216)
      position = laptop_.centre +
                 Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) * (position - laptop_.centre);
  }
  before = full.objects().at(laptop).cuboid;
  for (ObjectMap* map : {&full, &incremental}) follow(*map, {}, moved_points);
  ASSERT_GT(std::abs(full.objects().at(laptop).cuboid.yaw - before.yaw), 1e-3);
  expect_equal("points moved");
  // Up turned by more than a tenth of a degree: every object is estimated again.
  for (ObjectMap* map : {&full, &incremental}) {
    map->SetUp(turned(0.5));
    follow(*map, {}, {});
  }
  expect_equal("up turned");
  // By less: the objects nothing moved keep their cuboids, within that turn of the others.
  for (ObjectMap* map : {&full, &incremental}) {
    map->SetUp(turned(0.55));
    follow(*map, {}, {});
  }
  for (const auto& [id, object] : full.objects()) {
    const Cuboid& kept = incremental.objects().at(id).cuboid;
    EXPECT_LT((object.cuboid.centre - kept.centre).norm(), 1e-3 * object.cuboid.size.maxCoeff());
    EXPECT_LT((object.cuboid.size - kept.size).norm(), 0.02 * object.cuboid.size.maxCoeff());
  }
}

// Objects.reestimate_share: a new sighting estimates an object again only once the changes
// since its last estimate reach that share of the sightings it had then; the changes still
// waiting are estimated by EstimatePending, to exactly what estimating at every change
// gives. So a mature object costs a bounded amount per new sighting (issue 37, point 3).
TEST_F(TwoObjectScene, AnObjectIsEstimatedAgainOnceItsChangesReachTheShare) {
  ObjectsOptions every_change, half;
  every_change.reestimate_share = 0.0;
  half.reestimate_share = 0.5;
  ObjectMap eager(every_change, Camera()), lagging(half, Camera());
  Watch(eager, every_change, 0, 40);
  Watch(lagging, half, 0, 40);
  const ObjectId cup = IdOfClass(eager, 41);
  ASSERT_GT(cup, 0);
  ASSERT_EQ(IdOfClass(lagging, 41), cup);
  EXPECT_EQ(eager.objects().at(cup).changes_since_estimate, 0);
  // Its boxes now pull its estimate 2 cm aside, frame by frame.
  cup_.centre += Eigen::Vector3d(0.02, 0.0, 0.0);
  const MapObject& waiting = lagging.objects().at(cup);
  const int due =
      static_cast<int>(std::ceil(0.5 * static_cast<double>(waiting.sightings_at_estimate)));
  ASSERT_GT(due - waiting.changes_since_estimate, 2);
  const Eigen::Vector3d estimated = waiting.cuboid.centre;
  int frame = 40;
  while (waiting.changes_since_estimate + 1 < due) {
    Watch(eager, every_change, frame, frame + 1);
    Watch(lagging, half, frame, frame + 1);
    ++frame;
    EXPECT_EQ(waiting.cuboid.centre, estimated) << "frame " << frame;
  }
  EXPECT_GT((eager.objects().at(cup).cuboid.centre - estimated).norm(), 1e-3);
  // The change that reaches the share.
  Watch(eager, every_change, frame, frame + 1);
  Watch(lagging, half, frame, frame + 1);
  ++frame;
  EXPECT_EQ(waiting.changes_since_estimate, 0);
  EXPECT_EQ(waiting.cuboid.centre, eager.objects().at(cup).cuboid.centre);
  // A few changes wait again; EstimatePending (before outputs) takes them in.
  Watch(eager, every_change, frame, frame + 3);
  Watch(lagging, half, frame, frame + 3);
  EXPECT_EQ(waiting.changes_since_estimate, 3);
  EXPECT_NE(waiting.cuboid.centre, eager.objects().at(cup).cuboid.centre);
  lagging.EstimatePending();
  EXPECT_EQ(waiting.changes_since_estimate, 0);
  for (const auto& [id, object] : eager.objects()) {
    const Cuboid& kept = lagging.objects().at(id).cuboid;
    EXPECT_EQ(object.cuboid.centre, kept.centre) << "object " << id;
    EXPECT_EQ(object.cuboid.size, kept.size) << "object " << id;
    EXPECT_EQ(object.cuboid.yaw, kept.yaw) << "object " << id;
  }
}

// The changed points come with their states (SLAM's journal gives them): FollowMap takes
// those, asks position_of_point only for the points that joined an entity since the last
// call, and a changed point given as gone leaves its entity.
TEST_F(TwoObjectScene, FollowMapTakesTheChangedPointsStatesFromTheChanges) {
  ObjectsOptions options;
  ObjectMap map(options, Camera());
  const auto points = ScenePoints();
  Watch(map, options, 0, 40, true, &points);
  const std::map<std::uint64_t, Eigen::Vector3d> positions(points.begin(), points.end());
  int asked = 0;
  const auto follow = [&](const std::vector<ObjectMap::ChangedPoint>& changed) {
    const std::vector<std::int64_t> no_frames;
    map.FollowMap([&](std::int64_t frame) -> std::optional<SE3> { return OrbitPose(0.02 * frame); },
                  [&](std::uint64_t id) -> std::optional<Eigen::Vector3d> {
                    ++asked;
                    return positions.at(id);
                  },
                  {}, &no_frames, &changed);
  };
  map.SetUp(Eigen::Vector3d::UnitZ());
  follow({});
  EXPECT_GT(asked, 0);  // the points that joined the objects while they were watched
  const ObjectId cup = IdOfClass(map, 41);
  ASSERT_GT(cup, 0);
  const MapObject before = map.objects().at(cup);
  ASSERT_GT(before.points.size(), 4u);
  // Of the cup's counted points (FollowMap follows no others), the first is gone from the
  // map, the others rose 1 cm; the callback still gives the old positions.
  const std::vector<std::uint64_t> ids = CountedPointIds(before, options.min_point_votes);
  ASSERT_GT(ids.size(), 4u);
  std::map<std::uint64_t, Eigen::Vector3d> moved;
  for (const std::uint64_t id : ids) {
    if (id != ids.front()) moved[id] = before.points.at(id).position + Eigen::Vector3d(0, 0, 0.01);
  }
  asked = 0;
  follow(ChangedPointsOf(ids, moved));
  EXPECT_EQ(asked, 0);
  const MapObject& after = map.objects().at(cup);
  EXPECT_EQ(after.points.count(ids.front()), 0u);
  ASSERT_EQ(after.points.size(), before.points.size() - 1);
  for (const std::uint64_t id : ids) {
    if (id != ids.front()) {
      EXPECT_EQ(after.points.at(id).position, moved.at(id)) << id;
    }
  }
}

// A point an object holds with fewer than Objects.min_point_votes votes counts nowhere
// (ObjectPointIds), so FollowMap does not follow it: the background in a box gives many
// such points, and each would cost a lookup at every keyframe. Once its votes reach the
// threshold it is read from the map at the next call (it may have moved since its last
// vote), and followed from then on.
TEST_F(TwoObjectScene, FollowMapFollowsAPointOnceItsVotesCountIt) {
  ObjectsOptions options;
  ASSERT_EQ(options.min_point_votes, 3);
  ObjectMap map(options, Camera());
  auto points = ScenePoints();
  Watch(map, options, 0, 40, true, &points);
  std::map<std::uint64_t, Eigen::Vector3d> positions(points.begin(), points.end());
  const std::vector<std::int64_t> no_frames;
  const auto follow = [&](const std::vector<std::uint64_t>& changed) {
    const std::vector<ObjectMap::ChangedPoint> states = ChangedPointsOf(changed, positions);
    map.FollowMap([&](std::int64_t frame) -> std::optional<SE3> { return OrbitPose(0.02 * frame); },
                  [&](std::uint64_t id) -> std::optional<Eigen::Vector3d> {
                    const auto found = positions.find(id);
                    if (found == positions.end()) return {};
                    return found->second;
                  },
                  {}, &no_frames, &states);
  };
  map.SetUp(Eigen::Vector3d::UnitZ());
  follow({});
  const ObjectId cup = IdOfClass(map, 41);
  ASSERT_GT(cup, 0);
  // A new point on the cup's top, tracked in one frame: one vote.
  constexpr std::uint64_t kNew = 500;
  const Eigen::Vector3d first = cup_.centre + Eigen::Vector3d(0, 0, 0.5 * cup_.size.z());
  points.push_back({kNew, first});
  positions[kNew] = first;
  Watch(map, options, 40, 41, true, &points);
  ASSERT_EQ(map.objects().at(cup).points.at(kNew).votes, 1);
  // The map moves it 1 cm: not followed.
  positions[kNew] = first + Eigen::Vector3d(0, 0, 0.01);
  follow({kNew});
  EXPECT_EQ(map.objects().at(cup).points.at(kNew).position, first);
  // Two more votes (tracking still saw it where it was), then the map moves it again
  // before the next call: that call reads it.
  positions[kNew] = first;
  Watch(map, options, 41, 43, true, &points);
  ASSERT_EQ(map.objects().at(cup).points.at(kNew).votes, 3);
  const Eigen::Vector3d moved = first + Eigen::Vector3d(0, 0, 0.02);
  positions[kNew] = moved;
  follow({});
  EXPECT_EQ(map.objects().at(cup).points.at(kNew).position, moved);
  // Followed from then on: moved again, and then gone.
  positions[kNew] = moved + Eigen::Vector3d(0, 0, 0.01);
  follow({kNew});
  EXPECT_EQ(map.objects().at(cup).points.at(kNew).position, positions[kNew]);
  positions.erase(kNew);
  follow({kNew});
  EXPECT_EQ(map.objects().at(cup).points.count(kNew), 0u);
}

TEST(MinAreaRectangle, FindsTheRectangleOfRotatedPoints) {
  const double yaw = 0.5;
  const Eigen::Rotation2Dd rotation(yaw);
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < 40; ++i) {  // a 0.4 x 0.1 rectangle's outline and inside, at (1, 2)
    const double u = 0.4 * ((i % 8) / 7.0 - 0.5), v = 0.1 * ((i / 8) / 4.0 - 0.5);
    points.push_back(Eigen::Vector2d(1, 2) + rotation * Eigen::Vector2d(u, v));
  }
  const Rectangle2 rectangle = MinAreaRectangle(points);
  ASSERT_TRUE(rectangle.valid);
  EXPECT_NEAR(rectangle.yaw, yaw, 1e-9);
  EXPECT_NEAR(rectangle.length, 0.4, 1e-9);
  EXPECT_NEAR(rectangle.width, 0.1, 1e-9);
  EXPECT_LT((rectangle.centre - Eigen::Vector2d(1, 2)).norm(), 1e-9);
  // A quarter turn more is the same rectangle, its sides swapped, yaw kept in [0, 90).
  for (Eigen::Vector2d& p : points) p = Eigen::Rotation2Dd(kPi / 2) * p;
  const Rectangle2 turned = MinAreaRectangle(points);
  EXPECT_NEAR(turned.yaw, yaw, 1e-9);
  EXPECT_NEAR(turned.length, 0.1, 1e-9);
  EXPECT_NEAR(turned.width, 0.4, 1e-9);
  EXPECT_FALSE(MinAreaRectangle({{0, 0}, {1, 1}, {2, 2}}).valid);  // one line
}

// A long box seen from a narrow range of azimuths: the boxes alone cannot tell its yaw;
// the map points on its top face can.
TEST(ObjectMap, YawFromThePointSetWhenTheViewsAreNarrow) {
  const Cuboid truth = TurnedBox(Eigen::Vector3d(0.4, 0.15, 0.2));
  const Eigen::Matrix3d R_wg = GravityFrame(Eigen::Vector3d::UnitZ());
  std::vector<std::pair<std::uint64_t, Eigen::Vector3d>> points;
  for (int i = 0; i < 25; ++i) {
    const Eigen::Vector3d local(0.9 * truth.size.x() * ((i % 5) / 4.0 - 0.5),
                                0.9 * truth.size.y() * ((i / 5) / 4.0 - 0.5), 0.5 * truth.size.z());
    points.push_back(
        {static_cast<std::uint64_t>(i),
         truth.centre + Eigen::AngleAxisd(truth.yaw, Eigen::Vector3d::UnitZ()) * local});
  }
  ObjectsOptions options;
  options.classes = {73};
  const auto watch = [&](bool with_points) {
    ObjectMap map(options, Camera());
    for (int frame = 0; frame < 20; ++frame) {  // 23 degrees of azimuth
      const SE3 T_cw = OrbitPose(0.02 * frame, truth.centre);
      const Box2 box = *ProjectCuboid(truth, R_wg, T_cw, Camera());
      std::vector<PointObservation> tracked;
      for (const auto& [id, position] : points)
        tracked.push_back({id, Camera().ProjectUndistorted(T_cw * position), position});
      map.AddFrame(frame, frame / 30.0, T_cw,
                   FilterDetections({{73, box.x0, box.y0, box.Width(), box.Height(), 0.9}}, options,
                                    Camera()),
                   with_points ? &tracked : nullptr);
    }
    return map.objects();
  };
  const auto without = watch(false);
  ASSERT_EQ(without.size(), 1u);
  EXPECT_EQ(without.begin()->second.cuboid.yaw, 0.0);  // square footprint, no yaw
  const auto with = watch(true);
  ASSERT_EQ(with.size(), 1u);
  const Cuboid& estimate = with.begin()->second.cuboid;
  EXPECT_LT(std::abs(std::remainder(estimate.yaw - truth.yaw, kPi / 2)), 2 * kPi / 180);
  EXPECT_LT((estimate.centre - truth.centre).norm(), 0.15 * truth.size.maxCoeff());
}

// An object of 10 map points (a 5 x 2 grid, 8 by 4 cm), in front of the
// camera; its point set is what a tracked frame is checked against.
MapObject ObjectOfTenPoints(const SE3& T_cw) {
  MapObject object;
  object.id = 1;
  object.has_cuboid = true;
  object.cuboid.centre = T_cw.Inverse() * Eigen::Vector3d(0, 0, 1.5);
  object.cuboid.size = Eigen::Vector3d(0.1, 0.1, 0.1);
  for (std::uint64_t id = 0; id < 10; ++id) {
    const Eigen::Vector3d offset(0.02 * (static_cast<int>(id % 5) - 2),
                                 0.04 * static_cast<int>(id / 5) - 0.02, 0.0);
    object.points.Vote(id, 3, object.cuboid.centre + offset);
  }
  return object;
}

TEST(PresentByPoints, MostOfItsPointsInViewTrackedSaysPresent) {
  const SE3 T_cw = OrbitPose(0.0);
  const MapObject object = ObjectOfTenPoints(T_cw);
  ASSERT_EQ(ObjectPointIds(object, 3).size(), 10u);
  ObjectsOptions options;  // at least 5 tracked, and half of those in the image
  EXPECT_TRUE(PresentByPoints(object, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9}, T_cw, Camera(), options));
  EXPECT_TRUE(PresentByPoints(object, {0, 1, 2, 3, 4}, T_cw, Camera(), options));
  // A third of its points: what stays at the place of an object carried away (the table
  // behind it) is not the object.
  EXPECT_FALSE(PresentByPoints(object, {0, 1, 2, 3}, T_cw, Camera(), options));
  EXPECT_FALSE(PresentByPoints(object, {}, T_cw, Camera(), options)) << "no SLAM map";
  options.presence_min_share = 0.6;
  EXPECT_FALSE(PresentByPoints(object, {0, 1, 2, 3, 4}, T_cw, Camera(), options));
  // Points tracked by ids the object does not hold say nothing about it.
  EXPECT_FALSE(PresentByPoints(object, {20, 21, 22, 23, 24, 25}, T_cw, Camera(), options));
}

TEST(PresentByPoints, PointsOutsideTheImageAreNotAsked) {
  const SE3 T_cw = OrbitPose(0.0);
  const MapObject object = ObjectOfTenPoints(T_cw);
  ObjectsOptions options;
  // Five of its ten points tracked: from T_cw, half of the set in the image, enough. With
  // the camera turned round (the object behind it) none of its points is in the image, so
  // the same ids count for nothing (only points that project into the image are asked).
  const SE3 turned_round = SE3(Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitY()).toRotationMatrix(),
                               Eigen::Vector3d::Zero()) *
                           T_cw;
  EXPECT_TRUE(PresentByPoints(object, {0, 1, 2, 3, 4}, T_cw, Camera(), options));
  EXPECT_FALSE(PresentByPoints(object, {0, 1, 2, 3, 4}, turned_round, Camera(), options));
}

TEST(RobustPointBounds, LeaveOutliersOut) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 50; ++i)
    points.emplace_back(0.01 * (i % 7), 0.01 * (i % 5), 1.0 + 0.01 * (i % 3));
  points.emplace_back(2.0, 0.0, 1.0);
  points.emplace_back(0.0, 0.0, 5.0);
  const RobustBounds bounds = RobustPointBounds(points, 3.0);
  ASSERT_TRUE(bounds.valid);
  for (int i = 0; i < 50; ++i) EXPECT_TRUE(bounds.Contains(points[i])) << i;
  EXPECT_FALSE(bounds.Contains(points[50]));
  EXPECT_FALSE(bounds.Contains(points[51]));
  EXPECT_FALSE(RobustPointBounds({points[0], points[1]}, 3.0).valid);
}

TEST(PointsInBox, ShrinksTheBox) {
  const std::vector<PointObservation> points = {
      {1, Eigen::Vector2d(150, 150), Eigen::Vector3d::Zero()},
      {2, Eigen::Vector2d(105, 150), Eigen::Vector3d::Zero()},   // in the edge band
      {3, Eigen::Vector2d(250, 150), Eigen::Vector3d::Zero()}};  // outside
  const Box2 box{100, 100, 200, 200};
  EXPECT_EQ(PointsInBox(points, box, 0.0).size(), 2u);
  const auto inner = PointsInBox(points, box, 0.1);
  ASSERT_EQ(inner.size(), 1u);
  EXPECT_EQ(inner[0]->id, 1u);
}

// A monocular map in the first camera's frame (y down): a floor, a table top, a wall and
// clutter; the cameras pan about the vertical, looking 30 degrees down.
TEST(SupportingPlane, FindsTheFloorNotTheWallFromTheCamerasUp) {
  const Eigen::Matrix3d R_map = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized())
                                    .toRotationMatrix();  // the map's arbitrary frame
  const Eigen::Vector3d true_up = R_map * Eigen::Vector3d::UnitZ();
  std::vector<Eigen::Matrix3d> cameras;
  for (int i = 0; i < 12; ++i) {
    const double yaw = 0.15 * i;
    const Eigen::Vector3d forward(std::cos(yaw) * std::cos(kPi / 6),
                                  std::sin(yaw) * std::cos(kPi / 6), -std::sin(kPi / 6));
    const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
    Eigen::Matrix3d R_wc;
    R_wc << right, forward.cross(right), forward;
    cameras.push_back(R_map * R_wc);
  }
  const Eigen::Vector3d prior = CameraUpPrior(cameras);
  EXPECT_GT(prior.dot(true_up), std::cos(2 * kPi / 180));

  std::vector<Eigen::Vector3d> points;
  std::uint32_t state = 7;
  const auto noise = [&state] {  // deterministic, +-5 mm
    state = state * 1664525u + 1013904223u;
    return 0.01 * (state / 4294967296.0 - 0.5);
  };
  for (int i = 0; i < 900; ++i) {  // floor, 3 x 3 m
    points.push_back(R_map * Eigen::Vector3d(0.1 * (i % 30), 0.1 * (i / 30), noise()));
  }
  for (int i = 0; i < 1200; ++i) {  // a bigger wall
    points.push_back(R_map * Eigen::Vector3d(3.0 + noise(), 0.1 * (i % 40), 0.1 * (i / 40)));
  }
  for (int i = 0; i < 100; ++i) {  // a table top, 0.7 m up
    points.push_back(R_map * Eigen::Vector3d(1 + 0.1 * (i % 10), 1 + 0.1 * (i / 10), 0.7));
  }
  // The prior is tilted 20 degrees towards the wall: still within the 40-degree cone.
  const Eigen::Vector3d tilted =
      Eigen::AngleAxisd(20 * kPi / 180, R_map * Eigen::Vector3d::UnitY()) * true_up;
  const SupportingPlane plane = FindSupportingPlane(points, tilted, 40, 0.02, 300, 42);
  ASSERT_TRUE(plane.valid);
  EXPECT_GT(plane.normal.dot(true_up), std::cos(1 * kPi / 180));
  EXPECT_GE(plane.inliers, 850);
  EXPECT_LT(plane.inliers, 1100);  // the floor, not the wall
  const SupportingPlane again = FindSupportingPlane(points, tilted, 40, 0.02, 300, 42);
  EXPECT_EQ(again.normal, plane.normal);  // deterministic for a seed
  EXPECT_FALSE(
      FindSupportingPlane({points.begin(), points.begin() + 20}, tilted, 40, 0.02, 300, 42).valid);
}

// The floor points cover a small patch, noisily: their plane is tilted. The bottoms of
// objects standing on the floor and on a table top, spread over the room, level it.
TEST(SupportingPlane, ObjectBottomsRefineTheTilt) {
  std::vector<Eigen::Vector3d> points;
  std::uint32_t state = 11;
  const auto noise = [&state] {  // deterministic, +-1 cm
    state = state * 1664525u + 1013904223u;
    return 0.02 * (state / 4294967296.0 - 0.5);
  };
  const Eigen::Matrix3d tilt =
      Eigen::AngleAxisd(3 * kPi / 180, Eigen::Vector3d::UnitX()).toRotationMatrix();
  for (int i = 0; i < 100; ++i)  // a 0.3 m patch, tilted 3 degrees (a biased estimate)
    points.push_back(tilt * Eigen::Vector3d(0.03 * (i % 10), 0.03 * (i / 10), noise()));
  const SupportingPlane plane =
      FindSupportingPlane(points, Eigen::Vector3d::UnitZ(), 40, 0.05, 200, 3);
  ASSERT_TRUE(plane.valid);
  const double tilt_before = std::acos(std::min(1.0, plane.normal.z()));
  EXPECT_GT(tilt_before, 2 * kPi / 180);
  std::vector<Eigen::Vector3d> bottoms;
  for (int i = 0; i < 5; ++i) {
    bottoms.emplace_back(-2.0 + i, 1.5 * std::sin(i), 0.0);            // on the floor
    bottoms.emplace_back(0.2 * i, 0.3 * std::cos(i), 0.75 + noise());  // on the table
  }
  const Eigen::Vector3d up = RefineUpWithBottoms(plane, bottoms, 0.1);
  const double tilt_after = std::acos(std::min(1.0, up.z()));
  EXPECT_LT(tilt_after, 0.5 * tilt_before);
  // Two bottoms a level are not enough: the plane stays as it was.
  EXPECT_EQ(RefineUpWithBottoms(plane, {bottoms[0], bottoms[1], bottoms[2], bottoms[3]}, 0.1),
            plane.normal);
}

// Real data: 58 keyframes of TUM fr3/cabinet with ground-truth poses and YOLO boxes of the
// cabinet (CubeSLAM's files); the cuboid from the boxes against the ground-truth cuboid.
TEST(RealCabinet, CuboidFromBoxesMatchesTheGroundTruth) {
  const std::optional<std::string> data = testing::SharedDataDir();
  if (!data) GTEST_SKIP() << testing::SharedDataSkipMessage();
  const std::string folder = *data + "/tum_fr3_cabinet_keyframes";
  const std::vector<StampedPose> poses = ReadTumTrajectory(folder + "/truth_cam_poses.txt");
  ASSERT_EQ(poses.size(), 58u);
  PinholeCamera camera = Camera();  // TUM3.yaml: fr3 is undistorted
  camera.fx = 535.4;
  camera.fy = 539.2;
  camera.cx = 320.1;
  camera.cy = 247.6;
  ObjectsOptions options;
  options.classes = {72};  // the boxes have no class: call the cabinet a refrigerator
  ObjectMap map(options, camera);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    char name[64];
    std::snprintf(name, sizeof name, "/filter_2d_obj_txts/%04zu_yolo2_0.15.txt", i);
    std::ifstream file(folder + name);
    ASSERT_TRUE(file) << folder + name;
    std::vector<Detection> detections;
    double x = 0, y = 0, w = 0, h = 0, score = 0;
    while (file >> x >> y >> w >> h >> score) detections.push_back({72, x, y, w, h, score});
    map.AddFrame(static_cast<std::int64_t>(i), poses[i].timestamp, poses[i].T_wc.Inverse(),
                 FilterDetections(detections, options, camera));
  }
  ASSERT_EQ(map.objects().size(), 1u);
  const Cuboid& cuboid = map.objects().begin()->second.cuboid;
  // truth_objects.txt: centre, yaw, half sizes.
  const Eigen::Vector3d centre(-1.52988, 0.456476, 0.281575);
  const Eigen::Vector3d size = 2 * Eigen::Vector3d(0.396318, 0.222742, 0.272709);
  std::printf("cabinet: centre %.3f %.3f %.3f (error %.3f m), size %.3f %.3f %.3f, yaw %.3f\n",
              cuboid.centre.x(), cuboid.centre.y(), cuboid.centre.z(),
              (cuboid.centre - centre).norm(), cuboid.size.x(), cuboid.size.y(), cuboid.size.z(),
              cuboid.yaw);
  EXPECT_LT((cuboid.centre - centre).norm(), 0.25 * size.maxCoeff());
  EXPECT_NEAR(cuboid.size.z(), size.z(), 0.3 * size.z());
  const double long_side = std::max(cuboid.size.x(), cuboid.size.y());
  EXPECT_NEAR(long_side, size.x(), 0.3 * size.x());
  // The long side's direction, modulo 180 degrees (truth: yaw 3.10 of its x side). The
  // short side is not checked: seen from the front only, its depth is poorly observed.
  const double long_yaw = cuboid.size.x() >= cuboid.size.y() ? cuboid.yaw : cuboid.yaw + kPi / 2;
  EXPECT_LT(std::abs(std::remainder(long_yaw - 3.10232, kPi)), 10 * kPi / 180);
}

// The cup, mapped over frames 0-39, is lost for 20 frames and found again coming out from
// behind something nearer: for 10 frames its box is the visible part only, its right side
// growing from a fifth of the cup's width, then whole, drifting sideways (real boxes
// do). The first box misses the re-acquire gate and starts a candidate, which keeps the
// track through its predicted box; its rays, through the centres of growing boxes,
// meet far from the cup in depth on its line of sight. Without Objects.join_candidates it
// is a second cup beyond the merge distance; with it, the track fits the cup's
// projection (the partial views inside it, the whole boxes over it) and joins the cup,
// whose centre stays put (the partial views join truncated).
TEST_F(TwoObjectScene, AReDetectionAtTheWrongDepthOnTheSameRayJoinsTheObject) {
  const auto run = [this](bool join_candidates) {
    ObjectsOptions options;
    options.join_candidates = join_candidates;
    ObjectMap map(options, Camera());
    Watch(map, options, 0, 40);
    Watch(map, options, 40, 60, /*cup_visible=*/false);
    for (int frame = 60; frame < 80; ++frame) {
      const SE3 T_cw = OrbitPose(0.02 * frame);
      std::vector<Detection> detections = DetectionsAt(T_cw);
      Detection& cup = detections[0];
      if (frame < 70) {
        const double visible = 0.2 + 0.08 * (frame - 60);
        cup.x += (1.0 - visible) * cup.width;
        cup.width *= visible;
      } else {
        cup.x += 0.6 * (frame - 70);
      }
      map.AddFrame(frame, frame / 30.0, T_cw, FilterDetections(detections, options, Camera()));
    }
    return map;
  };
  const ObjectMap separate = run(false);
  ASSERT_EQ(separate.objects().size(), 3u) << "the case needs a second cup";
  std::vector<const MapObject*> cups;
  for (const auto& [id, object] : separate.objects()) {
    if (object.class_id == 41) cups.push_back(&object);
  }
  ASSERT_EQ(cups.size(), 2u);
  EXPECT_GT((cups[1]->cuboid.centre - cups[0]->cuboid.centre).norm(),
            ObjectsOptions().merge_distance * cups[0]->cuboid.size.maxCoeff());

  const ObjectMap joined = run(true);
  ASSERT_EQ(joined.objects().size(), 2u);
  for (const auto& [id, object] : joined.objects()) {
    if (object.class_id != 41) continue;
    EXPECT_EQ(object.sightings.size(), 60u);  // 40 before the gap, 20 after
    // The boxes showing less than 40 % of the cup's width (IoU below 0.4): partial views.
    const auto partial = std::count_if(object.sightings.begin(), object.sightings.end(),
                                       [](const ObjectSighting& s) { return s.truncated; });
    EXPECT_EQ(partial, 3);
    EXPECT_LT((object.cuboid.centre - cup_.centre).norm(), 0.15 * cup_.size.maxCoeff());
  }
}

// The cup mapped from whole views (frames 0-49), then hidden, then seen with its left 65 %
// behind something nearer for 30 frames (each box the cup's right part): with the join off,
// those boxes miss the re-acquire gate, become an object of their own where their
// off-centre rays meet, and the keyframe merges it into the cup along the rays. Its boxes
// are partial views of the cup: their centres are not the cup's, so they must not move
// it (they join as truncated sightings, as a joining candidate's do).
TEST_F(TwoObjectScene, PartialViewsMergedIntoAnObjectDoNotMoveIt) {
  ObjectsOptions options;
  options.join_candidates = false;
  ObjectMap map(options, Camera());
  Watch(map, options, 0, 50);
  Watch(map, options, 50, 70, /*cup_visible=*/false);
  const auto cup_of = [](const ObjectMap& objects) -> const MapObject* {
    const MapObject* cup = nullptr;
    for (const auto& [id, object] : objects.objects()) {
      if (object.class_id == 41 && (cup == nullptr || object.id < cup->id)) cup = &object;
    }
    return cup;
  };
  const Eigen::Vector3d mapped = cup_of(map)->cuboid.centre;
  for (int frame = 70; frame < 100; ++frame) {
    const SE3 T_cw = OrbitPose(0.02 * frame);
    std::vector<Detection> detections = DetectionsAt(T_cw);
    Detection& cup = detections[0];
    cup.x += 0.65 * cup.width;
    cup.width *= 0.35;
    map.AddFrame(frame, frame / 30.0, T_cw, FilterDetections(detections, options, Camera()));
  }
  std::size_t cups = 0;
  for (const auto& [id, object] : map.objects()) cups += object.class_id == 41 ? 1 : 0;
  ASSERT_EQ(cups, 2u) << "the case needs the partial views mapped as an object of their own";
  std::vector<ObjectChange> merges;
  map.MakeKeyframeObservation(0, 100 / 30.0, OrbitPose(2.0), &merges);
  ASSERT_EQ(merges.size(), 1u);
  const MapObject& merged = *cup_of(map);
  EXPECT_EQ(merged.sightings.size(), 80u);
  EXPECT_LT((merged.cuboid.centre - mapped).norm(), 1e-3);
}

// Two cups side by side, 0.15 m apart across the line of sight: the first is detected in
// frames 0-39, the second (put down beside it) in frames 40-79, while the first is hidden.
// Never seen together, so only geometry tells them apart: the second cup's boxes lie
// beside the first one's projection, not on it, so it neither joins it as a candidate nor
// is merged with it at the keyframe.
TEST_F(TwoObjectScene, TwoCupsSideBySideStayTwo) {
  ObjectsOptions options;
  ObjectMap map(options, Camera());
  Watch(map, options, 0, 40);
  const Cuboid first = cup_;
  cup_.centre += 0.15 * Eigen::Vector3d(-std::sin(1.2), std::cos(1.2), 0.0);
  Watch(map, options, 40, 80);
  map.MakeKeyframeObservation(0, 80 / 30.0, OrbitPose(1.6), nullptr);
  std::vector<Eigen::Vector3d> cups;
  for (const auto& [id, object] : map.objects()) {
    if (object.class_id == 41) cups.push_back(object.cuboid.centre);
  }
  ASSERT_EQ(cups.size(), 2u);
  EXPECT_LT((cups[0] - first.centre).norm(), 0.15 * first.size.maxCoeff());
  EXPECT_LT((cups[1] - cup_.centre).norm(), 0.15 * cup_.size.maxCoeff());
  cup_ = first;
}

// A hard object (issue 18): the detector finds the cup in one frame of ten only (the
// laptop in every frame). Each cup box comes after its candidate's predicted box is gone
// (Objects.predicted_box_frames), so without Objects.candidate_gap_seconds every box
// starts a candidate of its own, dropped before the next one, and the cup is never mapped;
// with it, the boxes continue one track, which becomes the cup. A second cup 0.3 m
// beside it, detected in the frames between (five after each box of the first), is
// another track: its boxes fit no depth of the first one's rays, so both cups are
// mapped, each at its place, each with its own boxes only.
TEST_F(TwoObjectScene, ACandidateDetectedOneFrameInTenStillBecomesAnObject) {
  Cuboid second = cup_;
  second.centre += Eigen::Vector3d(-0.1, 0.28, 0.0);
  const Eigen::Matrix3d R_wg = GravityFrame(Eigen::Vector3d::UnitZ());
  struct Cup {
    Eigen::Vector3d centre;
    std::vector<std::int64_t> frames;
  };
  const auto run = [&](double gap_seconds, bool with_second) {
    ObjectsOptions options;
    options.candidate_gap_seconds = gap_seconds;
    ObjectMap map(options, Camera());
    for (int frame = 0; frame < 160; ++frame) {
      const SE3 T_cw = OrbitPose(0.005 * frame);  // 3 degrees round the cup in 10 frames
      std::vector<Detection> detections = DetectionsAt(T_cw, /*cup_visible=*/frame % 10 == 0);
      if (with_second && frame % 10 == 7) {
        const Box2 box = *ProjectCuboid(second, R_wg, T_cw, Camera());
        detections.push_back({41, box.x0, box.y0, box.Width(), box.Height(), 0.9});
      }
      map.AddFrame(frame, frame / 30.0, T_cw, FilterDetections(detections, options, Camera()));
    }
    std::vector<Cup> cups;
    for (const auto& [id, object] : map.objects()) {
      if (object.class_id != 41) continue;
      cups.push_back({object.cuboid.centre, {}});
      for (const ObjectSighting& sighting : object.sightings)
        cups.back().frames.push_back(sighting.frame);
    }
    return cups;
  };
  EXPECT_TRUE(run(0.0, false).empty())
      << "the case needs a cup that is never mapped without the rule";
  const double gap_seconds = ObjectsOptions().candidate_gap_seconds;
  const std::vector<Cup> alone = run(gap_seconds, false);
  ASSERT_EQ(alone.size(), 1u);
  EXPECT_EQ(alone[0].frames.size(), 16u);  // every box from the first
  EXPECT_LT((alone[0].centre - cup_.centre).norm(), 0.15 * cup_.size.maxCoeff());

  const std::vector<Cup> two = run(gap_seconds, true);
  ASSERT_EQ(two.size(), 2u);
  for (const Cup& cup : two) {
    const bool first = (cup.centre - cup_.centre).norm() < 0.15 * cup_.size.maxCoeff();
    const bool other = (cup.centre - second.centre).norm() < 0.15 * second.size.maxCoeff();
    EXPECT_TRUE(first || other) << cup.centre.transpose();
    EXPECT_GE(cup.frames.size(), 14u);
    for (std::int64_t frame : cup.frames)
      EXPECT_EQ(frame % 10, first ? 0 : 7) << "a box of the other cup joined";
  }
}

// A hard object's first run of boxes (frames 0, 10, 20: too few to triangulate) and, 80
// frames on, 23 degrees further round, the run that maps it (every frame from 100). The
// later boxes do not continue the first run's track from that far round (its depth is
// not fixed: PredictsSharply), so the cup is mapped from the later run; the first run's
// candidate, waiting for a box, then fits the cup's projection and joins it at the next
// keyframe: the cup has every box. Without Objects.candidate_gap_seconds the first run's
// candidate is gone by then.
TEST_F(TwoObjectScene, AnEarlierRunOfBoxesJoinsTheObjectMappedLater) {
  const auto cup_sightings = [&](double gap_seconds) {
    ObjectsOptions options;
    options.candidate_gap_seconds = gap_seconds;
    ObjectMap map(options, Camera());
    for (int frame = 0; frame < 140; ++frame) {
      const SE3 T_cw = OrbitPose(0.005 * frame);
      const bool cup_seen = frame >= 100 || (frame <= 20 && frame % 10 == 0);
      map.AddFrame(frame, frame / 30.0, T_cw,
                   FilterDetections(DetectionsAt(T_cw, cup_seen), options, Camera()));
    }
    map.MakeKeyframeObservation(0, 140 / 30.0, OrbitPose(0.7), nullptr);
    std::size_t sightings = 0;
    for (const auto& [id, object] : map.objects()) {
      if (object.class_id != 41) continue;
      EXPECT_EQ(sightings, 0u) << "one cup";
      sightings = object.sightings.size();
      EXPECT_LT((object.cuboid.centre - cup_.centre).norm(), 0.15 * cup_.size.maxCoeff());
    }
    return sightings;
  };
  EXPECT_EQ(cup_sightings(0.0), 40u);
  EXPECT_EQ(cup_sightings(ObjectsOptions().candidate_gap_seconds), 43u);
}

// A television and, 0.26 m from its centre, a cup (on the table in front of it), never
// detected in the same frame: within half the television's width, beyond half the cup's
// size. One object under two classes has one size, so they stay two; two cups as far
// apart relative to the larger's size would be merged.
TEST_F(TwoObjectScene, ASmallObjectNearALargeOneOfAnotherClassIsNotMergedIntoIt) {
  Cuboid tv;
  tv.centre = Eigen::Vector3d(0.0, -0.05, 0.95);
  tv.size = Eigen::Vector3d(0.6, 0.1, 0.4);
  const Eigen::Matrix3d R_wg = GravityFrame(Eigen::Vector3d::UnitZ());
  ObjectsOptions options;
  ObjectMap map(options, Camera());
  for (int frame = 0; frame < 80; ++frame) {
    const SE3 T_cw = OrbitPose(0.02 * frame);
    const bool tv_seen = frame < 40;
    const Box2 box = *ProjectCuboid(tv_seen ? tv : cup_, R_wg, T_cw, Camera());
    const std::vector<Detection> detections = {
        {tv_seen ? 62 : 41, box.x0, box.y0, box.Width(), box.Height(), 0.9}};
    map.AddFrame(frame, frame / 30.0, T_cw, FilterDetections(detections, options, Camera()));
  }
  ASSERT_EQ(map.objects().size(), 2u);
  std::vector<ObjectChange> merges;
  map.MakeKeyframeObservation(0, 80 / 30.0, OrbitPose(1.6), &merges);
  EXPECT_TRUE(merges.empty());
  EXPECT_EQ(map.objects().size(), 2u);
  EXPECT_LT((cup_.centre - tv.centre).norm(), 0.5 * tv.size.maxCoeff());
}

// A detector that loses the cup for a while: the OCG removes it, and once it is detected
// again a new cup object forms at its place. With restore on (OCG.mode "restore"), that is
// the cup found again: back with its id and sightings, a "restored" change, the OCG told
// to restore it and to forget the stand-in. Off, after the window, or found elsewhere (a
// move), the new cup stays a new object.
TEST_F(TwoObjectScene, ARemovedObjectFoundAgainAtItsPlaceIsRestored) {
  struct Outcome {
    ObjectId removed = 0;
    std::map<ObjectId, std::size_t> cups;  // live cups: id -> sightings
    KeyframeObservation observation;
    std::vector<ObjectChange> changes;
  };
  const auto run = [this](bool restore, double window, const Eigen::Vector3d& shift) {
    ObjectsOptions options;
    options.restore_window = window;
    ObjectMap map(options, Camera());
    map.SetRestore(restore);
    Outcome outcome;
    Watch(map, options, 0, 40);
    map.MakeKeyframeObservation(0, 40 / 30.0, OrbitPose(0.8), nullptr);
    for (const auto& [id, object] : map.objects()) {
      if (object.class_id == 41) outcome.removed = id;
    }
    Watch(map, options, 40, 50, /*cup_visible=*/false);
    RemovalEvent event;
    event.object_id = outcome.removed;
    event.keyframe_id = 1;
    event.timestamp = 50 / 30.0;
    map.Remove(event);
    cup_.centre += shift;
    Watch(map, options, 50, 100);
    cup_.centre -= shift;
    outcome.observation = map.MakeKeyframeObservation(2, 100 / 30.0, OrbitPose(2.0), nullptr);
    for (const auto& [id, object] : map.objects()) {
      if (object.class_id == 41) outcome.cups[id] = object.sightings.size();
    }
    outcome.changes = map.changes();
    return outcome;
  };
  const Outcome restored = run(true, 60.0, Eigen::Vector3d::Zero());
  ASSERT_EQ(restored.cups.size(), 1u);
  EXPECT_EQ(restored.cups.begin()->first, restored.removed);
  EXPECT_GE(restored.cups.begin()->second, 40u + 45u);  // its history and the new sightings
  EXPECT_EQ(restored.observation.restored, (std::vector<ObjectId>{restored.removed}));
  ASSERT_FALSE(restored.changes.empty());
  const ObjectChange& change = restored.changes.back();
  EXPECT_EQ(change.type, "restored");
  EXPECT_EQ(change.object_id, restored.removed);
  EXPECT_DOUBLE_EQ(change.removed_at, 50 / 30.0);
  EXPECT_NE(change.recreated_as, restored.removed);
  EXPECT_EQ(restored.observation.forgotten, (std::vector<ObjectId>{change.recreated_as}));
  EXPECT_LT((change.cuboid.centre - cup_.centre).norm(), 0.15 * cup_.size.maxCoeff());

  for (const auto& [what, outcome] :
       {std::pair{"restore off", run(false, 60.0, Eigen::Vector3d::Zero())},
        std::pair{"after the window", run(true, 1.0, Eigen::Vector3d::Zero())},
        std::pair{"moved 0.25 m", run(true, 60.0, Eigen::Vector3d(0.2, -0.15, 0))}}) {
    ASSERT_EQ(outcome.cups.size(), 1u) << what;
    EXPECT_NE(outcome.cups.begin()->first, outcome.removed) << what;
    EXPECT_TRUE(outcome.observation.restored.empty()) << what;
    for (const ObjectChange& entry : outcome.changes) EXPECT_NE(entry.type, "restored") << what;
  }
}

// A camera going back and forth over the same arc for 800 frames: each object keeps at
// most Objects.max_sightings sightings, yet reports every one it had, stays where it is, and
// nothing else appears (issue 33: each revisit added a sighting of ~0.3 kB, for good).
TEST_F(TwoObjectScene, ARevisitedObjectKeepsABoundedHistoryAndAnswersAsBefore) {
  const auto run = [&](int max_sightings) {
    ObjectsOptions options;
    options.max_sightings = max_sightings;
    ObjectMap map(options, Camera());
    EXPECT_TRUE(BackAndForth(map, options, 800).empty());
    return map;
  };
  const ObjectMap bounded = run(64);
  const ObjectMap all = run(0);
  ASSERT_EQ(bounded.objects().size(), 2u);
  ASSERT_EQ(all.objects().size(), 2u);
  const nlohmann::json listed = nlohmann::json::parse(ObjectsJson(bounded, {}))["objects"];
  for (const auto& [id, object] : bounded.objects()) {
    const MapObject& whole = all.objects().at(id);
    EXPECT_LE(object.sightings.size(), 64u);
    EXPECT_GT(whole.sightings.size(), 700u);
    EXPECT_EQ(object.sightings.total(), whole.sightings.size());
    EXPECT_EQ(object.class_id, whole.class_id);
    EXPECT_DOUBLE_EQ(object.last_timestamp, whole.last_timestamp);
    const Cuboid& truth = object.class_id == 41 ? cup_ : laptop_;
    EXPECT_LT((object.cuboid.centre - truth.centre).norm(), 0.15 * truth.size.maxCoeff());
    EXPECT_LT((object.cuboid.centre - whole.cuboid.centre).norm(), 0.05 * truth.size.maxCoeff());
    for (const nlohmann::json& entry : listed) {
      if (entry["id"] == id) {
        EXPECT_EQ(entry["observations"], whole.sightings.size());
      }
    }
  }
  EXPECT_EQ(bounded.SeenAsClassThisSession().first, all.SeenAsClassThisSession().first);
  EXPECT_EQ(bounded.SeenAsClassThisSession().last, all.SeenAsClassThisSession().last);
}

// An object watched for 5,000 frames keeps at most Objects.max_sightings sightings and
// Objects.max_object_points map points (the most voted), so what a keyframe costs per
// object stays bounded; its cuboid stays within a tenth of its size of the one every
// sighting and point give.
TEST_F(TwoObjectScene, ALongWatchedObjectKeepsBoundedSightingsAndPoints) {
  // The objects' points and a stretch of the wall behind them (enough for the bound).
  std::vector<std::pair<std::uint64_t, Eigen::Vector3d>> points = ScenePoints();
  points.resize(32 + 160);
  const auto run = [&](int max_sightings, int max_points) {
    ObjectsOptions options;
    options.max_sightings = max_sightings;
    options.max_object_points = max_points;
    ObjectMap map(options, Camera());
    BackAndForth(map, options, 5000, &points);
    return map;
  };
  const ObjectMap bounded = run(256, 20);
  const ObjectMap all = run(0, 0);
  ASSERT_EQ(bounded.objects().size(), 2u);
  ASSERT_EQ(all.objects().size(), 2u);
  const std::size_t limit = 256;
  for (const auto& [id, object] : bounded.objects()) {
    const MapObject& whole = all.objects().at(id);
    EXPECT_LE(object.sightings.size(), limit);
    EXPECT_GT(whole.sightings.size(), 4000u);
    EXPECT_EQ(object.sightings.total(), whole.sightings.size());
    EXPECT_LE(object.points.size(), 25u);  // 20, pruned once a quarter over
    EXPECT_GT(whole.points.size(), 25u);
    const double size = whole.cuboid.size.maxCoeff();
    EXPECT_LT((object.cuboid.centre - whole.cuboid.centre).norm(), 0.1 * size);
    EXPECT_LT((object.cuboid.size - whole.cuboid.size).norm(), 0.1 * size);
  }
}

}  // namespace
}  // namespace ocg
