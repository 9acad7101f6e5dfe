// The off-screen viewer: known scenes rendered and read back pixel by pixel.

#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <array>
#include <fstream>
#include <map>
#include <sstream>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "ocg/core/file_io.h"
#include "ocg/io/point_cloud.h"
#include "ocg/viewer/diff_view.h"
#include "ocg/viewer/frame_view.h"
#include "ocg/viewer/label_layout.h"
#include "ocg/viewer/map_view.h"
#include "ocg/viewer/object_mesh.h"
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
    // All white: nothing drawn, so no legend either.
    EXPECT_EQ(cv::countNonZero(image.reshape(1) < 245), 0) << ToString(viewpoint);
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

// Issue 32, point 6: the legend lists only what is drawn.
TEST(MapView, TheLegendListsOnlyWhatIsDrawn) {
  EXPECT_TRUE(MapLegend(MapScene{}).empty());
  // A SLAM run without objects: no OCG state in its legend.
  MapScene slam_only = TwoObjects();
  slam_only.objects.clear();
  EXPECT_EQ(MapLegend(slam_only), (std::vector<std::string>{"keyframes", "camera path"}));
  MapScene scene = TwoObjects();
  EXPECT_EQ(MapLegend(scene), (std::vector<std::string>{"observed", "suspicious", "removed",
                                                        "keyframes", "camera path"}));
  scene.moves.emplace_back(Eigen::Vector3d(0, 1.2, 0.2), Eigen::Vector3d(1, 0, 0.2));
  scene.groundtruth = scene.trajectory;
  scene.trajectory_name = "given camera path";
  EXPECT_EQ(MapLegend(scene),
            (std::vector<std::string>{"observed", "suspicious", "removed", "moved", "keyframes",
                                      "given camera path", "ground truth"}));
  // The legend drawn: the observed green in its first row, nothing where a sixth row of the
  // five-state legend of old was.
  Renderer renderer(480, 360);
  const cv::Mat image =
      RenderMapView(renderer, slam_only, SmallSnapshots(), MapViewpoint::kTopDown);
  const cv::Vec3b first_row = image.at<cv::Vec3b>(14, 15);
  EXPECT_FALSE(first_row[1] > first_row[2] + 60 && first_row[1] > first_row[0] + 60);
}

TEST(Labels, PlacedLabelsNeverOverlapAndStayInTheImage) {
  // Thirty labels naming one pixel, and an obstacle (a legend) near it.
  std::vector<LabelRequest> requests(30, LabelRequest{{200, 150}, {90, 16}});
  const cv::Rect legend(150, 100, 40, 40);
  const std::vector<std::optional<cv::Rect>> boxes =
      PlaceLabels(requests, cv::Size(480, 360), {legend});
  ASSERT_EQ(boxes.size(), 30u);
  // The first takes its preferred place: above right of its pixel.
  ASSERT_TRUE(boxes[0]);
  EXPECT_EQ(boxes[0]->tl(), cv::Point(204, 130));
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    ASSERT_TRUE(boxes[i]) << i;
    EXPECT_EQ(*boxes[i] & cv::Rect(0, 0, 480, 360), *boxes[i]) << i;
    EXPECT_EQ((*boxes[i] & legend).area(), 0) << i;
    for (std::size_t j = 0; j < i; ++j)
      EXPECT_EQ((*boxes[i] & *boxes[j]).area(), 0) << i << " " << j;
  }
  // No free place near enough: left out rather than drawn over another.
  LabelLayoutOptions near;
  near.max_shift = 20;
  const auto crowded = PlaceLabels(requests, cv::Size(480, 360), {}, near);
  EXPECT_TRUE(crowded[0]);
  EXPECT_FALSE(crowded[29]);
  EXPECT_FALSE(PlaceLabels({{{10, 10}, {600, 16}}}, cv::Size(480, 360), {})[0]);
}

// fr3 long_office gave "25 bookigerator": a book and a refrigerator whose labels' places
// were one. Two objects projecting to the same spot get labels apart, the nearer one at its
// place, the other moved (with a leader line), neither over the legend.
TEST(Labels, TwoObjectsProjectingToOneSpotGetLabelsApart) {
  MapScene scene = TwoObjects();
  ObjectView book = Object(25, {-1, 0, 0.2}, 1);
  book.class_id = 73;
  ObjectView refrigerator = Object(23, {-1, 0, 0.2}, 1);
  refrigerator.class_id = 72;
  scene.objects = {book, refrigerator, Object(2, {1, 0, 0.2}, 4)};
  for (MapViewpoint viewpoint :
       {MapViewpoint::kTopDown, MapViewpoint::kThreeQuarter, MapViewpoint::kObjects}) {
    const std::vector<PlacedLabel> labels = MapViewLabels(scene, SmallSnapshots(), viewpoint);
    ASSERT_EQ(labels.size(), 3u) << ToString(viewpoint);
    const auto named = [&](const std::string& text) {
      return *std::find_if(labels.begin(), labels.end(),
                           [&](const PlacedLabel& label) { return label.text == text; });
    };
    const PlacedLabel first = named("25 book"), second = named("23 refrigerator");
    EXPECT_EQ(first.anchor, second.anchor) << ToString(viewpoint);
    EXPECT_EQ((first.box & second.box).area(), 0) << ToString(viewpoint);
    EXPECT_FALSE(first.moved) << ToString(viewpoint);  // listed first, as near
    EXPECT_TRUE(second.moved) << ToString(viewpoint);
    EXPECT_EQ((first.box & named("2 cup").box).area(), 0) << ToString(viewpoint);
    for (const PlacedLabel& label : labels) {
      EXPECT_EQ(label.box & cv::Rect(0, 0, 480, 360), label.box) << label.text;
      EXPECT_EQ((label.box & cv::Rect(0, 0, 160, 80)).area(), 0) << label.text;  // legend
    }
  }
}

TEST(FrameView, TrackedKeypointsAreGreenSquaresAndListedInTheLegend) {
  PinholeCamera camera;
  const SE3 T_cw = LookAt({0, -2, 1}, {0, 0, 0.2});
  const cv::Mat grey(480, 640, CV_8UC1, cv::Scalar(128));
  const cv::Mat without = RenderFrameView(grey, {}, {}, T_cw, camera, Eigen::Vector3d::UnitZ());
  EXPECT_EQ(cv::countNonZero(cv::Mat(without.reshape(1) != 128)), 0);  // nothing drawn, no legend
  const cv::Mat with =
      RenderFrameView(grey, {}, {}, T_cw, camera, Eigen::Vector3d::UnitZ(), {{400, 300}});
  EXPECT_EQ(with.at<cv::Vec3b>(300, 400), cv::Vec3b(0, 255, 0));  // the dot
  EXPECT_EQ(with.at<cv::Vec3b>(300, 405), cv::Vec3b(0, 255, 0));  // the square's side
  EXPECT_EQ(with.at<cv::Vec3b>(300, 408), cv::Vec3b(128, 128, 128));
  // The legend's panel in the top-left corner, lighter than the image.
  EXPECT_GT(with.at<cv::Vec3b>(8, 200)[0], 180);
}

// The diff's unchanged objects keep their state's colour (blue: recently observed), not a
// grey that reads as removed; new ones are labelled.
TEST(DiffView, ObjectsKeepTheirStateColourAndNewOnesAreLabelled) {
  MapDiff diff;
  ObjectRecord cup = Record(1, 41, {-1, 0, 0.2});
  cup.state = 2;
  diff.unchanged.push_back({cup, cup, 0.0});
  diff.added.push_back(Record(10, 64, {1, 0, 0.2}));
  const DiffScenes scenes = MakeDiffScenes(diff, MapScene{});
  EXPECT_EQ(MapLegend(scenes.after),
            (std::vector<std::string>{"recently observed", "not judged yet"}));
  Renderer renderer(480, 360);
  const ViewerOptions options = SmallSnapshots();
  const cv::Mat after = RenderMapView(renderer, scenes.after, options, MapViewpoint::kTopDown);
  const cv::Vec3b top =
      PixelAt(after, MapViewCamera(scenes.after, options, MapViewpoint::kTopDown), {-1, 0, 0.4});
  EXPECT_GT(top[0], top[2] + 60);  // blue
  const std::vector<PlacedLabel> labels =
      MapViewLabels(scenes.after, options, MapViewpoint::kTopDown);
  ASSERT_EQ(labels.size(), 2u);
  EXPECT_EQ(labels[1].text, "10 mouse (added)");
}

// Issue 32, point 9: the object map as a mesh, written and parsed back.
struct ParsedMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<cv::Vec3i> colours;
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::string> materials;  // OBJ: per triangle
};

ParsedMesh ParsePly(const std::string& path) {
  ParsedMesh mesh;
  std::ifstream file(path);
  std::string line;
  std::size_t vertices = 0, faces = 0;
  while (std::getline(file, line) && line != "end_header") {
    std::istringstream words(line);
    std::string word, element;
    words >> word;
    if (word == "element") {
      std::size_t count = 0;
      words >> element >> count;
      (element == "vertex" ? vertices : faces) = count;
    }
  }
  for (std::size_t i = 0; i < vertices; ++i) {
    Eigen::Vector3d p;
    cv::Vec3i c;
    file >> p.x() >> p.y() >> p.z() >> c[0] >> c[1] >> c[2];
    mesh.vertices.push_back(p);
    mesh.colours.push_back(c);
  }
  for (std::size_t i = 0; i < faces; ++i) {
    int count = 0;
    std::array<int, 3> t{};
    file >> count >> t[0] >> t[1] >> t[2];
    EXPECT_EQ(count, 3);
    mesh.triangles.push_back(t);
  }
  EXPECT_TRUE(file.good()) << path;
  return mesh;
}

ParsedMesh ParseObj(const std::string& path, std::map<std::string, Eigen::Vector3d>* kd) {
  ParsedMesh mesh;
  std::ifstream file(path);
  std::string line, material, library;
  while (std::getline(file, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "mtllib") words >> library;
    if (key == "usemtl") words >> material;
    if (key == "v") {
      Eigen::Vector3d p, c;
      words >> p.x() >> p.y() >> p.z() >> c.x() >> c.y() >> c.z();
      mesh.vertices.push_back(p);
      mesh.colours.emplace_back(static_cast<int>(std::lround(255 * c.x())),
                                static_cast<int>(std::lround(255 * c.y())),
                                static_cast<int>(std::lround(255 * c.z())));
    }
    if (key == "f") {
      std::array<int, 3> t{};
      words >> t[0] >> t[1] >> t[2];
      for (int& index : t) --index;  // OBJ counts from 1
      mesh.triangles.push_back(t);
      mesh.materials.push_back(material);
    }
  }
  std::ifstream mtl(std::filesystem::path(path).parent_path() / library);
  EXPECT_TRUE(mtl.good()) << library;
  std::string name;
  while (std::getline(mtl, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "newmtl") words >> name;
    if (key == "Kd") words >> (*kd)[name].x() >> (*kd)[name].y() >> (*kd)[name].z();
  }
  return mesh;
}

// Every object's 8 vertices and 12 triangles form a closed surface (each edge in two
// triangles, once in each direction) whose triangles face away from the object's centre.
void ExpectClosedAndOutward(const ParsedMesh& mesh, const std::vector<ObjectView>& live) {
  ASSERT_EQ(mesh.vertices.size(), 8 * live.size());
  ASSERT_EQ(mesh.triangles.size(), 12 * live.size());
  std::map<std::pair<int, int>, int> edges;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const std::array<int, 3>& triangle = mesh.triangles[t];
    const std::size_t object = t / 12;
    for (int k = 0; k < 3; ++k) {
      ASSERT_EQ(static_cast<std::size_t>(triangle[k]) / 8, object);  // its own box's corners
      ++edges[{triangle[k], triangle[(k + 1) % 3]}];
    }
    const Eigen::Vector3d a = mesh.vertices[triangle[0]], b = mesh.vertices[triangle[1]],
                          c = mesh.vertices[triangle[2]];
    const Eigen::Vector3d normal = (b - a).cross(c - a);
    EXPECT_GT(normal.norm(), 1e-6) << t;
    EXPECT_GT(normal.dot((a + b + c) / 3 - live[object].cuboid.centre), 0) << "triangle " << t;
  }
  for (const auto& [edge, count] : edges) {
    EXPECT_EQ(count, 1);
    const auto reverse = edges.find({edge.second, edge.first});
    EXPECT_TRUE(reverse != edges.end() && reverse->second == 1);
  }
}

TEST(ObjectMesh, PlyAndObjLoadBackClosedFacingOutwardsInTheStateColours) {
  // Turned about a tilted up, one removed (left out), a flat one (a book).
  std::vector<ObjectView> objects = {Object(1, {-1, 0, 0.2}, 1), Object(2, {1, 0, 0.2}, 4),
                                     Object(3, {0, 1, 0.2}, 0, true), Object(4, {0, -1, 0.1}, 2)};
  objects[0].cuboid.yaw = 0.7;
  objects[3].cuboid.size = Eigen::Vector3d(0.3, 0.2, 0.0);
  const Eigen::Vector3d up = Eigen::Vector3d(0.1, -0.2, 1).normalized();
  const ObjectMesh mesh = MakeObjectMesh(objects, up);
  const std::vector<ObjectView> live = {objects[0], objects[1], objects[3]};
  ASSERT_EQ(mesh.objects.size(), 3u);
  const std::string folder = testing::MakeTempDir("ocg_object_mesh");
  WriteObjectMesh(folder + "/objects.ply", mesh);
  WriteObjectMesh(folder + "/objects.obj", mesh);
  EXPECT_THROW(WriteObjectMesh(folder + "/objects.stl", mesh), std::invalid_argument);

  std::map<std::string, Eigen::Vector3d> kd;
  for (const ParsedMesh& parsed :
       {ParsePly(folder + "/objects.ply"), ParseObj(folder + "/objects.obj", &kd)}) {
    ExpectClosedAndOutward(parsed, live);
    for (std::size_t v = 0; v < parsed.vertices.size(); ++v) {
      const ObjectView& object = live[v / 8];
      const Eigen::Vector3f rgb = 255.0f * StateColour(object.state, false);
      EXPECT_NEAR(parsed.colours[v][0], rgb.x(), 1.0) << v;
      EXPECT_NEAR(parsed.colours[v][1], rgb.y(), 1.0) << v;
      EXPECT_NEAR(parsed.colours[v][2], rgb.z(), 1.0) << v;
      // A corner: half the size from the centre along each of the box's axes.
      EXPECT_NEAR((parsed.vertices[v] - object.cuboid.centre).norm(),
                  0.5 * object.cuboid.size.cwiseMax(1e-3).norm(), 1e-5);
    }
  }
  const ParsedMesh obj = ParseObj(folder + "/objects.obj", &kd);
  EXPECT_EQ(obj.materials[0], "observed");
  EXPECT_EQ(obj.materials[12], "suspicious");
  EXPECT_EQ(obj.materials[24], "recently_observed");
  EXPECT_NEAR(kd["suspicious"].x(), StateColour(4, false).x(), 1e-6);
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace ocg
