#include "ocg/render/renderer.h"

#include <GL/gl.h>
#include <GL/osmesa.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace ocg {
namespace {

void AddQuad(Mesh& mesh, const Eigen::Vector3f corners[4], const Eigen::Vector3f& normal,
             const Eigen::Vector2f uvs[4]) {
  const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
  for (int i = 0; i < 4; ++i) mesh.vertices.push_back({corners[i], normal, uvs[i]});
  for (std::uint32_t index : {0u, 1u, 2u, 0u, 2u, 3u}) mesh.triangles.push_back(base + index);
}

Mesh MakeBox(const Eigen::Vector3f& size, float uv_scale, float normal_sign) {
  Mesh mesh;
  const Eigen::Vector3f half = 0.5f * size;
  for (int axis = 0; axis < 3; ++axis) {
    const int u_axis = (axis + 1) % 3;
    const int v_axis = (axis + 2) % 3;
    for (float side : {-1.0f, 1.0f}) {
      Eigen::Vector3f normal = Eigen::Vector3f::Zero();
      normal[axis] = side * normal_sign;
      Eigen::Vector3f corners[4];
      Eigen::Vector2f uvs[4];
      const float us[4] = {-1, 1, 1, -1};
      const float vs[4] = {-1, -1, 1, 1};
      for (int i = 0; i < 4; ++i) {
        corners[i][axis] = side * half[axis];
        corners[i][u_axis] = us[i] * half[u_axis];
        corners[i][v_axis] = vs[i] * half[v_axis];
        // Each face gets its own offset in texture space, so faces do not repeat.
        uvs[i] = Eigen::Vector2f(
            (corners[i][u_axis] + half[u_axis]) * uv_scale + 0.37f * (2 * axis + (side > 0)),
            (corners[i][v_axis] + half[v_axis]) * uv_scale + 0.21f * axis);
      }
      AddQuad(mesh, corners, normal, uvs);
    }
  }
  return mesh;
}

std::uint32_t DecodeId(const unsigned char* rgba) {
  return static_cast<std::uint32_t>(rgba[0]) | (static_cast<std::uint32_t>(rgba[1]) << 8) |
         (static_cast<std::uint32_t>(rgba[2]) << 16);
}

}  // namespace

Mesh Mesh::Box(const Eigen::Vector3f& size, float uv_scale) {
  return MakeBox(size, uv_scale, 1.0f);
}

Mesh Mesh::InwardBox(const Eigen::Vector3f& size, float uv_scale) {
  return MakeBox(size, uv_scale, -1.0f);
}

Mesh Mesh::Cylinder(float radius, float height, int segments, float uv_scale) {
  Mesh mesh;
  const float half = 0.5f * height;
  const float circumference = 2.0f * static_cast<float>(M_PI) * radius;
  for (int i = 0; i <= segments; ++i) {
    const float angle = 2.0f * static_cast<float>(M_PI) * static_cast<float>(i) / segments;
    const Eigen::Vector3f normal(std::cos(angle), std::sin(angle), 0.0f);
    const float u = circumference * static_cast<float>(i) / segments * uv_scale;
    mesh.vertices.push_back({radius * normal + Eigen::Vector3f(0, 0, -half), normal, {u, 0.0f}});
    mesh.vertices.push_back(
        {radius * normal + Eigen::Vector3f(0, 0, half), normal, {u, height * uv_scale}});
  }
  for (int i = 0; i < segments; ++i) {
    const auto a = static_cast<std::uint32_t>(2 * i);
    for (std::uint32_t index : {a, a + 2, a + 3, a, a + 3, a + 1}) mesh.triangles.push_back(index);
  }
  for (float side : {-1.0f, 1.0f}) {
    const auto centre = static_cast<std::uint32_t>(mesh.vertices.size());
    const Eigen::Vector3f normal(0, 0, side);
    mesh.vertices.push_back({Eigen::Vector3f(0, 0, side * half), normal, {0.5f, 0.5f}});
    for (int i = 0; i <= segments; ++i) {
      const float angle = 2.0f * static_cast<float>(M_PI) * static_cast<float>(i) / segments;
      const Eigen::Vector2f rim(std::cos(angle), std::sin(angle));
      mesh.vertices.push_back({Eigen::Vector3f(radius * rim.x(), radius * rim.y(), side * half),
                               normal, Eigen::Vector2f(0.5f, 0.5f) + radius * uv_scale * rim});
    }
    for (int i = 0; i < segments; ++i) {
      const auto rim = centre + 1 + static_cast<std::uint32_t>(i);
      for (std::uint32_t index : {centre, rim, rim + 1}) mesh.triangles.push_back(index);
    }
  }
  return mesh;
}

Mesh Mesh::Transformed(const SE3& T_world_object) const {
  Mesh moved = *this;
  const Eigen::Matrix3f rotation = T_world_object.rotation().cast<float>();
  const Eigen::Vector3f translation = T_world_object.translation().cast<float>();
  for (MeshVertex& vertex : moved.vertices) {
    vertex.position = rotation * vertex.position + translation;
    vertex.normal = rotation * vertex.normal;
  }
  return moved;
}

struct Renderer::Context {
  OSMesaContext handle = nullptr;
  std::vector<unsigned char> buffer;  // RGBA, top row first
};

Renderer::Renderer(int width, int height)
    : context_(std::make_unique<Context>()), width_(width), height_(height) {
  const int attributes[] = {OSMESA_FORMAT,
                            OSMESA_RGBA,
                            OSMESA_DEPTH_BITS,
                            24,
                            OSMESA_STENCIL_BITS,
                            0,
                            OSMESA_PROFILE,
                            OSMESA_COMPAT_PROFILE,
                            0};
  context_->handle = OSMesaCreateContextAttribs(attributes, nullptr);
  if (context_->handle == nullptr) throw std::runtime_error("OSMesa: cannot create a GL context");
  context_->buffer.resize(static_cast<size_t>(width) * static_cast<size_t>(height) * 4);
  if (!OSMesaMakeCurrent(context_->handle, context_->buffer.data(), GL_UNSIGNED_BYTE, width,
                         height)) {
    OSMesaDestroyContext(context_->handle);
    throw std::runtime_error("OSMesa: cannot make the context current");
  }
  OSMesaPixelStore(OSMESA_Y_UP, 0);  // row 0 of the buffer is the top of the image
  glDisable(GL_DITHER);
  glDisable(GL_CULL_FACE);
  glDisable(GL_LIGHTING);
  glEnable(GL_DEPTH_TEST);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
}

Renderer::~Renderer() {
  if (context_ && context_->handle != nullptr) {
    OSMesaMakeCurrent(context_->handle, context_->buffer.data(), GL_UNSIGNED_BYTE, width_, height_);
    if (!textures_.empty())
      glDeleteTextures(static_cast<GLsizei>(textures_.size()), textures_.data());
    OSMesaDestroyContext(context_->handle);
  }
}

int Renderer::AddTexture(const cv::Mat& bgr) {
  CV_Assert(bgr.type() == CV_8UC3);
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  GLuint texture = 0;
  glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
  // Bilinear within the nearest mip level: half the texture reads of trilinear filtering
  // in software rendering, with no visible difference at these texel densities.
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_GENERATE_MIPMAP, GL_TRUE);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB, rgb.cols, rgb.rows, 0, GL_RGB, GL_UNSIGNED_BYTE, rgb.data);
  textures_.push_back(texture);
  return static_cast<int>(textures_.size()) - 1;
}

void Renderer::Shade(DrawItem& item, const Eigen::Vector3f& light_direction, float ambient) {
  const Eigen::Vector3f towards_light = -light_direction.normalized();
  item.shade.clear();
  item.shade.reserve(item.mesh.vertices.size());
  for (const MeshVertex& vertex : item.mesh.vertices) {
    const float diffuse = std::max(0.0f, vertex.normal.normalized().dot(towards_light));
    const float light = std::min(1.0f, ambient + (1.0f - ambient) * diffuse);
    item.shade.push_back(light * item.colour);
  }
}

Eigen::Matrix4f Renderer::ProjectionMatrix(const PinholeCamera& camera, float near_plane,
                                           float far_plane) {
  // Eye coordinates are camera coordinates with y and z negated (OpenGL looks down -z,
  // y up); the half-pixel terms put pixel centres at integer coordinates.
  const float w = static_cast<float>(camera.width);
  const float h = static_cast<float>(camera.height);
  Eigen::Matrix4f projection = Eigen::Matrix4f::Zero();
  projection(0, 0) = 2.0f * static_cast<float>(camera.fx) / w;
  projection(0, 2) = 1.0f - 2.0f * (static_cast<float>(camera.cx) + 0.5f) / w;
  projection(1, 1) = 2.0f * static_cast<float>(camera.fy) / h;
  projection(1, 2) = 2.0f * (static_cast<float>(camera.cy) + 0.5f) / h - 1.0f;
  projection(2, 2) = -(far_plane + near_plane) / (far_plane - near_plane);
  projection(2, 3) = -2.0f * far_plane * near_plane / (far_plane - near_plane);
  projection(3, 2) = -1.0f;
  return projection;
}

void Renderer::SetCamera(const SE3& T_cw, const PinholeCamera& camera) {
  OSMesaMakeCurrent(context_->handle, context_->buffer.data(), GL_UNSIGNED_BYTE, width_, height_);
  glViewport(0, 0, width_, height_);
  const Eigen::Matrix4f projection = ProjectionMatrix(camera, kNear, kFar);
  glMatrixMode(GL_PROJECTION);
  glLoadMatrixf(projection.data());
  Eigen::Matrix4f eye_from_camera = Eigen::Matrix4f::Identity();
  eye_from_camera(1, 1) = -1.0f;
  eye_from_camera(2, 2) = -1.0f;
  const Eigen::Matrix4f model_view = eye_from_camera * T_cw.Matrix().cast<float>();
  glMatrixMode(GL_MODELVIEW);
  glLoadMatrixf(model_view.data());
}

void Renderer::Draw(const DrawItem& item, bool id_pass) {
  const std::vector<MeshVertex>& vertices = item.mesh.vertices;
  if (vertices.empty()) return;
  const GLsizei stride = sizeof(MeshVertex);
  glEnableClientState(GL_VERTEX_ARRAY);
  glVertexPointer(3, GL_FLOAT, stride, vertices[0].position.data());
  const bool textured = !id_pass && item.texture >= 0;
  if (textured) {
    glEnable(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, textures_.at(static_cast<size_t>(item.texture)));
    glEnableClientState(GL_TEXTURE_COORD_ARRAY);
    glTexCoordPointer(2, GL_FLOAT, stride, vertices[0].uv.data());
  } else {
    glDisable(GL_TEXTURE_2D);
    glDisableClientState(GL_TEXTURE_COORD_ARRAY);
  }
  if (id_pass) {
    glDisableClientState(GL_COLOR_ARRAY);
    glColor3ub(static_cast<GLubyte>(item.id & 0xff), static_cast<GLubyte>((item.id >> 8) & 0xff),
               static_cast<GLubyte>((item.id >> 16) & 0xff));
  } else if (item.shade.size() == vertices.size()) {
    glEnableClientState(GL_COLOR_ARRAY);
    glColorPointer(3, GL_FLOAT, sizeof(Eigen::Vector3f), item.shade[0].data());
  } else {
    glDisableClientState(GL_COLOR_ARRAY);
    glColor3f(item.colour.x(), item.colour.y(), item.colour.z());
  }
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(item.mesh.triangles.size()), GL_UNSIGNED_INT,
                 item.mesh.triangles.data());
  glDisableClientState(GL_COLOR_ARRAY);
  glDisableClientState(GL_TEXTURE_COORD_ARRAY);
  glDisableClientState(GL_VERTEX_ARRAY);
}

void Renderer::DrawOverlay(const Overlay& overlay) {
  glDisable(GL_TEXTURE_2D);
  glDisableClientState(GL_COLOR_ARRAY);
  glDisableClientState(GL_TEXTURE_COORD_ARRAY);
  glEnableClientState(GL_VERTEX_ARRAY);
  for (const LineBatch& batch : overlay.lines) {
    if (batch.segments.size() < 2) continue;
    glLineWidth(batch.width);
    if (batch.dashed) {
      glEnable(GL_LINE_STIPPLE);
      glLineStipple(3, 0x00FF);
    }
    glColor3f(batch.colour.x(), batch.colour.y(), batch.colour.z());
    glVertexPointer(3, GL_FLOAT, sizeof(Eigen::Vector3f), batch.segments[0].data());
    glDrawArrays(GL_LINES, 0, static_cast<GLsizei>(batch.segments.size() / 2 * 2));
    glDisable(GL_LINE_STIPPLE);
  }
  for (const PointBatch& batch : overlay.points) {
    if (batch.positions.empty()) continue;
    glPointSize(batch.size);
    glColor3f(batch.colour.x(), batch.colour.y(), batch.colour.z());
    glVertexPointer(3, GL_FLOAT, sizeof(Eigen::Vector3f), batch.positions[0].data());
    glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(batch.positions.size()));
  }
  glDisableClientState(GL_VERTEX_ARRAY);
  glLineWidth(1.0f);
  glPointSize(1.0f);
}

cv::Mat Renderer::ReadColour() {
  glFinish();
  const cv::Mat rgba(height_, width_, CV_8UC4, context_->buffer.data());
  cv::Mat bgr;
  cv::cvtColor(rgba, bgr, cv::COLOR_RGBA2BGR);
  return bgr;
}

cv::Mat Renderer::RenderColour(const std::vector<const DrawItem*>& items, const SE3& T_cw,
                               const PinholeCamera& camera, const Eigen::Vector3f& background) {
  SetCamera(T_cw, camera);
  glClearColor(background.x(), background.y(), background.z(), 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  for (const DrawItem* item : items) Draw(*item, false);
  return ReadColour();
}

cv::Mat Renderer::RenderColour(const std::vector<const DrawItem*>& items, const Overlay& overlay,
                               const SE3& T_cw, const PinholeCamera& camera,
                               const Eigen::Vector3f& background) {
  SetCamera(T_cw, camera);
  glClearColor(background.x(), background.y(), background.z(), 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.0f, 1.0f);
  for (const DrawItem* item : items) Draw(*item, false);
  glDisable(GL_POLYGON_OFFSET_FILL);
  DrawOverlay(overlay);
  return ReadColour();
}

cv::Mat Renderer::RenderIds(const std::vector<const DrawItem*>& items, const SE3& T_cw,
                            const PinholeCamera& camera, cv::Mat* depth) {
  SetCamera(T_cw, camera);
  glClearColor(0, 0, 0, 1);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  for (const DrawItem* item : items) Draw(*item, true);
  glFinish();
  cv::Mat ids(height_, width_, CV_32SC1);
  const unsigned char* pixel = context_->buffer.data();
  for (int row = 0; row < height_; ++row) {
    auto* out = ids.ptr<std::int32_t>(row);
    for (int column = 0; column < width_; ++column, pixel += 4) {
      out[column] = static_cast<std::int32_t>(DecodeId(pixel));
    }
  }
  if (depth != nullptr) {
    cv::Mat window_depth(height_, width_, CV_32FC1);
    glReadPixels(0, 0, width_, height_, GL_DEPTH_COMPONENT, GL_FLOAT, window_depth.data);
    cv::flip(window_depth, window_depth, 0);  // glReadPixels is bottom-up
    depth->create(height_, width_, CV_32FC1);
    for (int row = 0; row < height_; ++row) {
      const float* in = window_depth.ptr<float>(row);
      float* out = depth->ptr<float>(row);
      for (int column = 0; column < width_; ++column) {
        const float ndc = 2.0f * in[column] - 1.0f;
        out[column] =
            in[column] >= 1.0f ? 0.0f : 2.0f * kFar * kNear / (kFar + kNear - ndc * (kFar - kNear));
      }
    }
  }
  return ids;
}

}  // namespace ocg
