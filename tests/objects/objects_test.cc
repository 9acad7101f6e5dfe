// The object layer: assignment, ray intersection, cuboid estimation, detection filtering,
// and the object map on a scene of known cuboids seen by a moving camera.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "ocg/objects/assignment.h"
#include "ocg/objects/object_geometry.h"
#include "ocg/objects/object_map.h"

namespace ocg {
namespace {

constexpr double kPi = 3.14159265358979323846;

PinholeCamera Camera() {
  PinholeCamera camera;
  camera.fx = camera.fy = 525.0;
  camera.cx = 319.5;
  camera.cy = 239.5;
  camera.width = 640;
  camera.height = 480;
  return camera;
}

// A camera at the given azimuth on a circle of radius 1.5 m, 0.5 m above the target,
// looking at the target (world z up).
SE3 OrbitPose(double azimuth, const Eigen::Vector3d& target = Eigen::Vector3d(0, 0, 0.8)) {
  const Eigen::Vector3d centre =
      target + Eigen::Vector3d(1.5 * std::cos(azimuth), 1.5 * std::sin(azimuth), 0.5);
  const Eigen::Vector3d forward = (target - centre).normalized();
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Matrix3d R_wc;
  R_wc << right, down, forward;
  return SE3(R_wc, centre).Inverse();
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

TEST(IntersectRays, ParallelRaysHaveNoIntersection) {
  std::vector<Ray> rays = {{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d::UnitX()},
                           {Eigen::Vector3d(0, 1, 0), Eigen::Vector3d::UnitX()}};
  EXPECT_FALSE(IntersectRays(rays).valid);
  EXPECT_FALSE(IntersectRays({rays[0]}).valid);
}

TEST(EstimateCuboid, SizeAndYawFromBoxesAllAround) {
  Cuboid truth;
  truth.centre = Eigen::Vector3d(0, 0, 0.8);
  truth.size = Eigen::Vector3d(0.4, 0.2, 0.15);
  truth.yaw = 0.5;
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
  // Frames first..last-1 of the orbit into the map (the cup hidden if asked).
  void Watch(ObjectMap& map, const ObjectsOptions& options, int first, int last,
             bool cup_visible = true) const {
    for (int frame = first; frame < last; ++frame) {
      const SE3 T_cw = OrbitPose(0.02 * frame);
      map.AddFrame(frame, frame / 30.0, T_cw,
                   FilterDetections(DetectionsAt(T_cw, cup_visible), options, Camera()));
    }
  }
  Cuboid cup_, laptop_;
};

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

TEST_F(TwoObjectScene, TheSameObjectMappedTwiceIsMerged) {
  ObjectsOptions options;
  options.min_reacquire_iou = 1.0;  // after a gap, nothing is found again: new objects
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
  EXPECT_EQ(forgotten, (std::vector<ObjectId>{merges[0].object_id, merges[1].object_id}));
  for (const auto& [id, object] : map.objects()) EXPECT_EQ(object.sightings.size(), 50u);
}

}  // namespace
}  // namespace ocg
