#pragma once
// Off-screen rendering with OSMesa (software OpenGL, no window, no display): textured,
// shaded meshes seen through a pinhole camera, and an id pass that tells which mesh owns
// each pixel. Used by the synthetic sequence generator and the map viewer.
//
// Threading: a Renderer owns an OSMesa context, which is current on one thread at a
// time. Create and use each Renderer on one thread.

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "ocg/core/camera.h"
#include "ocg/core/lie.h"

namespace ocg {

struct MeshVertex {
  Eigen::Vector3f position;  // world frame once placed
  Eigen::Vector3f normal;
  Eigen::Vector2f uv;  // texture coordinates (repeat beyond [0, 1])
};

struct Mesh {
  std::vector<MeshVertex> vertices;
  std::vector<std::uint32_t> triangles;  // three indices each

  // Box centred at the origin with the given full extents; uv in metres times uv_scale.
  static Mesh Box(const Eigen::Vector3f& size, float uv_scale = 1.0f);
  // Box with its faces facing inwards (a room seen from inside).
  static Mesh InwardBox(const Eigen::Vector3f& size, float uv_scale = 1.0f);
  // Upright cylinder centred at the origin (axis z), with caps.
  static Mesh Cylinder(float radius, float height, int segments = 32, float uv_scale = 1.0f);
  // The mesh moved by T_world_object.
  Mesh Transformed(const SE3& T_world_object) const;
};

// A mesh placed in the world, ready to draw.
struct DrawItem {
  Mesh mesh;         // world coordinates
  int texture = -1;  // from Renderer::AddTexture, -1 for plain colour
  Eigen::Vector3f colour = Eigen::Vector3f(0.8f, 0.8f, 0.8f);  // multiplies the texture
  std::uint32_t id = 0;                // written by the id pass; 0 is the background
  std::vector<Eigen::Vector3f> shade;  // per-vertex light, filled by Renderer::Shade
};

// Lines and points, drawn after the meshes and depth-tested against them (the map
// viewer's points, frustums, trajectories and cuboid edges).
struct LineBatch {
  std::vector<Eigen::Vector3f> segments;  // world points, two per segment
  Eigen::Vector3f colour = Eigen::Vector3f::Zero();
  float width = 1.0f;  // pixels
  bool dashed = false;
};
struct PointBatch {
  std::vector<Eigen::Vector3f> positions;  // world
  Eigen::Vector3f colour = Eigen::Vector3f::Zero();
  float size = 2.0f;  // pixels
};
struct Overlay {
  std::vector<LineBatch> lines;
  std::vector<PointBatch> points;
};

class Renderer {
 public:
  // Throws std::runtime_error when no OSMesa context can be created.
  Renderer(int width, int height);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }

  // Uploads a BGR (CV_8UC3) image as a repeating, mip-mapped texture; returns its handle.
  int AddTexture(const cv::Mat& bgr);
  // Lambert shading from a directional light plus ambient, baked per vertex (the light
  // is fixed in the world, so it does not depend on the camera).
  static void Shade(DrawItem& item, const Eigen::Vector3f& light_direction, float ambient);

  // Colour image (CV_8UC3, BGR, top row first) of the items through the camera.
  // Distortion of the camera model is ignored (rendered images are ideal pinhole).
  cv::Mat RenderColour(const std::vector<const DrawItem*>& items, const SE3& T_cw,
                       const PinholeCamera& camera, const Eigen::Vector3f& background);
  // The same with lines and points over the meshes (faces are pushed back a little so
  // that edges drawn on them stay visible).
  cv::Mat RenderColour(const std::vector<const DrawItem*>& items, const Overlay& overlay,
                       const SE3& T_cw, const PinholeCamera& camera,
                       const Eigen::Vector3f& background);
  // Id image (CV_32SC1): the id of the item visible at each pixel, 0 where none.
  // With depth, also fills a CV_32FC1 image of metric depth (0 where nothing).
  cv::Mat RenderIds(const std::vector<const DrawItem*>& items, const SE3& T_cw,
                    const PinholeCamera& camera, cv::Mat* depth = nullptr);

  // OpenGL projection matrix of a pinhole camera (column-major layout as GL wants).
  // Pixel (0, 0) is the centre of the top-left pixel, as in OpenCV.
  static Eigen::Matrix4f ProjectionMatrix(const PinholeCamera& camera, float near_plane,
                                          float far_plane);

  static constexpr float kNear = 0.05f;
  static constexpr float kFar = 100.0f;

 private:
  void SetCamera(const SE3& T_cw, const PinholeCamera& camera);
  void Draw(const DrawItem& item, bool id_pass);
  void DrawOverlay(const Overlay& overlay);
  cv::Mat ReadColour();

  struct Context;
  std::unique_ptr<Context> context_;
  int width_;
  int height_;
  std::vector<unsigned> textures_;
};

}  // namespace ocg
