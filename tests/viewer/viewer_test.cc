// The off-screen viewer: known scenes rendered and read back pixel by pixel.

#include <gtest/gtest.h>

#include <unistd.h>
#include <fstream>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "ocg/core/file_io.h"
#include "ocg/io/point_cloud.h"
#include "ocg/viewer/diff_view.h"
#include "ocg/viewer/frame_view.h"
#include "ocg/viewer/map_view.h"
#include "ocg/viewer/run_scene.h"
#include "ocg/viewer/snapshots.h"
#include "test_support.h"

namespace ocg {
namespace {

ViewerOptions SmallSnapshots() {
  ViewerOptions options;
  options.snapshot_width = 480;
  options.snapshot_height = 360;
  return options;
}

ObjectView Object(std::int64_t id, const Eigen::Vector3d& centre, int state, bool removed = false) {
  ObjectView object;
  object.id = id;
  object.class_id = 41;
  object.cuboid.centre = centre;
  object.cuboid.size = Eigen::Vector3d(0.4, 0.4, 0.4);
  object.state = state;
  object.removed = removed;
  return object;
}

cv::Vec3b PixelAt(const cv::Mat& image, const ViewCamera& view, const Eigen::Vector3d& point) {
  const Eigen::Vector2d pixel = view.camera.ProjectUndistorted(view.T_cw * point);
  return image.at<cv::Vec3b>(static_cast<int>(pixel.y()), static_cast<int>(pixel.x()));
}

bool IsWhite(const cv::Vec3b& bgr) { return bgr[0] > 245 && bgr[1] > 245 && bgr[2] > 245; }

// A table-sized scene: two objects, one observed (green) and one suspicious (red), a
// removed ghost, map points on the floor, a few keyframes.
MapScene TwoObjects() {
  MapScene scene;
  scene.objects = {Object(1, {-1, 0, 0.2}, 1), Object(2, {1, 0, 0.2}, 4),
                   Object(3, {0, 1.2, 0.2}, 0, true)};
  for (int i = 0; i < 400; ++i)
    scene.points.emplace_back(-2 + 0.2 * (i % 20), -2 + 0.2 * (i / 20), 0);
  for (int i = 0; i < 5; ++i) {
    scene.keyframes.push_back(LookAt({-1.5 + 0.5 * i, -2.5, 1.2}, {0, 0, 0.2}).Inverse());
    scene.trajectory.push_back(scene.keyframes.back().translation());
  }
  return scene;
}

TEST(MapView, CuboidsShowTheirStateColourWhereTheyProject) {
  Renderer renderer(480, 360);
  const ViewerOptions options = SmallSnapshots();
  const MapScene scene = TwoObjects();
  for (MapViewpoint viewpoint : {MapViewpoint::kTopDown, MapViewpoint::kThreeQuarter}) {
    const cv::Mat image = RenderMapView(renderer, scene, options, viewpoint);
    ASSERT_EQ(image.cols, 480);
    ASSERT_EQ(image.rows, 360);
    const ViewCamera view = MapViewCamera(scene, options, viewpoint);
    // The top face's centre: observed is green, suspicious red.
    const cv::Vec3b observed = PixelAt(image, view, {-1, 0, 0.4});
    EXPECT_GT(observed[1], observed[2] + 60) << ToString(viewpoint);
    EXPECT_GT(observed[1], observed[0] + 60) << ToString(viewpoint);
    const cv::Vec3b suspicious = PixelAt(image, view, {1, 0, 0.4});
    EXPECT_GT(suspicious[2], suspicious[1] + 60) << ToString(viewpoint);
    // A ghost has edges only: its top face's centre shows what is behind (the floor's
    // white between the map points).
    EXPECT_TRUE(IsWhite(PixelAt(image, view, {0.02, 1.22, 0.4}))) << ToString(viewpoint);
  }
}

TEST(MapView, PointsAndBackground) {
  Renderer renderer(480, 360);
  const ViewerOptions options = SmallSnapshots();
  MapScene scene;
  scene.points = {{0, 0, 0}, {1, 1, 0}, {-1, 1, 0}};
  const cv::Mat image = RenderMapView(renderer, scene, options, MapViewpoint::kTopDown);
  const ViewCamera view = MapViewCamera(scene, options, MapViewpoint::kTopDown);
  for (const Eigen::Vector3d& point : scene.points) {
    const cv::Vec3b pixel = PixelAt(image, view, point);
    EXPECT_LT(pixel[0] + pixel[1] + pixel[2], 100) << point.transpose();  // black
  }
  EXPECT_TRUE(IsWhite(PixelAt(image, view, {0.5, 0.5, 0})));
  EXPECT_TRUE(IsWhite(image.at<cv::Vec3b>(350, 470)));
}

TEST(MapView, AnEmptyMapRendersAsTheBackground) {
  Renderer renderer(480, 360);
  const ViewerOptions options = SmallSnapshots();
  for (MapViewpoint viewpoint :
       {MapViewpoint::kFollow, MapViewpoint::kTopDown, MapViewpoint::kThreeQuarter}) {
    const cv::Mat image = RenderMapView(renderer, MapScene{}, options, viewpoint);
    ASSERT_EQ(image.size(), cv::Size(480, 360));
    // Everything but the legend in the top-left corner is white.
    const cv::Mat outside_legend = image(cv::Rect(200, 120, 280, 240));
    EXPECT_EQ(cv::countNonZero(outside_legend.reshape(1) < 245), 0) << ToString(viewpoint);
  }
}

TEST(MapView, FollowViewIsBehindTheLastKeyframe) {
  const ViewerOptions options = SmallSnapshots();
  const MapScene scene = TwoObjects();
  const ViewCamera view = MapViewCamera(scene, options, MapViewpoint::kFollow);
  const SE3& T_wc = scene.keyframes.back();
  const Eigen::Vector3d eye =
      T_wc * Eigen::Vector3d(options.viewpoint_x, options.viewpoint_y, options.viewpoint_z);
  EXPECT_LT((view.T_cw.Inverse().translation() - eye).norm(), 1e-9);
  // The keyframe's camera is straight ahead, in the middle of the image.
  const Eigen::Vector3d camera_in_view = view.T_cw * T_wc.translation();
  EXPECT_NEAR(camera_in_view.x(), 0.0, 1e-9);
  EXPECT_NEAR(camera_in_view.y(), 0.0, 1e-9);
  EXPECT_GT(camera_in_view.z(), 0.0);
  EXPECT_DOUBLE_EQ(view.camera.fx, options.viewpoint_f * options.snapshot_width / 1024.0);
}

long ResidentKilobytes() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return resident * sysconf(_SC_PAGESIZE) / 1024;
}

// AddressSanitizer keeps freed memory in quarantine (256 MB by default), so resident memory
// grows by design under it; LeakSanitizer checks for leaks there instead.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

TEST(MapView, AThousandRendersLeakNeitherMemoryNorContexts) {
  if (kAddressSanitizer) GTEST_SKIP() << "resident memory under AddressSanitizer's quarantine";
  const ViewerOptions options = SmallSnapshots();
  const MapScene scene = TwoObjects();
  {
    Renderer warm_up(480, 360);
    RenderMapView(warm_up, scene, options, MapViewpoint::kThreeQuarter);
  }
  const long before = ResidentKilobytes();
  Renderer renderer(480, 360);
  for (int i = 0; i < 1000; ++i) {
    RenderMapView(renderer, scene, options,
                  i % 2 == 0 ? MapViewpoint::kTopDown : MapViewpoint::kThreeQuarter);
  }
  for (int i = 0; i < 50; ++i) {  // contexts are made and freed
    Renderer another(480, 360);
    RenderMapView(another, scene, options, MapViewpoint::kTopDown);
  }
  const long growth = ResidentKilobytes() - before;
  // One context with its buffers is about 1.5 MB: a leak per render or per context would
  // show as hundreds of megabytes.
  EXPECT_LT(growth, 20 * 1024) << growth << " kB";
}

TEST(FrameView, CuboidEdgesInTheStateColourAndDetectionBoxes) {
  PinholeCamera camera;
  camera.width = 640;
  camera.height = 480;
  camera.cx = 319.5;
  camera.cy = 239.5;
  const SE3 T_cw = LookAt({0, -2, 1}, {0, 0, 0.2});
  const cv::Mat grey(480, 640, CV_8UC1, cv::Scalar(128));
  ObjectView observed = Object(1, {0, 0, 0.2}, 1);
  ObjectView gone = Object(2, {0.8, 0, 0.2}, 4, true);
  FrameDetection detection;
  detection.box = {100, 100, 200, 180};
  detection.class_id = 41;
  detection.confidence = 0.9;
  detection.object_id = 1;
  const cv::Mat view =
      RenderFrameView(grey, {detection}, {observed, gone}, T_cw, camera, Eigen::Vector3d::UnitZ());
  ASSERT_EQ(view.type(), CV_8UC3);
  // Midpoint of the observed cuboid's top front edge: green.
  const Eigen::Vector2d edge = camera.ProjectUndistorted(T_cw * Eigen::Vector3d(0, -0.2, 0.4));
  const cv::Vec3b on_edge = view.at<cv::Vec3b>(static_cast<int>(std::lround(edge.y())),
                                               static_cast<int>(std::lround(edge.x())));
  EXPECT_GT(on_edge[1], on_edge[2] + 60);
  // The removed object is not drawn: the grey image shows there.
  const Eigen::Vector2d gone_edge =
      camera.ProjectUndistorted(T_cw * Eigen::Vector3d(0.8, -0.2, 0.4));
  EXPECT_EQ(view.at<cv::Vec3b>(static_cast<int>(std::lround(gone_edge.y())),
                               static_cast<int>(std::lround(gone_edge.x()))),
            cv::Vec3b(128, 128, 128));
  // The detection's box: a white outline with a black core along its left side.
  EXPECT_EQ(view.at<cv::Vec3b>(150, 100), cv::Vec3b(0, 0, 0));
  EXPECT_EQ(view.at<cv::Vec3b>(150, 101), cv::Vec3b(255, 255, 255));
}

TEST(SnapshotPolicy, ParsesFinalEveryAndNone) {
  EXPECT_TRUE(ParseSnapshotPolicy("final").final);
  EXPECT_EQ(ParseSnapshotPolicy("final").every_keyframes, 0);
  const SnapshotPolicy every = ParseSnapshotPolicy("every:25");
  EXPECT_TRUE(every.final);
  EXPECT_EQ(every.every_keyframes, 25);
  EXPECT_FALSE(ParseSnapshotPolicy("none").Enabled());
  for (const char* bad : {"every:0", "every:", "every:x", "every:3x", "all", ""}) {
    EXPECT_THROW(ParseSnapshotPolicy(bad), std::invalid_argument) << bad;
  }
}

// A run folder written by hand: the scene read back holds what the files say.
TEST(RunScene, ReadsARunFolderAndWritesItsSnapshots) {
  const std::string run = testing::MakeTempDir("ocg_viewer_run");
  WriteFileAtomically(run + "/KeyFrameTrajectory.txt", "1.0 0 0 1 0 0 0 1\n2.0 0.5 0 1 0 0 0 1\n");
  WritePlyPoints(run + "/map_points.ply", {{0, 0, 0}, {1, 2, 3}});
  WriteFileAtomically(run + "/objects.json", R"({"up": [0, 0, 1], "objects": [
      {"id": 4, "class_id": 41, "cuboid": {"centre": [0, 0, 0.5], "size": [0.2, 0.2, 0.3],
       "yaw": 0.1}, "state": 2},
      {"id": 5, "class_id": 63, "cuboid": {"centre": [1, 0, 0.5], "size": [0.3, 0.2, 0.05],
       "yaw": 0}, "state": null}]})");
  WriteFileAtomically(run + "/changes.json", R"({"changes": [
      {"type": "merged", "object_id": 7, "class_id": 41,
       "cuboid": {"centre": [0, 0, 0.5], "size": [0.2, 0.2, 0.3], "yaw": 0}},
      {"type": "removed", "object_id": 6, "class_id": 63,
       "cuboid": {"centre": [2, 0, 0.5], "size": [0.3, 0.2, 0.05], "yaw": 0}}]})");
  const MapScene scene = ReadRunScene(run);
  ASSERT_EQ(scene.keyframes.size(), 2u);
  EXPECT_DOUBLE_EQ(scene.keyframes[1].translation().x(), 0.5);
  ASSERT_EQ(scene.points.size(), 2u);
  EXPECT_EQ(scene.points[1], Eigen::Vector3d(1, 2, 3));
  ASSERT_EQ(scene.objects.size(), 3u);  // two live, one removed; the merge is not drawn
  EXPECT_EQ(scene.objects[0].state, 2);
  EXPECT_DOUBLE_EQ(scene.objects[0].cuboid.yaw, 0.1);
  EXPECT_EQ(scene.objects[1].state, 0);
  EXPECT_TRUE(scene.objects[2].removed);
  EXPECT_EQ(scene.objects[2].id, 6);

  ViewerOptions options = SmallSnapshots();
  SnapshotWriter writer(run + "/snapshots", options);
  WriteFileAtomically(run + "/snapshots/stale.png", "old");
  WriteFileAtomically(run + "/snapshots/notes.txt", "kept");
  writer.RemoveOldSnapshots();
  EXPECT_FALSE(std::filesystem::exists(run + "/snapshots/stale.png"));
  EXPECT_TRUE(std::filesystem::exists(run + "/snapshots/notes.txt"));
  const std::vector<std::string> paths =
      writer.WriteMapViews(scene, "map", {MapViewpoint::kTopDown, MapViewpoint::kObjects});
  ASSERT_EQ(paths.size(), 2u);
  EXPECT_EQ(paths[0], run + "/snapshots/map_top.png");
  const cv::Mat image = cv::imread(paths[1]);
  EXPECT_EQ(image.size(), cv::Size(480, 360));
  std::filesystem::remove_all(run);
}

ObjectRecord Record(ObjectId id, int class_id, const Eigen::Vector3d& centre) {
  ObjectRecord record;
  record.id = id;
  record.class_id = class_id;
  record.cuboid.centre = centre;
  record.cuboid.size = Eigen::Vector3d(0.4, 0.4, 0.4);
  return record;
}

bool IsMagenta(const cv::Vec3b& bgr) { return bgr[2] > 150 && bgr[0] > 120 && bgr[1] < 90; }

TEST(DiffView, RemovedObjectsAreGhostsAndMovesArrowsAfterOnly) {
  MapDiff diff;
  const ObjectRecord cup = Record(1, 41, {-1, 0, 0.2}), book = Record(2, 73, {1, 0, 0.2});
  diff.unchanged.push_back({cup, cup, 0.0});
  diff.removed.push_back(book);
  diff.moved.push_back({Record(3, 63, {0, -1.2, 0.2}), Record(9, 63, {0, 1.2, 0.2}), 2.4});
  diff.added.push_back(Record(10, 64, {-1, 1.2, 0.2}));
  MapScene background;
  for (int i = 0; i < 400; ++i)
    background.points.emplace_back(-2 + 0.2 * (i % 20), -2 + 0.2 * (i / 20), 0);
  const DiffScenes scenes = MakeDiffScenes(diff, background);
  ASSERT_EQ(scenes.before.objects.size(), 3u);  // cup, book, laptop at its old place
  for (const ObjectView& object : scenes.before.objects) EXPECT_FALSE(object.removed);
  EXPECT_TRUE(scenes.before.moves.empty());
  ASSERT_EQ(scenes.after.objects.size(), 5u);  // cup, book ghost, laptop ghost and new, mouse
  ASSERT_EQ(scenes.after.moves.size(), 1u);
  EXPECT_EQ(scenes.after.moves[0].second, Eigen::Vector3d(0, 1.2, 0.2));
  EXPECT_EQ(scenes.after.points.size(), 400u);

  Renderer renderer(480, 360);
  const ViewerOptions options = SmallSnapshots();
  const cv::Mat before = RenderMapView(renderer, scenes.before, options, MapViewpoint::kTopDown);
  const cv::Mat after = RenderMapView(renderer, scenes.after, options, MapViewpoint::kTopDown);
  const ViewCamera before_view = MapViewCamera(scenes.before, options, MapViewpoint::kTopDown);
  const ViewCamera after_view = MapViewCamera(scenes.after, options, MapViewpoint::kTopDown);
  // The arrow's shaft, halfway, in the after snapshot only.
  EXPECT_TRUE(IsMagenta(PixelAt(after, after_view, {0, 0.1, 0.2})));
  EXPECT_FALSE(IsMagenta(PixelAt(before, before_view, {0, 0.1, 0.2})));
  // The removed book: solid before, a ghost (edges only) after.
  EXPECT_FALSE(IsWhite(PixelAt(before, before_view, {1.02, 0.02, 0.4})));
  EXPECT_TRUE(IsWhite(PixelAt(after, after_view, {1.02, 0.02, 0.4})));
}

TEST(RunScene, AMovedEntryIsAGhostWithAnArrow) {
  const std::string run = testing::MakeTempDir("ocg_viewer_moved");
  WriteFileAtomically(run + "/KeyFrameTrajectory.txt", "1.0 0 0 1 0 0 0 1\n");
  WriteFileAtomically(run + "/changes.json", R"({"changes": [
      {"type": "moved", "object_id": 6, "class_id": 63,
       "cuboid": {"centre": [2, 0, 0.5], "size": [0.3, 0.2, 0.05], "yaw": 0},
       "to": {"object_id": 8,
              "cuboid": {"centre": [0, 1, 0.5], "size": [0.3, 0.2, 0.05], "yaw": 0}}}]})");
  const MapScene scene = ReadRunScene(run);
  ASSERT_EQ(scene.objects.size(), 1u);
  EXPECT_TRUE(scene.objects[0].removed);
  ASSERT_EQ(scene.moves.size(), 1u);
  EXPECT_EQ(scene.moves[0].first, Eigen::Vector3d(2, 0, 0.5));
  EXPECT_EQ(scene.moves[0].second, Eigen::Vector3d(0, 1, 0.5));
}

// The run's own final snapshots take their arrows from the revised change log: only moves
// that stand (a later "restored" undoes one), never plain removals.
TEST(RunScene, ArrowsAreTheStandingMovesOfAChangeLog) {
  const nlohmann::json changes = nlohmann::json::parse(R"([
      {"type": "moved", "object_id": 6, "class_id": 63,
       "cuboid": {"centre": [2, 0, 0.5], "size": [0.3, 0.2, 0.05], "yaw": 0},
       "to": {"object_id": 9, "cuboid": {"centre": [0, 1, 0.5], "size": [0.3, 0.2, 0.05], "yaw": 0}}},
      {"type": "removed", "object_id": 3, "class_id": 41,
       "cuboid": {"centre": [1, 1, 0.5], "size": [0.1, 0.1, 0.1], "yaw": 0}},
      {"type": "moved", "object_id": 4, "class_id": 39,
       "cuboid": {"centre": [3, 0, 0.5], "size": [0.1, 0.1, 0.2], "yaw": 0},
       "to": {"object_id": 7, "cuboid": {"centre": [3, 2, 0.5], "size": [0.1, 0.1, 0.2], "yaw": 0}}},
      {"type": "restored", "object_id": 4, "class_id": 39,
       "cuboid": {"centre": [3, 0, 0.5], "size": [0.1, 0.1, 0.2], "yaw": 0}}])");
  const auto moves = MovesInChanges(changes);
  ASSERT_EQ(moves.size(), 1u);
  EXPECT_EQ(moves[0].first, Eigen::Vector3d(2, 0, 0.5));
  EXPECT_EQ(moves[0].second, Eigen::Vector3d(0, 1, 0.5));
  EXPECT_TRUE(MovesInChanges(nlohmann::json::array()).empty());
}

}  // namespace
}  // namespace ocg
