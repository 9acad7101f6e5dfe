// ocg.ObjectSlam: the whole system (SLAM, objects, OCG) fed frame by frame from Python.

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <memory>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "bindings.h"
#include "ocg/app/object_slam.h"
#include "ocg/app/sequence_runner.h"
#include "ocg/app/settings.h"
#include "ocg/core/file_io.h"
#include "ocg/detect/detection_model.h"
#include "ocg/io/detections.h"
#include "ocg/io/text_lines.h"

namespace py = pybind11;

namespace ocg::python {
namespace {

using Matrix4 = py::array_t<double>;

Matrix4 ToMatrix(const SE3& pose) {
  Matrix4 matrix({4, 4});
  auto out = matrix.mutable_unchecked<2>();
  const Eigen::Matrix4d m = pose.Matrix();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out(r, c) = m(r, c);
  return matrix;
}

std::vector<Detection> ToDetections(const py::object& given) {
  std::vector<Detection> detections;
  if (given.is_none()) return detections;
  const auto rows = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(given);
  if (!rows) throw py::value_error("detections: expected an (N, 6) numeric array");
  if (rows.size() == 0) return detections;
  if (rows.ndim() != 2 || rows.shape(1) != 6) {
    std::string shape;
    for (py::ssize_t i = 0; i < rows.ndim(); ++i)
      shape += (i > 0 ? ", " : "") + std::to_string(rows.shape(i));
    throw py::value_error(
        "detections: expected an (N, 6) array [class, x, y, w, h, score] (pixels, x y the "
        "top-left corner), got shape (" +
        shape + (rows.ndim() == 1 ? "," : "") + ")" +
        (rows.ndim() == 2 ? ": " + std::to_string(rows.shape(1)) + " columns"
                          : ": " + std::to_string(rows.ndim()) + " dimension(s)"));
  }
  const auto in = rows.unchecked<2>();
  for (py::ssize_t i = 0; i < rows.shape(0); ++i) {
    const double row[6] = {in(i, 0), in(i, 1), in(i, 2), in(i, 3), in(i, 4), in(i, 5)};
    // The text reader's check (io/detections.h): Python refuses what files may not hold.
    detections.push_back(DetectionFromRow(row, "detections: row " + std::to_string(i)));
  }
  return detections;
}

// One ObjectSlam for Python: its methods are serialized (Track is for one thread at a
// time, and track() runs without the GIL, so two Python threads could otherwise enter it).
class PyObjectSlam {
 public:
  PyObjectSlam(const std::string& settings_path, const std::optional<std::string>& vocabulary,
               const std::optional<std::string>& mode, bool map_objects,
               const std::optional<std::string>& load_map)
      : settings_path_(settings_path) {
    description_.sequence = "(python)";
    description_.settings = settings_path;
    Settings settings = LoadSettings(settings_path, CameraNeed::kIntrinsics).settings;
    if (mode) {
      settings.ocg.mode = *mode;
      settings.ocg.Check();
    }
    ObjectSlamOptions options;
    if (vocabulary) options.vocabulary_path = *vocabulary;
    options.map_objects = map_objects;
    options.snapshots = SnapshotPolicy{false, 0};
    if (load_map) options.load_map = *load_map;
    py::gil_scoped_release release;
    slam_ = std::make_unique<ObjectSlam>(settings, options);
  }

  FrameReport Track(const py::array& image, double timestamp, const py::object& detections,
                    const std::optional<std::string>& image_path) {
    if (!image.dtype().is(py::dtype::of<std::uint8_t>())) {
      throw py::value_error("image: expected a uint8 array (HxW grey or HxWx3 BGR), got dtype " +
                            std::string(py::str(image.dtype())));
    }
    if (!(image.ndim() == 2 || (image.ndim() == 3 && image.shape(2) == 3))) {
      throw py::value_error("image: expected HxW (grey) or HxWx3 (BGR), got " +
                            std::to_string(image.ndim()) + " dimension(s)" +
                            (image.ndim() == 3
                                 ? " with " + std::to_string(image.shape(2)) + " channels"
                                 : std::string()));
    }
    const auto pixels = py::array_t<std::uint8_t, py::array::c_style>::ensure(image);
    const std::vector<Detection> boxes = ToDetections(detections);
    // A header over NumPy's buffer: no copy; pixels keeps it alive past the GIL release.
    const cv::Mat mat(static_cast<int>(pixels.shape(0)), static_cast<int>(pixels.shape(1)),
                      image.ndim() == 2 ? CV_8UC1 : CV_8UC3,
                      const_cast<std::uint8_t*>(pixels.data()));
    py::gil_scoped_release release;
    const std::lock_guard<std::mutex> lock(mutex_);
    FrameSource source;
    if (image_path) source.image_path = *image_path;
    slam_->Track(mat, timestamp, boxes, source);
    return slam_->LastFrame();
  }

  // A recorded sequence fed by the sequence runner (read-ahead, realtime, detections
  // from files, boxes in memory or the detector); its description is what save() writes.
  py::object Run(const py::object& sequence, const std::string& format,
                 const py::object& detections, bool detect, const std::optional<std::string>& model,
                 double detect_score, std::size_t max_frames, int read_ahead, bool realtime,
                 bool lenient) {
    const std::string root = py::str(py::module_::import("os").attr("fspath")(sequence));
    DetectionInput input;
    input.detect = detect;
    if (model) input.model = *model;
    input.detect_score = detect_score;
    input.lenient = lenient;
    std::unordered_map<std::string, std::vector<Detection>> boxes;
    const bool in_memory = py::isinstance<py::dict>(detections);
    if (in_memory) {
      if (detect) throw py::value_error("give either detections or detect=True, not both");
      for (const auto& [key, value] : detections.cast<py::dict>())
        boxes[py::str(key)] = ToDetections(py::reinterpret_borrow<py::object>(value));
    } else if (!detections.is_none()) {
      input.files = py::str(py::module_::import("os").attr("fspath")(detections));
    }
    FeedOptions options;
    options.max_frames = max_frames;
    options.read_ahead = read_ahead;
    options.realtime = realtime;
    options.format = format;
    FeedReport report;
    {
      py::gil_scoped_release release;
      const ImageSequence images = ReadSequence(root, format);
      std::vector<std::string> frames;
      for (std::size_t i = 0; i < images.images.size() && (max_frames == 0 || i < max_frames); ++i)
        frames.push_back(images.images[i].timestamp_text);
      std::unique_ptr<DetectionSource> source =
          in_memory ? std::make_unique<InMemoryDetectionSource>(std::move(boxes), frames)
                    : OpenDetections(input, frames);
      const std::lock_guard<std::mutex> lock(mutex_);
      report = FeedSequence(*slam_, images, source.get(), options);
      description_ = {root, settings_path_,
                      in_memory
                          ? "(python)"
                          : (detect ? (model ? *model : DefaultDetectorModel()) : input.files),
                      source ? source->FramesMatched() : 0, report.feed};
      description_.reader = report.reader;
    }
    const nlohmann::json result = {{"frames", report.frames},
                                   {"stopped", report.stopped},
                                   {"frames_dropped", report.dropped},
                                   {"feed", report.feed},
                                   {"reader", report.reader}};
    return py::module_::import("json").attr("loads")(result.dump());
  }

  const RunDescription& description() const { return description_; }

  template <typename Result, typename Body>
  Result Locked(Body body) {
    py::gil_scoped_release release;
    const std::lock_guard<std::mutex> lock(mutex_);
    return body(*slam_);
  }

  ObjectSlam& slam() { return *slam_; }
  const std::string& settings_path() const { return settings_path_; }

 private:
  std::string settings_path_;
  RunDescription description_;
  std::mutex mutex_;
  std::unique_ptr<ObjectSlam> slam_;
};

// An image file as `ocg_slam run` reads it, so Python feeds ObjectSlam the same pixels.
py::array ReadImage(const std::string& path, const std::string& mode) {
  if (mode != "grey" && mode != "bgr") {
    throw py::value_error("read_image: mode must be 'grey' or 'bgr', not '" + mode + "'");
  }
  cv::Mat image;
  {
    py::gil_scoped_release release;
    image = cv::imread(path, mode == "grey" ? cv::IMREAD_GRAYSCALE : cv::IMREAD_COLOR);
  }
  if (image.empty()) throw FileError("cannot read image '" + path + "'");
  std::vector<py::ssize_t> shape = {image.rows, image.cols};
  if (mode == "bgr") shape.push_back(3);
  py::array_t<std::uint8_t> pixels(shape);
  const std::size_t row_bytes = image.cols * image.elemSize();
  for (int r = 0; r < image.rows; ++r)
    std::copy(image.ptr<std::uint8_t>(r), image.ptr<std::uint8_t>(r) + row_bytes,
              pixels.mutable_data() + r * row_bytes);
  return pixels;
}

// A trajectory reader of ObjectSlam as TUM rows, under the lock.
template <std::vector<StampedPose> (ObjectSlam::*Reader)() const>
TumRows Trajectory(PyObjectSlam& self) {
  return ToTumRows(
      self.Locked<std::vector<StampedPose>>([](ObjectSlam& slam) { return (slam.*Reader)(); }));
}

std::string StateName(TrackingState state) {
  switch (state) {
    case TrackingState::kNoImages:
    case TrackingState::kNotInitialized:
      return "not_initialized";
    case TrackingState::kOk:
      return "ok";
    case TrackingState::kLost:
      return "lost";
  }
  return "not_initialized";
}

py::object ParseJson(const std::string& text) {
  if (text.empty()) return py::none();
  return py::module_::import("json").attr("loads")(text);
}

}  // namespace

void BindObjectSlam(py::module_& module) {
  module.def(
      "read_image",
      [](const py::object& path, const std::string& mode) {
        return ReadImage(py::str(py::module_::import("os").attr("fspath")(path)), mode);
      },
      py::arg("path"), py::arg("mode") = "grey",
      "An image file (PNG, JPEG, ...) decoded as `ocg_slam run` decodes it (OpenCV): mode "
      "'grey' gives an (H, W) uint8 array, 'bgr' an (H, W, 3) one. Raises ocg.FileError "
      "when the file is missing or not an image, ValueError for another mode.");
  py::class_<FrameReport>(module, "TrackResult",
                          "What track() made of a frame: state, pose, keyframe, relocalized, "
                          "inliers.")
      .def_property_readonly(
          "state", [](const FrameReport& report) { return StateName(report.state); },
          "'not_initialized' (before the map is initialized), 'ok' (tracked) or 'lost'.")
      .def_property_readonly(
          "pose",
          [](const FrameReport& report) -> std::optional<Matrix4> {
            if (!report.T_cw) return std::nullopt;
            return ToMatrix(*report.T_cw);
          },
          "The (4, 4) float64 T_cw (world to camera) when tracked, else None.")
      .def_readonly("keyframe", &FrameReport::new_keyframe, "The frame became a keyframe.")
      .def_readonly("relocalized", &FrameReport::relocalized,
                    "Tracked again after being lost (or in a loaded map).")
      .def_readonly("inliers", &FrameReport::inliers, "Map points matched in the frame.")
      .def("__repr__", [](const FrameReport& report) {
        return "TrackResult(state='" + StateName(report.state) +
               "', keyframe=" + (report.new_keyframe ? "True" : "False") +
               ", inliers=" + std::to_string(report.inliers) + ")";
      });
  py::class_<PyObjectSlam>(
      module, "ObjectSlam",
      "The whole system: monocular SLAM, the cuboid object map from the detections given "
      "with each frame, and the OCG that removes objects that moved (what `ocg_slam run` "
      "runs, frame by frame).\n\n"
      "Threading: track(), shutdown() and the trajectory readers run one at a time (a lock "
      "serializes them); track() releases the GIL, so other Python threads run meanwhile. "
      "In sequential mode (System.sequential, the default) identical inputs give identical "
      "outputs; otherwise local mapping, loop closing and the OCG have threads of their own.")
      .def(py::init<const std::string&, const std::optional<std::string>&,
                    const std::optional<std::string>&, bool, const std::optional<std::string>&>(),
           py::arg("settings"), py::kw_only(), py::arg("vocabulary") = py::none(),
           py::arg("mode") = py::none(), py::arg("map_objects") = true,
           py::arg("load_map") = py::none(),
           "settings: a settings file (ours or ORB-SLAM2's; docs/settings.md) with the camera "
           "intrinsics. vocabulary: a vocabulary file instead of the settings' "
           "Vocabulary.path. mode: OCG.mode instead of the file's (off, visibility, paper, "
           "...). map_objects: False runs SLAM alone. load_map: a map file (save_map()) to "
           "continue as its next session: it relocalizes in it (docs/sessions.md).\n"
           "Raises ocg.SettingsError naming file, line and key (also for a missing settings "
           "file); ocg.FileError when the vocabulary cannot be read or the map file is not "
           "one, of another version, truncated, damaged or made with another camera; "
           "ValueError for an unknown mode.")
      .def("track", &PyObjectSlam::Track, py::arg("image"), py::arg("timestamp"),
           py::arg("detections") = py::none(), py::arg("image_path") = py::none(),
           "One frame. image: (H, W) grey or (H, W, 3) BGR uint8 array of the camera in the "
           "settings; a BGR image gives the objects their colour signatures (which pair moved "
           "objects), a grey one none unless image_path names its file. timestamp: seconds, "
           "finite, strictly "
           "increasing. detections: (N, 6) array, one row per box [class, x, y, w, h, score]: "
           "COCO-80 class index, top-left corner and size in pixels, score in [0, 1] (the "
           "rules of detection files); None or (0, 6) when there is none. image_path: "
           "optional, the frame's image file, read in colour when the image given is grey and "
           "the frame is an OCG keyframe with detections.\n"
           "Returns a TrackResult: state ('not_initialized', 'ok', 'lost'), pose (the (4, 4) "
           "float64 T_cw, world to camera; camera x right, y down, z forward; map units, "
           "monocular: arbitrary scale; None when not tracked), keyframe, relocalized, "
           "inliers.\n"
           "Raises ValueError for another dtype or shape (naming the detections' columns), a "
           "timestamp not finite or not later than the last frame's; ocg.ParseError (a "
           "ValueError) for a detection row a detection file may not hold (class outside "
           "0..79, a coordinate not finite, width or height <= 0, score outside [0, 1]); "
           "RuntimeError after shutdown().")
      .def("run", &PyObjectSlam::Run, py::arg("sequence"), py::kw_only(), py::arg("format") = "tum",
           py::arg("detections") = py::none(), py::arg("detect") = false,
           py::arg("model") = py::none(), py::arg("detect_score") = 0.0, py::arg("max_frames") = 0,
           py::arg("read_ahead") = -1, py::arg("realtime") = false, py::arg("lenient") = false,
           "A recorded sequence, fed as `ocg_slam run` feeds it (the sequence runner): images "
           "decoded, their ORB features extracted and their detections made up to read_ahead "
           "frames ahead on a thread of their own (-1: 4 on two cores or more, 0: none), at "
           "the pace of their timestamps with realtime=True (images a live camera would have "
           "replaced are dropped). sequence: a sequence folder of format 'tum', 'euroc' or "
           "'kitti'. detections: None, a folder of EAO files or a JSON list file (a path), or "
           "a dict {timestamp text as in rgb.txt: (N, 6) array [class, x, y, w, h, score]}; "
           "detect=True runs the detector network (model: an .onnx file, default the one "
           "tools/get_detector.sh builds; detect_score: minimum confidence, 0: the model's). "
           "max_frames: the first frames only (0: all). Then shutdown() and save() as after "
           "track(); save() names the sequence and detections in run.json.\n"
           "Returns a dict: frames, stopped, frames_dropped, feed (realtime) and reader "
           "(read-ahead depth, the time tracking waited per frame, the detections' time per "
           "frame on the reader thread). Raises ocg.FileError for a missing sequence, image, "
           "detection file or model (saying how to get the model), ocg.ParseError for "
           "malformed detections, ValueError for detections and detect together.")
      .def(
          "pose",
          [](PyObjectSlam& self) -> std::optional<Matrix4> {
            const std::optional<SE3> pose =
                self.Locked<std::optional<SE3>>([](ObjectSlam& slam) { return slam.Pose(); });
            if (!pose) return std::nullopt;
            return ToMatrix(*pose);
          },
          "The last frame's (4, 4) T_cw (world to camera), None when it was not tracked.")
      .def(
          "objects",
          [](PyObjectSlam& self) {
            return ParseJson(
                self.Locked<std::string>([](ObjectSlam& slam) { return slam.Objects(); }));
          },
          "The object map as objects.json holds it (docs/objects.md): a dict with the live "
          "and removed objects (world frame, map units) and their OCG states; None when "
          "objects are not mapped.")
      .def(
          "changes",
          [](PyObjectSlam& self) {
            return ParseJson(
                self.Locked<std::string>([](ObjectSlam& slam) { return slam.Changes(); }));
          },
          "The change log as changes.json holds it: every removal by the OCG with its "
          "keyframe and timestamp; None when objects are not mapped.")
      .def("keyframe_trajectory", &Trajectory<&ObjectSlam::KeyFrameTrajectory>,
           "The keyframes in the map as an (N, 8) float64 array of TUM rows [timestamp, tx, ty, "
           "tz, qx, qy, qz, qw], camera to world (T_wc); final after shutdown().")
      .def("camera_trajectory", &Trajectory<&ObjectSlam::CameraTrajectory>,
           "Every tracked frame, (N, 8) TUM rows as keyframe_trajectory(); final after "
           "shutdown().")
      .def(
          "shutdown",
          [](PyObjectSlam& self) {
            self.Locked<int>([](ObjectSlam& slam) {
              slam.Shutdown();
              return 0;
            });
          },
          "Finishes local mapping, loop closing and the OCG; the objects take the final "
          "poses. Safe to call twice. Raises RuntimeError when a worker thread failed.")
      .def(
          "save",
          [](PyObjectSlam& self, const py::object& folder) {
            const std::string path = py::str(py::module_::import("os").attr("fspath")(folder));
            const RunDescription description = self.description();
            const std::string report = self.Locked<std::string>(
                [&](ObjectSlam& slam) { return slam.Save(path, description).dump(); });
            return ParseJson(report);
          },
          py::arg("folder"),
          "After shutdown(): writes what `ocg_slam run` writes into folder (an existing, "
          "writable one): KeyFrameTrajectory.txt, CameraTrajectory.txt, map_points.ply, the "
          "object files and run.json; returns run.json as a dict. Raises RuntimeError "
          "before shutdown(), ocg.FileError when a file cannot be written.")
      .def(
          "save_map",
          [](PyObjectSlam& self, const py::object& path) {
            const std::string file = py::str(py::module_::import("os").attr("fspath")(path));
            self.Locked<int>([&](ObjectSlam& slam) {
              slam.SaveMap(file);
              return 0;
            });
          },
          py::arg("path"),
          "After shutdown(): the whole state (SLAM map, objects, OCG, settings) as a map file "
          "(docs/sessions.md), written atomically; call before save() so that run.json names "
          "it. Raises RuntimeError before shutdown(), ocg.FileError when it cannot be written.")
      .def_property_readonly(
          "session", [](PyObjectSlam& self) { return self.slam().Session(); },
          "This run's session index: 0 for a new map, the loaded map's sessions otherwise.");
}

}  // namespace ocg::python
