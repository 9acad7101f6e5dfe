// ocg.Detector and ocg.detect_images: the detector of `ocg_detect` from Python.

#include <pybind11/stl.h>

#include <optional>

#include "bindings.h"
#include "ocg/detect/detect_images.h"

namespace ocg::python {
namespace py = pybind11;

namespace {

using ImagePixels = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>;

DetectionModelOptions Options(const std::optional<std::string>& model, double score, double nms_iou,
                              const std::string& tile, int input_size) {
  if (tile != "auto" && tile != "off") {
    throw py::value_error("tile: expected 'auto' or 'off', got '" + tile + "'");
  }
  DetectionModelOptions options;
  options.model_path = model ? *model : DefaultDetectorModel();
  options.score_threshold = score;
  options.nms_iou = nms_iou;
  options.tile_mode = tile == "off" ? TileMode::kOff : TileMode::kAuto;
  options.input_size = input_size;
  return options;
}

// (N, 6) rows [class, x, y, w, h, score]: what ObjectSlam.track takes.
py::array_t<double> ToRows(const std::vector<Detection>& detections) {
  py::array_t<double> rows({static_cast<py::ssize_t>(detections.size()), py::ssize_t{6}});
  auto out = rows.mutable_unchecked<2>();
  for (std::size_t i = 0; i < detections.size(); ++i) {
    const Detection& d = detections[i];
    const double values[6] = {
        static_cast<double>(d.class_id), d.x, d.y, d.width, d.height, d.confidence};
    for (int k = 0; k < 6; ++k) out(static_cast<py::ssize_t>(i), k) = values[k];
  }
  return rows;
}

py::array_t<double> DetectPixels(DetectionModel& model, const ImagePixels& pixels) {
  if (pixels.ndim() != 2 &&
      !(pixels.ndim() == 3 && (pixels.shape(2) == 3 || pixels.shape(2) == 4))) {
    throw py::value_error("image: expected an (H, W) grey or (H, W, 3) BGR uint8 array");
  }
  const int type = pixels.ndim() == 2 ? CV_8UC1 : CV_8UC(static_cast<int>(pixels.shape(2)));
  const cv::Mat image(static_cast<int>(pixels.shape(0)), static_cast<int>(pixels.shape(1)), type,
                      const_cast<std::uint8_t*>(pixels.data()));
  std::vector<Detection> detections;
  {
    py::gil_scoped_release release;
    detections = model.Detect(image);
  }
  return ToRows(detections);
}

}  // namespace

void BindDetector(py::module_& module) {
  py::class_<DetectionModel>(
      module, "Detector",
      "A detector network (ONNX: the default NanoDet from tools/get_detector.sh, or a YOLOv5 "
      "or YOLOv8 export) run on the CPU by OpenCV, as `ocg_detect` runs it "
      "(docs/detector.md). One image at a time; use one Detector per thread.")
      .def(py::init([](const std::optional<std::string>& model, double score, double nms_iou,
                       const std::string& tile, int input_size) {
             return std::make_unique<DetectionModel>(
                 Options(model, score, nms_iou, tile, input_size));
           }),
           py::arg("model") = py::none(), py::kw_only(), py::arg("score") = 0.4,
           py::arg("nms_iou") = 0.5, py::arg("tile") = "auto", py::arg("input_size") = 0,
           "model: an .onnx file (default: the one tools/get_detector.sh built). score: "
           "minimum confidence. tile: 'auto' cuts images wider than 1.5:1 into overlapping "
           "squares, 'off' does not. Raises ocg.FileError when the model is missing, "
           "ocg.ParseError when OpenCV cannot load it, ValueError for outputs of no known "
           "layout or a bad option.")
      .def("detect", &DetectPixels, py::arg("image"),
           "Detections of one image ((H, W) grey or (H, W, 3) BGR uint8, as ocg.read_image "
           "gives): an (N, 6) array [class, x, y, w, h, score], pixels, x y the top-left "
           "corner, COCO-80 ids, by decreasing score; ObjectSlam.track takes it as is.")
      .def_property_readonly("description", &DetectionModel::Describe,
                             "layout, classes and input size, e.g. 'NanoDet, 80 classes, input "
                             "416x416'");
  module.def(
      "detect_images",
      [](const std::string& images, const std::string& out, const std::optional<std::string>& model,
         double score, const std::string& tile, bool json) {
        DetectionModel detector(Options(model, score, 0.5, tile, 0));
        const std::vector<TimedImage> list = ListImagesToDetect(images);
        DetectRunSummary summary;
        {
          py::gil_scoped_release release;
          summary = DetectImagesToFolder(detector, list, out, json);
        }
        py::dict per_class;
        for (const auto& [class_id, count] : summary.boxes_per_class)
          per_class[py::int_(class_id)] = count;
        py::dict result;
        result["images"] = summary.images;
        result["boxes"] = summary.boxes;
        result["boxes_per_class"] = per_class;
        result["seconds"] = summary.seconds;
        return result;
      },
      py::arg("images"), py::arg("out"), py::kw_only(), py::arg("model") = py::none(),
      py::arg("score") = 0.4, py::arg("tile") = "auto", py::arg("json") = false,
      "What `ocg_detect` does: runs the detector on every image of images (a TUM rgb.txt, a "
      "sequence folder or a folder of images) and writes out/<timestamp>.txt (EAO format; "
      "with json=True also out/detections.json). Returns {'images', 'boxes', "
      "'boxes_per_class', 'seconds'}.");
}

}  // namespace ocg::python
