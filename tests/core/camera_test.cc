#include <gtest/gtest.h>

#include "ocg/core/camera.h"
#include "ocg/core/options.h"

namespace ocg {
namespace {

PinholeCamera Tum1() {
  PinholeCamera camera;
  camera.fx = 517.306408;
  camera.fy = 516.469215;
  camera.cx = 318.643040;
  camera.cy = 255.313989;
  camera.k1 = 0.262383;
  camera.k2 = -0.953104;
  camera.p1 = -0.005358;
  camera.p2 = 0.002628;
  camera.k3 = 1.163314;
  return camera;
}

TEST(Camera, ProjectWithoutDistortion) {
  PinholeCamera camera;
  camera.fx = 500;
  camera.fy = 400;
  camera.cx = 320;
  camera.cy = 240;
  const Eigen::Vector2d pixel = camera.Project({0.2, -0.1, 2.0});
  EXPECT_DOUBLE_EQ(pixel.x(), 320 + 500 * 0.1);
  EXPECT_DOUBLE_EQ(pixel.y(), 240 - 400 * 0.05);
  EXPECT_FALSE(camera.HasDistortion());
}

TEST(Camera, UnprojectInvertsProjectWithDistortion) {
  const PinholeCamera camera = Tum1();
  for (double x = -0.5; x <= 0.5; x += 0.1) {
    for (double y = -0.4; y <= 0.4; y += 0.1) {
      const Eigen::Vector3d bearing = camera.Unproject(camera.Project({x, y, 1.0}));
      EXPECT_NEAR(bearing.x(), x, 1e-9);
      EXPECT_NEAR(bearing.y(), y, 1e-9);
    }
  }
}

TEST(Camera, DistortionMovesPixelsAndUndistortRestoresIdealProjection) {
  const PinholeCamera camera = Tum1();
  const Eigen::Vector3d point(0.3, 0.2, 1.0);
  const Eigen::Vector2d distorted = camera.Project(point);
  const Eigen::Vector2d ideal = camera.ProjectUndistorted(point);
  EXPECT_GT((distorted - ideal).norm(), 1.0);
  EXPECT_LT((camera.UndistortPixel(distorted) - ideal).norm(), 1e-6);
  const auto batch = camera.UndistortPixels({distorted, distorted});
  ASSERT_EQ(batch.size(), 2u);
  EXPECT_LT((batch[1] - ideal).norm(), 1e-6);
}

TEST(Camera, IsInImageHonoursMargin) {
  PinholeCamera camera = Tum1();
  EXPECT_TRUE(camera.IsInImage({0, 0}));
  EXPECT_FALSE(camera.IsInImage({0, 0}, 5));
  EXPECT_FALSE(camera.IsInImage({640, 10}));
  EXPECT_TRUE(camera.IsInImage({639.5, 479.5}));
}

TEST(Camera, CheckNamesTheKey) {
  PinholeCamera camera = Tum1();
  camera.fy = -1;
  try {
    camera.Check();
    FAIL() << "negative focal length accepted";
  } catch (const OptionError& error) {
    EXPECT_EQ(error.key(), "Camera.fy");
  }
}

}  // namespace
}  // namespace ocg
