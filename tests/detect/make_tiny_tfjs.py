#!/usr/bin/python3
"""Writes a tiny TF.js graph model with the ops of the default detector, its input and the
outputs numpy computes for it, for the test of tools/tfjs_to_onnx.py.

usage: make_tiny_tfjs.py DIR
Writes DIR/model.json, DIR/weights.bin (float weights stored as float16, as in the real
model), DIR/input.f32 ([1, 3, 8, 8]), DIR/out0.f32 ([1, 16, 5]) and DIR/out1.f32 ([1, 3, 16]).

The graph: NCHW input -> NHWC -> Pad -> Conv2D (stride 2) -> Add bias -> LeakyRelu ->
depthwise conv (SAME) -> MaxPool -> ResizeBilinear (half-pixel) -> concat with the
LeakyRelu -> NCHW -> SplitV [5, 3] -> Sigmoid -> Reshape to a shape computed by
SparseToDense + AddV2 (as TF exports of ONNX graphs do) -> Transpose.
"""
import json
import os
import sys

import numpy as np

rng = np.random.RandomState(7)
out_dir = sys.argv[1]
os.makedirs(out_dir, exist_ok=True)

nodes, specs, blobs = [], [], []


def const(name, array, quantize=False):
    array = np.asarray(array)
    spec = {"name": name, "shape": list(array.shape)}
    if array.dtype.kind in "iu":
        spec["dtype"] = "int32"
        blobs.append(array.astype(np.int32).tobytes())
    elif quantize:
        spec["dtype"] = "float32"
        spec["quantization"] = {"dtype": "float16", "original_dtype": "float32"}
        array = array.astype(np.float16)
        blobs.append(array.tobytes())
        array = array.astype(np.float32)
    else:
        spec["dtype"] = "float32"
        blobs.append(array.astype(np.float32).tobytes())
    specs.append(spec)
    nodes.append({"name": name, "op": "Const", "attr": {}})
    return array


def node(name, op, inputs, **attr):
    nodes.append({"name": name, "op": op, "input": inputs, "attr": attr})


def ints(values):
    return {"list": {"i": [str(v) for v in values]}}


def text(value):
    import base64
    return {"s": base64.b64encode(value.encode()).decode()}


# --- the graph, and numpy beside it ---
x = rng.randn(1, 3, 8, 8).astype(np.float32)
nodes.append({"name": "input_1", "op": "Placeholder",
              "attr": {"shape": {"shape": {"dim": [{"size": "1"}, {"size": "3"}, {"size": "8"},
                                                   {"size": "8"}]}},
                       "dtype": {"type": "DT_FLOAT"}}})
const("perm_nhwc", [0, 2, 3, 1])
const("perm_nchw", [0, 3, 1, 2])
node("t1", "Transpose", ["input_1", "perm_nhwc"])
h = x.transpose(0, 2, 3, 1)
pads = const("pads", [[0, 0], [1, 1], [1, 1], [0, 0]])
node("pad", "Pad", ["t1", "pads"])
h = np.pad(h, pads)
w = const("w", rng.randn(3, 3, 3, 4) * 0.5, quantize=True)
node("conv", "Conv2D", ["pad", "w"], strides=ints([1, 2, 2, 1]), padding=text("VALID"),
     data_format=text("NHWC"), dilations=ints([1, 1, 1, 1]))


def conv(h, w, stride):
    n, hh, ww, c = h.shape
    kh, kw, _, co = w.shape
    oh, ow = (hh - kh) // stride + 1, (ww - kw) // stride + 1
    out = np.zeros((n, oh, ow, co), np.float32)
    for i in range(oh):
        for j in range(ow):
            patch = h[:, i * stride:i * stride + kh, j * stride:j * stride + kw, :]
            out[:, i, j, :] = np.tensordot(patch, w, axes=([1, 2, 3], [0, 1, 2]))
    return out


h = conv(h, w, 2)  # [1, 4, 4, 4]
b = const("b", rng.randn(4), quantize=True)
node("add", "Add", ["conv", "b"])
h = h + b
node("lrelu", "LeakyRelu", ["add"], alpha={"f": 0.1})
lrelu = np.where(h > 0, h, 0.1 * h)
wd = const("wd", rng.randn(3, 3, 4, 1) * 0.5, quantize=True)
node("dw", "DepthwiseConv2dNative", ["lrelu", "wd"], strides=ints([1, 1, 1, 1]),
     padding=text("SAME"), data_format=text("NHWC"), dilations=ints([1, 1, 1, 1]))
padded = np.pad(lrelu, [[0, 0], [1, 1], [1, 1], [0, 0]])
dw = np.stack([conv(padded[..., c:c + 1], wd[:, :, c:c + 1, :], 1)[..., 0] for c in range(4)],
              axis=-1)
node("mp", "MaxPool", ["dw"], ksize=ints([1, 2, 2, 1]), strides=ints([1, 2, 2, 1]),
     padding=text("VALID"), data_format=text("NHWC"))
mp = dw.reshape(1, 2, 2, 2, 2, 4).max(axis=(2, 4))  # [1, 2, 2, 4]
const("size", [4, 4])
node("up", "ResizeBilinear", ["mp", "size"], align_corners={"b": False},
     half_pixel_centers={"b": True})


def bilinear_axis(a, axis, out_size):
    in_size = a.shape[axis]
    src = np.clip((np.arange(out_size) + 0.5) * in_size / out_size - 0.5, 0, in_size - 1)
    lo = np.floor(src).astype(int)
    hi = np.minimum(lo + 1, in_size - 1)
    t = (src - lo).reshape([-1 if k == axis else 1 for k in range(a.ndim)])
    return np.take(a, lo, axis) * (1 - t) + np.take(a, hi, axis) * t


up = bilinear_axis(bilinear_axis(mp, 1, 4), 2, 4)
const("axis3", np.array(3))
node("cat", "ConcatV2", ["up", "lrelu", "axis3"])
cat = np.concatenate([up, lrelu], axis=3)
node("t2", "Transpose", ["cat", "perm_nchw"])
t2 = cat.transpose(0, 3, 1, 2)  # [1, 8, 4, 4]
const("sizes", [5, 3])
const("axis1", np.array(1))
node("split", "SplitV", ["t2", "sizes", "axis1"], num_split={"i": "2"})
node("sig", "Sigmoid", ["split"])
sig = 1 / (1 + np.exp(-t2[:, :5]))
const("where", np.zeros((0, 1), np.int32))
const("dense_shape", [3])
const("gather", np.zeros((0,), np.int32))
const("zero", np.array(0))
node("std", "SparseToDense", ["where", "dense_shape", "gather", "zero"])
const("base_shape", [1, 5, -1])
node("shape", "AddV2", ["base_shape", "std"])
node("reshape", "Reshape", ["sig", "shape"])
const("perm_021", [0, 2, 1])
node("t3", "Transpose", ["reshape", "perm_021"])
node("Identity", "Identity", ["t3"])
out0 = sig.reshape(1, 5, 16).transpose(0, 2, 1)
const("shape1", [1, 3, 16])
node("reshape1", "Reshape", ["split:1", "shape1"])
node("Identity_1", "Identity", ["reshape1"])
out1 = t2[:, 5:].reshape(1, 3, 16)

model = {
    "format": "graph-model", "generatedBy": "tests", "convertedBy": "tests",
    "signature": {"outputs": {"Identity:0": {"name": "Identity:0"},
                              "Identity_1:0": {"name": "Identity_1:0"}}},
    "modelTopology": {"node": nodes},
    "weightsManifest": [{"paths": ["weights.bin"], "weights": specs}],
}
with open(os.path.join(out_dir, "model.json"), "w") as f:
    json.dump(model, f)
with open(os.path.join(out_dir, "weights.bin"), "wb") as f:
    f.write(b"".join(blobs))
x.tofile(os.path.join(out_dir, "input.f32"))
out0.astype(np.float32).tofile(os.path.join(out_dir, "out0.f32"))
out1.astype(np.float32).tofile(os.path.join(out_dir, "out1.f32"))
