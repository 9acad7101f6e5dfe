#!/usr/bin/python3
"""Writes a tiny ONNX detector with a known answer, for the loading tests.

usage: make_tiny_detector.py yolov5|yolov8 OUT.onnx

Input 1x3x128x128. A stride-4 convolution with zero weights, so every one of the 1024
anchors outputs its bias: a box centred at (64, 64), 32 x 32 input pixels, class 5 with
score 0.9 (YOLOv5: objectness 0.9, class score 1). Output [1, 1024, 85] (YOLOv5) or
[1, 84, 1024] (YOLOv8): more anchors than channels, as in real exports.
"""
import sys

import numpy as np
from onnx import TensorProto, helper, numpy_helper, save

kind, out = sys.argv[1], sys.argv[2]
channels = 85 if kind == "yolov5" else 84
bias = np.zeros(channels, np.float32)
bias[:4] = [64, 64, 32, 32]
if kind == "yolov5":
    bias[4] = 0.9
    bias[5 + 5] = 1.0
else:
    bias[4 + 5] = 0.9
inits = [numpy_helper.from_array(np.zeros((channels, 3, 4, 4), np.float32), "w"),
         numpy_helper.from_array(bias, "b"),
         numpy_helper.from_array(np.array([1, channels, 1024], np.int64), "shape")]
nodes = [helper.make_node("Conv", ["images", "w", "b"], ["conv"], kernel_shape=[4, 4],
                          strides=[4, 4]),
         helper.make_node("Reshape", ["conv", "shape"],
                          ["flat" if kind == "yolov5" else "output0"])]
out_shape = [1, channels, 1024]
if kind == "yolov5":
    nodes.append(helper.make_node("Transpose", ["flat"], ["output0"], perm=[0, 2, 1]))
    out_shape = [1, 1024, channels]
graph = helper.make_graph(
    nodes, "tiny", [helper.make_tensor_value_info("images", TensorProto.FLOAT, [1, 3, 128, 128])],
    [helper.make_tensor_value_info("output0", TensorProto.FLOAT, out_shape)], inits)
save(helper.make_model(graph, opset_imports=[helper.make_opsetid("", 11)]), out)
