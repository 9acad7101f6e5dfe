#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "ocg/render/renderer.h"

namespace ocg {
namespace {

PinholeCamera Camera() {
  PinholeCamera camera;
  camera.fx = 535.4;
  camera.fy = 539.2;
  camera.cx = 320.1;
  camera.cy = 247.6;
  return camera;
}

cv::Rect IdBox(const cv::Mat& ids, std::int32_t id) {
  cv::Mat mask = ids == id;
  return cv::boundingRect(mask);
}

TEST(Renderer, IdPassBoxEqualsTheProjectedBox) {
  Renderer renderer(640, 480);
  const PinholeCamera camera = Camera();
  DrawItem box;
  box.mesh =
      Mesh::Box({0.3f, 0.2f, 0.4f}).Transformed(SE3(Eigen::Matrix3d::Identity(), {0.1, -0.2, 0.2}));
  box.id = 7;
  const SE3 T_cw = LookAt({-1.5, 0.4, 0.9}, {0, 0, 0});
  const cv::Mat ids = renderer.RenderIds({&box}, T_cw, camera);
  const cv::Rect rendered = IdBox(ids, 7);
  double min_u = 1e9, min_v = 1e9, max_u = -1e9, max_v = -1e9;
  for (const MeshVertex& vertex : box.mesh.vertices) {
    const Eigen::Vector2d pixel = camera.Project(T_cw * vertex.position.cast<double>());
    min_u = std::min(min_u, pixel.x());
    max_u = std::max(max_u, pixel.x());
    min_v = std::min(min_v, pixel.y());
    max_v = std::max(max_v, pixel.y());
  }
  // Rendered pixels are those whose centre lies inside the projection: never outside the
  // exact box, and inside it by less than 1.5 px (a sharp corner's sliver may hold no
  // pixel centre).
  EXPECT_GE(rendered.x, min_u);
  EXPECT_GE(rendered.y, min_v);
  EXPECT_LE(rendered.x + rendered.width - 1, max_u);
  EXPECT_LE(rendered.y + rendered.height - 1, max_v);
  EXPECT_NEAR(rendered.x, min_u, 1.5);
  EXPECT_NEAR(rendered.y, min_v, 1.5);
  EXPECT_NEAR(rendered.x + rendered.width - 1, max_u, 1.5);
  EXPECT_NEAR(rendered.y + rendered.height - 1, max_v, 1.5);
  EXPECT_EQ(ids.at<std::int32_t>(0, 0), 0);  // background
}

TEST(Renderer, DepthAndOcclusion) {
  Renderer renderer(320, 240);
  PinholeCamera camera = Camera();
  camera.width = 320;
  camera.height = 240;
  camera.cx = 160;
  camera.cy = 120;
  DrawItem near_box, far_box;
  near_box.mesh =
      Mesh::Box({0.2f, 0.2f, 0.2f}).Transformed(SE3(Eigen::Matrix3d::Identity(), {0, 0, 2}));
  near_box.id = 1;
  far_box.mesh =
      Mesh::Box({1.0f, 1.0f, 0.2f}).Transformed(SE3(Eigen::Matrix3d::Identity(), {0, 0, 4}));
  far_box.id = 2;
  cv::Mat depth;
  const cv::Mat ids = renderer.RenderIds({&far_box, &near_box}, SE3(), camera, &depth);
  EXPECT_EQ(ids.at<std::int32_t>(120, 160), 1);  // the near box hides the far one
  EXPECT_NEAR(depth.at<float>(120, 160), 1.9f, 1e-3);
  EXPECT_EQ(ids.at<std::int32_t>(120, 160 + 60), 2);
  EXPECT_NEAR(depth.at<float>(120, 160 + 60), 3.9f, 1e-3);
  EXPECT_EQ(depth.at<float>(0, 0), 0.0f);
}

TEST(Renderer, ColourShadingAndTexture) {
  Renderer renderer(160, 120);
  PinholeCamera camera = Camera();
  camera.width = 160;
  camera.height = 120;
  camera.cx = 80;
  camera.cy = 60;
  cv::Mat texture(64, 64, CV_8UC3, cv::Scalar(0, 0, 255));       // red
  texture(cv::Rect(0, 0, 32, 64)).setTo(cv::Scalar(255, 0, 0));  // left half blue
  DrawItem wall;
  wall.mesh =
      Mesh::Box({2.0f, 2.0f, 0.01f}, 0.5f).Transformed(SE3(Eigen::Matrix3d::Identity(), {0, 0, 1}));
  wall.texture = renderer.AddTexture(texture);
  wall.colour = Eigen::Vector3f(1, 1, 1);
  Renderer::Shade(wall, Eigen::Vector3f(0, 0, 1),
                  0.3f);  // light along +z: lights the face at z < 1
  const cv::Mat image = renderer.RenderColour({&wall}, SE3(), camera, Eigen::Vector3f(0, 1, 0));
  const cv::Vec3b centre = image.at<cv::Vec3b>(60, 80);
  EXPECT_GT(centre[0] + centre[2], 200);  // textured red or blue, lit
  EXPECT_LT(centre[1], 30);
  Renderer::Shade(wall, Eigen::Vector3f(0, 0, -1), 0.3f);  // now the camera sees the dark side
  const cv::Vec3b dark =
      renderer.RenderColour({&wall}, SE3(), camera, Eigen::Vector3f(0, 1, 0)).at<cv::Vec3b>(60, 80);
  EXPECT_LT(dark[0] + dark[2], centre[0] + centre[2]);
  const cv::Mat empty = renderer.RenderColour({}, SE3(), camera, Eigen::Vector3f(0, 1, 0));
  EXPECT_EQ(empty.at<cv::Vec3b>(5, 5), cv::Vec3b(0, 255, 0));
}

TEST(Renderer, ManyRenderersCanBeCreatedAndDestroyed) {
  for (int i = 0; i < 50; ++i) {
    Renderer renderer(64, 48);
    EXPECT_EQ(renderer.RenderIds({}, SE3(), Camera()).at<std::int32_t>(0, 0), 0);
  }
}

}  // namespace
}  // namespace ocg
