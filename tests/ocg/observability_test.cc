#include <gtest/gtest.h>

#include "ocg/ocg/observability.h"
#include "ocg_test_scene.h"

namespace ocg {
namespace {

using testing::LookAt;
using testing::TestCamera;

TEST(CentroidInImage, FrontInsideBehindOutside) {
  const SE3 T_cw = LookAt({0, 0, 0}, {1, 0, 0});  // looking along +x
  const PinholeCamera camera = TestCamera();
  EXPECT_TRUE(CentroidInImage({3, 0, 0}, T_cw, camera));
  EXPECT_FALSE(CentroidInImage({-3, 0, 0}, T_cw, camera));  // behind
  EXPECT_FALSE(CentroidInImage({1, 5, 0}, T_cw, camera));   // far to the side
  // 0.62 m to the side at 1 m depth: pixel 320 + 310 = 630, inside; with a 20 px margin, not.
  EXPECT_TRUE(CentroidInImage({1, -0.62, 0}, T_cw, camera));
  EXPECT_FALSE(CentroidInImage({1, -0.62, 0}, T_cw, camera, 20.0));
}

TEST(CentroidInImage, RejectsPointsThatDistortionFoldsBackIntoTheImage) {
  PinholeCamera camera = TestCamera();
  camera.k1 = -0.5;
  const SE3 identity;
  // x/z = 1.2 (ideal pixel x = 920, outside): r^2 = 1.44, radial factor 0.28, so the
  // distorted pixel lands at x = 488, inside the image.
  ASSERT_TRUE(camera.IsInImage(camera.Project({1.2, 0, 1})));
  EXPECT_FALSE(CentroidInImage({1.2, 0, 1}, identity, camera));
  EXPECT_TRUE(CentroidInImage({0.2, 0.1, 1}, identity, camera));
}

TEST(BoxFraction, InsideAtTheEdgeAndBehind) {
  const SE3 T_cw = LookAt({0, 0, 0}, {1, 0, 0});
  const PinholeCamera camera = TestCamera();
  const Eigen::Vector3d size(0.2, 0.2, 0.2);
  EXPECT_DOUBLE_EQ(BoxFractionInImage({3, 0, 0}, size, T_cw, camera), 1.0);
  EXPECT_DOUBLE_EQ(BoxFractionInImage({-3, 0, 0}, size, T_cw, camera), 0.0);
  // Centred on the right image border (pixel x = 640 at y_world = -0.64 m for depth 1).
  const double fraction =
      BoxFractionInImage({1, -0.64, 0}, Eigen::Vector3d(0.01, 0.2, 0.2), T_cw, camera);
  EXPECT_NEAR(fraction, 0.5, 0.05);
}

TEST(Distance, FromCameraCentre) {
  const SE3 T_cw = LookAt({1, 2, 3}, {0, 0, 0});
  EXPECT_NEAR(DistanceFromCamera({1, 2, 0}, T_cw), 3.0, 1e-12);
}

}  // namespace
}  // namespace ocg
